"""The README's example test file, exactly as printed there, passes in a fresh project: a
directory with no pytest configuration at all (pytest-asyncio in its default strict mode), the
plugin loaded from the installed package. The file is read out of README.md at each run, so the
test fails when the README's example stops working."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from .inner import run_inner

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.sitl

README = Path(__file__).resolve().parents[2] / "README.md"
SECTION = "## Testing your own drone code"


def readme_example() -> tuple[str, str]:
    """(file name, source) of the first python block of the README's section on the plugin; its
    first line is a comment naming the file."""
    text = README.read_text()
    section = text[text.index(SECTION):]
    source = re.search(r"^```python\n(.*?)^```$", section, re.M | re.S).group(1)
    name = re.match(r"# (test_\w+\.py)\n", source).group(1)
    return name, source


def test_the_readme_example_passes_as_printed_with_no_configuration(pytester):
    name, source = readme_example()
    (pytester.path / name).write_text(source)
    assert not [p.name for p in pytester.path.iterdir() if p.name in ("pytest.ini", "pyproject.toml", "tox.ini",
                                                                      "setup.cfg", "conftest.py")]
    result = run_inner(pytester, "-v", asyncio_mode=None)
    assert "configfile:" not in result.stdout.str()  # no ini file of this suite's reached it
    assert re.search(r"^asyncio: mode=(Mode\.)?strict", result.stdout.str(), re.M | re.I), result.stdout.str()
    tests = len(re.findall(r"^(?:async )?def test_", source, re.M))
    result.assert_outcomes(passed=tests)
