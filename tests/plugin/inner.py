"""Running pytest as a user runs it: a fresh directory holding test files and a pytest.ini, a
separate `python -m pytest` process, and the installed plugin loaded from its entry point."""
from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

INI = """[pytest]
asyncio_mode = {mode}
asyncio_default_fixture_loop_scope = function
"""
INNER_WALL_S = 240


@dataclass
class InnerRun:
    returncode: int
    output: str  # stdout and stderr together

    def outcomes(self) -> dict[str, int]:
        """{'passed': 3, 'failed': 1, ...} from pytest's last summary line."""
        import re
        summary = [line for line in self.output.splitlines() if re.search(r"\bin [\d.]+s\b", line)]
        if not summary:
            return {}
        return {kind: int(n) for n, kind in re.findall(r"(\d+) (passed|failed|errors?|skipped)", summary[-1])}


def run_pytest(directory: Path, files: dict[str, str], *args: str, asyncio_mode: str = "auto") -> InnerRun:
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "pytest.ini").write_text(INI.format(mode=asyncio_mode))
    for name, text in files.items():
        (directory / name).write_text(text)
    done = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", *args],
                          cwd=directory, capture_output=True, text=True, timeout=INNER_WALL_S)
    return InnerRun(done.returncode, done.stdout + done.stderr)


def autopilots_under(directory: Path) -> list[str]:
    """Command lines of running `autopilot` processes whose files are under `directory`."""
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            state = (proc / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if "-m autopilot" in cmdline and str(directory) in cmdline and state != "Z":
            found.append(cmdline)
    return found
