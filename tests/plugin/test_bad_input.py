"""A mistake in how a test asks for its vehicle fails that test at setup, in one line that says
what to fix, and never as a traceback from inside the plugin."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from .inner import block, firefly_section, run_inner

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.sitl

BAD_MARKERS = '''
import pytest

@pytest.mark.firefly(spedup=3)
def test_unknown_key(firefly): pass

@pytest.mark.firefly(speedup=-1)
def test_negative_speedup(firefly): pass

@pytest.mark.firefly(count=0)
def test_no_vehicles(firefly): pass

@pytest.mark.firefly(faults={"WPNAV_SPEED": 1})
def test_a_fault_that_is_not_sim(firefly): pass

@pytest.mark.firefly(3)
def test_positional_argument(firefly): pass
'''
# test -> what its one line must say besides "@pytest.mark.firefly"
MARKER_ERRORS = {
    "test_unknown_key": "unknown key 'spedup'",
    "test_negative_speedup": "(speedup=...): expected a positive number or 'inf', got -1",
    "test_no_vehicles": "(count=...): expected an integer in 1..1000, got 0",
    "test_a_fault_that_is_not_sim": "(faults=...): WPNAV_SPEED is not a SIM_* parameter",
    "test_positional_argument": "takes keywords only",
}

REFUSED = '''
import pytest

@pytest.mark.firefly(scenario="misspelt_wind.toml", speedup="inf")
def test_a_scenario_the_autopilot_refuses(firefly): pass

@pytest.mark.firefly(params={"NO_SUCH_PARAM_16": 1}, speedup="inf")
def test_an_unknown_parameter(firefly): pass

@pytest.mark.firefly(params={"WPNAV_SPEED": 1e9}, speedup="inf")
def test_a_parameter_out_of_range(firefly): pass
'''


def test_bad_markers_and_refused_settings_fail_at_setup_in_one_line(pytester):
    """Five marker mistakes (an unknown key, a negative speedup, count=0, a non-SIM_* fault, a
    positional argument) each error at setup with exactly one line that names
    `@pytest.mark.firefly` and the key, and start no process (no evidence directory is made for
    them). Three settings only the vehicle can judge also error at setup: a scenario file the
    autopilot refuses (the report quotes the autopilot's own stderr line), an unknown parameter
    (16 characters long, so the vehicle's reason arrives cut to STATUSTEXT's 50) and an
    out-of-range value (each named). No traceback anywhere."""
    pytester.makepyfile(test_bad_markers=BAD_MARKERS, test_refused=REFUSED)
    pytester.makefile(".toml", misspelt_wind="[wind]\nspeeed = 3\n")
    evidence = pytester.path / "evidence"
    result = run_inner(pytester, "--firefly-evidence", str(evidence))
    result.assert_outcomes(errors=len(MARKER_ERRORS) + 3)
    assert "Traceback" not in result.stdout.str() + result.stderr.str()

    for test, says in MARKER_ERRORS.items():
        lines = [line for line in block(result, f"ERROR at setup of {test}") if line.strip()]
        assert len(lines) == 1, f"{test}: {lines}"
        assert lines[0].startswith("@pytest.mark.firefly") and says in lines[0], f"{test}: {lines[0]!r}"

    refused = "\n".join(block(result, "ERROR at setup of test_a_scenario_the_autopilot_refuses"))
    section = firefly_section(result, "ERROR at setup of test_a_scenario_the_autopilot_refuses")
    stderr_path = Path(re.search(r"^autopilot stderr: (\S+)$", "\n".join(section), re.M).group(1))
    (said,) = [line for line in stderr_path.read_text().splitlines() if line.strip()]
    assert "unknown key 'speeed'" in said and said in refused, refused

    unknown = "\n".join(block(result, "ERROR at setup of test_an_unknown_parameter"))
    assert "NO_SUCH_PARAM_16 = 1 refused" in unknown and "unknown parameter NO_SUCH_PARAM" in unknown, unknown
    out_of_range = "\n".join(block(result, "ERROR at setup of test_a_parameter_out_of_range"))
    assert "WPNAV_SPEED = 1e+09 refused" in out_of_range and "out of range" in out_of_range, out_of_range

    started = sorted(p.name.split("__", 1)[1] for p in evidence.iterdir())  # "test_refused.py__<test>"
    assert started == ["test_a_parameter_out_of_range", "test_a_scenario_the_autopilot_refuses",
                       "test_an_unknown_parameter"], "a bad marker started a process"


def test_a_bad_speedup_option_is_a_one_line_usage_error(pytester):
    """--firefly-speedup=fast stops pytest before collection with its usage-error status and one
    line naming the option, not a traceback."""
    pytester.makepyfile(test_any="def test_any(firefly): pass\n")
    result = run_inner(pytester, "--firefly-speedup=fast")
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    said = [line for line in result.outlines + result.errlines if line.strip()]
    assert len(said) == 1 and "--firefly-speedup" in said[0] and "'fast'" in said[0], said
