"""What a test run leaves behind: a failed test's report names its seed, tlog and state log and the
files are kept; a passing test's files are deleted unless --firefly-keep; a wait that never ends
fails in vehicle time; a test that returns while its vehicle flies still stops the process."""
from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from .inner import block, firefly_section, run_inner

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.sitl

OUTCOMES = '''
from pathlib import Path

import pytest


def autopilot_pids(path):
    """Live `python -m firefly.autopilot` processes whose command line names `path`."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            cmdline = (entry / "cmdline").read_bytes().replace(b"\\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if "-m firefly.autopilot" in cmdline and path in cmdline:
            pids.append(int(entry.name))
    return pids


@pytest.mark.firefly(speedup=50)
def test_a_wait_that_never_ends(firefly):
    print(f"WAIT STARTS t={firefly.state().time_s!r}")
    firefly.wait_until(lambda s: s.altitude_m > 5, timeout=3, what="a climb nobody commanded")


@pytest.mark.firefly(speedup="inf")
def test_passes(firefly):
    print(f"EVIDENCE {firefly.tlog_path.parent}")
    assert firefly.sleep(1.0).on_ground


@pytest.mark.firefly(airborne=10, speedup=50)
def test_returns_while_flying(firefly):
    flying = firefly.state()
    assert flying.armed and not flying.on_ground and flying.altitude_m > 9
    assert len(autopilot_pids(str(firefly.tlog_path))) == 1  # the scan below finds a running one
    Path("flying.txt").write_text(str(firefly.tlog_path))


def test_the_flying_vehicles_process_has_stopped():
    assert autopilot_pids(Path("flying.txt").read_text()) == []
'''


def reproduce_runs_beside_the_evidence(section: list[str], *evidence: Path) -> None:
    """The report's reproduce command starts a vehicle, and leaves the evidence files as they were."""
    line = next(line for line in section if line.startswith("reproduce: "))
    argv = shlex.split(line.removeprefix("reproduce: "))
    assert argv[0] == "autopilot" and not {"--tlog", "--state-log", "--quiet"} & set(argv), argv
    before = [path.read_bytes() for path in evidence]
    state_dir = Path(argv[argv.index("--state-dir") + 1])
    process = subprocess.Popen([sys.executable, "-m", "firefly.autopilot", *argv[1:]], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    try:
        assert "autopilot" in process.stdout.readline()  # its first line: it runs
        assert state_dir.is_dir()
    finally:
        process.terminate()
        process.wait(timeout=10)
    assert [path.read_bytes() for path in evidence] == before


def test_a_failed_test_keeps_its_evidence_and_a_passing_one_deletes_it(pytester):
    """One inner run of four tests:
    - a wait_until whose condition never holds fails once its 3 s of *vehicle* time are up (not
      sooner, not much later), saying "timed out after ... of vehicle time";
    - that failure's report has a "firefly" section naming the seed, the tlog, the state log and
      a reproduce command, and those files are on disk and hold the flight; the reproduce
      command starts a vehicle and leaves them as they were;
    - only the failed test's evidence directory is left: the passing test's is gone, and so is
      that of a test that returned with its vehicle in the air, whose autopilot process had
      stopped before the next test began.
    Then --firefly-keep keeps a passing test's tlog and state log."""
    pytester.makepyfile(test_outcomes=OUTCOMES)
    evidence = pytester.path / "evidence"
    result = run_inner(pytester, "-s", "--firefly-evidence", str(evidence))
    result.assert_outcomes(failed=1, passed=3)

    failure = "\n".join(block(result, "test_a_wait_that_never_ends"))
    assert "timed out after 3 s of vehicle time waiting for a climb nobody commanded" in failure, failure
    began = float(re.search(r"WAIT STARTS t=([\d.]+)", result.stdout.str()).group(1))
    gave_up = float(re.search(r"last state: t=([\d.]+) s", failure).group(1))
    assert 3.0 <= gave_up - began < 4.0, "the wait ended after its timeout in vehicle time"

    section = firefly_section(result, "test_a_wait_that_never_ends")
    assert re.fullmatch(r"seed \d+, speedup 50, 1 vehicle", section[0]), section
    tlog = Path(re.search(r"^vehicle 1: tlog (\S+)$", "\n".join(section), re.M).group(1))
    state_log = Path(re.search(r"^vehicle 1: state log (\S+)$", "\n".join(section), re.M).group(1))
    assert any(line.startswith("vehicle 1: last state t=") for line in section), section
    assert any(line.startswith("reproduce: autopilot ") for line in section), section
    assert tlog.is_file() and tlog.stat().st_size > 0
    assert state_log.is_file() and len(state_log.read_text().splitlines()) > 30  # > 3 s of 0.1 s lines
    (kept,) = evidence.iterdir()
    assert kept == tlog.parent and kept.name == "test_outcomes.py__test_a_wait_that_never_ends"
    assert section[1] == f"evidence kept in {kept}"
    reproduce_runs_beside_the_evidence(section, tlog, state_log)

    passed_dir = Path(re.search(r"EVIDENCE (\S+)", result.stdout.str()).group(1))
    assert passed_dir.parent == evidence and not passed_dir.exists()

    keep = run_inner(pytester, "-s", "-k", "test_passes", "--firefly-keep",
                     "--firefly-evidence", str(pytester.path / "kept"))
    keep.assert_outcomes(passed=1)
    kept_dir = Path(re.search(r"EVIDENCE (\S+)", keep.stdout.str()).group(1))
    assert (kept_dir / "vehicle.tlog").stat().st_size > 0
    assert (kept_dir / "state.csv").stat().st_size > 0


DATAFLASH = '''
def test_fails_with_a_dataflash_log(firefly):
    logs = firefly.run.state_dir / "instance-0" / "logs"  # where the vehicle writes its own
    logs.mkdir(parents=True, exist_ok=True)
    (logs / "firefly-test.BIN").write_bytes(b"a dataflash log")
    assert firefly.state().armed, "the vehicle is not armed"


def test_passes(firefly):
    assert not firefly.state().armed
'''


def test_evidence_outlives_later_runs_under_the_rootdir_or_the_ini_setting(pytester):
    """By default a failed test's evidence goes to <rootdir>/.firefly/evidence/<node id>/ (a
    .gitignore beside it), the report names the directory, and the dataflash logs found under
    the vehicle's state directory are copied in beside the .tlog. A later run that does not
    fail that test leaves it there. The ini setting firefly_evidence moves the root."""
    pytester.makepyfile(test_evidence=DATAFLASH)
    result = run_inner(pytester)
    result.assert_outcomes(failed=1, passed=1)
    root = pytester.path / ".firefly" / "evidence"
    kept = root / "test_evidence.py__test_fails_with_a_dataflash_log"
    assert sorted(p.name for p in root.iterdir()) == [kept.name]  # the passing test's is gone
    assert (pytester.path / ".firefly" / ".gitignore").read_text().splitlines()[-1] == "*"
    section = firefly_section(result, "test_fails_with_a_dataflash_log")
    copy = kept / "instance-0-firefly-test.BIN"
    assert f"evidence kept in {kept}" in section and f"dataflash log: {copy}" in section, section
    assert copy.read_bytes() == b"a dataflash log"
    assert (kept / "vehicle.tlog").stat().st_size > 0 and (kept / "state.csv").stat().st_size > 0

    later = run_inner(pytester, "-k", "test_passes")
    later.assert_outcomes(passed=1)
    assert copy.read_bytes() == b"a dataflash log" and (kept / "vehicle.tlog").stat().st_size > 0

    pytester.makeini("[pytest]\nfirefly_evidence = ci-artifacts\n")
    moved = run_inner(pytester, "-k", "test_fails")
    moved.assert_outcomes(failed=1)
    assert (pytester.path / "ci-artifacts" / kept.name / copy.name).is_file()
