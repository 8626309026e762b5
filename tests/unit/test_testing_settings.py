"""The pytest plugin's pure parts: marker settings checked in one line each, and the state-log
reader following a file that is still being written."""
from __future__ import annotations

import math

import pytest

from autopilot.io.state_log import HEADER
from autopilot.testing.settings import FireflySettings, SettingsError, seed_for, settings
from autopilot.testing.state import StateLogReader

DEFAULTS = FireflySettings(speedup=10.0, seed=5)


def test_marker_keys_apply_over_the_defaults(tmp_path):
    (tmp_path / "world.toml").write_text("seed = 1\n")
    s = settings({"speedup": "inf", "scenario": "world.toml", "home": (1, 2, 3), "params": {"WPNAV_SPEED": 500},
                  "faults": {"SIM_GPS_DISABLE": 1}, "count": 3, "airborne": 10, "startup": "realistic"},
                 DEFAULTS, tmp_path)
    assert math.isinf(s.speedup) and s.speedup_text == "inf"
    assert s.scenario == tmp_path / "world.toml" and s.home == "1.0,2.0,3.0"
    assert s.params == {"WPNAV_SPEED": 500.0} and s.faults == {"SIM_GPS_DISABLE": 1.0}
    assert (s.count, s.airborne, s.startup, s.seed) == (3, 10.0, "realistic", 5)
    assert settings({}, DEFAULTS, tmp_path) == DEFAULTS


@pytest.mark.parametrize("kwargs, args, says", [
    ({"sped": 1}, (), "unknown key 'sped'"),
    ({"speedup": 0}, (), "(speedup=...): expected a positive number or 'inf'"),
    ({"speedup": "fast"}, (), "(speedup=...)"),
    ({"scenario": "nowhere.toml"}, (), "(scenario=...): no scenario file"),
    ({"scenario": 3}, (), "(scenario=...): expected a path"),
    ({"home": (91, 0, 0)}, (), "(home=...): latitude must be in -90..90"),
    ({"home": "1,2"}, (), "(home=...): expected (lat, lon, alt[, yaw])"),
    ({"seed": -1}, (), "(seed=...): expected an integer"),
    ({"seed": 1.5}, (), "(seed=...)"),
    ({"params": {"WPNAV_SPEED": math.nan}}, (), "(params=...)['WPNAV_SPEED']: expected a finite number"),
    ({"params": {"A" * 17: 1}}, (), "is not a parameter name"),
    ({"params": [1]}, (), "(params=...): expected a dict"),
    ({"faults": {"WPNAV_SPEED": 1}}, (), "WPNAV_SPEED is not a SIM_* parameter"),
    ({"count": 51}, (), "(count=...): expected an integer in 1..50"),
    ({"count": True}, (), "(count=...)"),
    ({"airborne": 0.5}, (), "(airborne=...): expected a height in 1..500 m"),
    ({"startup": "slow"}, (), "(startup=...): expected 'instant' or 'realistic'"),
    ({}, (10,), "takes keywords only"),
])
def test_a_bad_marker_is_one_line_naming_the_marker_and_key(tmp_path, kwargs, args, says):
    with pytest.raises(SettingsError) as caught:
        settings(kwargs, DEFAULTS, tmp_path, args)
    text = str(caught.value)
    assert text.startswith("@pytest.mark.firefly") and says in text and "\n" not in text


def test_seeds_are_stable_and_differ_between_tests():
    assert seed_for("tests.test_app::test_a") == seed_for("tests.test_app::test_a")
    assert seed_for("tests.test_app::test_a") != seed_for("tests.test_app::test_b")
    assert 0 <= seed_for("x") < 2 ** 31


def line(t: float, armed: int = 0, mode: int = 0, home: str = "0.0,0.0,0.0", d: float = 0.0) -> str:
    return f"{t!r},1.0,2.0,{d!r},0.0,0.0,0.0,1.0,0.0,0.0,0.0,0.0,0.0,0.0,1,{armed},{mode},{home}\n"


def test_the_reader_waits_for_the_header_and_for_unfinished_lines(tmp_path):
    path = tmp_path / "state.csv"
    reader = StateLogReader(path)
    assert reader.new_states() == []  # no file yet
    path.write_text(HEADER[:10])
    assert reader.new_states() == []  # the header is not whole yet
    with open(path, "w") as f:
        f.write(HEADER + line(0.1))
        f.write(line(0.2)[:12])  # half a line
        f.flush()
        assert [s.time_s for s in reader.new_states()] == [0.1]
        f.write(line(0.2)[12:] + line(0.3, armed=1, mode=4, d=-5.0))
        f.flush()
        states = reader.new_states()
    assert [s.time_s for s in states] == [0.2, 0.3]
    last = states[-1]
    assert last.armed and last.mode == "GUIDED" and last.altitude_m == 5.0
    assert last.distance_from_home_m == pytest.approx(math.hypot(1.0, 2.0))
    assert reader.latest is last


def test_a_reader_from_the_end_skips_the_line_it_starts_in_and_home_may_be_unset(tmp_path):
    path = tmp_path / "state.csv"
    with open(path, "w") as f:
        f.write(HEADER + line(0.1) + line(0.2)[:20])
        f.flush()
        reader = StateLogReader(path, from_end=True)
        assert reader.new_states() == []
        f.write(line(0.2)[20:] + line(0.3, home=",,"))
        f.flush()
        (state,) = reader.new_states()
    assert state.time_s == 0.3 and state.home_ned_m is None and state.altitude_m == 0.0
    assert StateLogReader(path).latest_state().time_s == 0.3
    assert StateLogReader(path, from_end=True).new_states() == []  # at a line's end: nothing older


def test_unknown_mode_numbers_are_shown_as_numbers(tmp_path):
    path = tmp_path / "state.csv"
    path.write_text(HEADER + line(0.1, mode=99))
    assert StateLogReader(path).latest_state().mode == "99"
