"""Running the plugin as a user runs it: pytester writes test files into a fresh directory and a
separate `python -m pytest` process runs them (`runpytest_subprocess`), with the plugin loaded
from the installed package's `pytest11` entry point and nothing of this suite's configuration.

Every inner run is followed by a look at /proc: an autopilot process still running with a path
of the inner run's directory on its command line is one the plugin failed to stop. (The plugin
starts the autopilot with --exit-with-parent, so an orphan stops by itself within about 0.5 s of
its pytest's exit; the look comes at once, inside that window. A test that must see a process
stop for certain looks from inside the inner session, as test_failure_evidence.py does.)

The modules that use these helpers say `pytest_plugins = ["pytester"]` themselves: in
tests/plugin/conftest.py that line would stop `pytest` run from the repository root at collection
("Defining 'pytest_plugins' in a non-top-level conftest is no longer supported").
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

INNER_WALL_S = 180  # one inner session; a hung vehicle fails the test instead of hanging the suite


def run_inner(pytester: pytest.Pytester, *args: str, asyncio_mode: str | None = "auto") -> pytest.RunResult:
    """pytest in its own process in pytester's directory, then the check that it left no
    autopilot running. asyncio_mode None: pytest-asyncio as a project with no configuration has it."""
    asyncio = ["-o", f"asyncio_mode={asyncio_mode}", "-o", "asyncio_default_fixture_loop_scope=function"]
    result = pytester.runpytest_subprocess(
        "-p", "no:cacheprovider", *(asyncio if asyncio_mode is not None else []), *args, timeout=INNER_WALL_S)
    assert_no_autopilot_left(pytester.path)
    return result


def autopilots_under(directory: Path) -> list[str]:
    """Each live `python -m firefly.autopilot` process whose command line names a path under `directory`
    (its state directory, tlog, state log), as "pid: command line". A zombie has an empty
    /proc/PID/cmdline and so is not listed: it has stopped."""
    under = str(directory).rstrip("/") + "/"
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            words = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:  # it ended while we looked
            continue
        cmdline = " ".join(w.decode(errors="replace") for w in words if w)
        if "-m firefly.autopilot" in cmdline and under in cmdline:
            found.append(f"{entry.name}: {cmdline}")
    return found


def assert_no_autopilot_left(directory: Path) -> None:
    left = autopilots_under(directory)
    assert left == [], "autopilot processes outlived their pytest session:\n" + "\n".join(left)


HEADER = re.compile(r"^[_=-]{3,} .* [_=-]{3,}$")  # "____ test_x ____", "---- firefly ----", "==== ... ===="


def _header_index(lines: list[str], title: str) -> int | None:
    return next((i for i, line in enumerate(lines) if HEADER.match(line) and line.strip("_=- ") == title), None)


def _body(lines: list[str], header: int) -> list[str]:
    body = []
    for line in lines[header + 1:]:
        if HEADER.match(line):
            break
        body.append(line)
    return body


def block(result: pytest.RunResult, title: str) -> list[str]:
    """The lines under the report header titled `title` ("test_x", "ERROR at setup of test_x"),
    up to the next header of any kind."""
    header = _header_index(result.outlines, title)
    assert header is not None, f"no report header {title!r} in:\n" + result.stdout.str()
    return _body(result.outlines, header)


def firefly_section(result: pytest.RunResult, title: str) -> list[str]:
    """The plugin's "firefly" section in the report of the test under header `title`."""
    lines = result.outlines
    header = _header_index(lines, title)
    assert header is not None, f"no report header {title!r} in:\n" + result.stdout.str()
    for i in range(header + 1, len(lines)):
        if lines[i].startswith(("____", "====")):  # the next test's report: none in this one
            break
        if HEADER.match(lines[i]) and lines[i].strip("_=- ") == "firefly":
            return _body(lines, i)
    raise AssertionError(f"no firefly section in the report of {title!r}:\n" + result.stdout.str())
