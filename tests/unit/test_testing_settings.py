"""The pytest plugin's pure parts (autopilot/testing): a marker's keys checked in one line each
before any process starts, the command line's speedup, the per-test seed, and the state-log reader
following a file the autopilot is still writing."""
from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from firefly.autopilot.io.state_log import COLUMNS, HEADER
from firefly.autopilot.testing.settings import FireflySettings, SettingsError, parse_speedup, seed_for, settings
from firefly.autopilot.testing.state import StateLogReader

RUN_DEFAULTS = FireflySettings(speedup=10.0, seed=5)  # what the command line gives every test


# ----- the marker ----------------------------------------------------------------------------
def test_every_marker_key_applies_over_the_run_defaults(tmp_path):
    """Each key of @pytest.mark.firefly lands in the settings, converted to what the autopilot is
    started with; a key not given keeps the run's default (here the seed)."""
    (tmp_path / "world.toml").write_text("seed = 1\n")
    s = settings({"speedup": "inf", "scenario": "world.toml", "home": (47.5, 8.5, 400, 90),
                  "params": {"WPNAV_SPEED": 500}, "faults": {"SIM_GPS_DISABLE": 1}, "count": 3,
                  "airborne": 10, "startup": "realistic"}, RUN_DEFAULTS, tmp_path)
    assert math.isinf(s.speedup) and s.speedup_text == "inf"
    assert s.scenario == tmp_path / "world.toml"
    assert s.home == "47.5,8.5,400.0,90.0"
    assert s.params == {"WPNAV_SPEED": 500.0} and s.faults == {"SIM_GPS_DISABLE": 1.0}
    assert (s.count, s.airborne, s.startup, s.seed) == (3, 10.0, "realistic", 5)
    assert settings({"seed": 7}, RUN_DEFAULTS, tmp_path).seed == 7


def test_no_marker_keys_keep_the_run_defaults(tmp_path):
    assert settings({}, RUN_DEFAULTS, tmp_path) == RUN_DEFAULTS


def test_a_scenario_path_is_relative_to_the_test_file_unless_absolute(tmp_path):
    """A test names its scenario beside it ("wind.toml"), wherever pytest was started from."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "wind.toml").write_text("")
    beside = settings({"scenario": "wind.toml"}, RUN_DEFAULTS, tmp_path / "tests")
    assert beside.scenario == tmp_path / "tests" / "wind.toml"
    absolute = settings({"scenario": str(tmp_path / "tests" / "wind.toml")}, RUN_DEFAULTS, tmp_path / "elsewhere")
    assert absolute.scenario == tmp_path / "tests" / "wind.toml"


@pytest.mark.parametrize("kwargs, args, says", [
    ({"spedup": 1}, (), "unknown key 'spedup'"),
    ({"speedup": 0}, (), "(speedup=...): expected a positive number or 'inf'"),
    ({"speedup": -1}, (), "(speedup=...): expected a positive number or 'inf', got -1"),
    ({"speedup": "fast"}, (), "(speedup=...): expected a positive number or 'inf', got 'fast'"),
    ({"speedup": True}, (), "(speedup=...): expected a positive number or 'inf', got True"),
    ({"scenario": "nowhere.toml"}, (), "(scenario=...): no scenario file"),
    ({"scenario": 3}, (), "(scenario=...): expected a path"),
    ({"home": (91, 0, 0)}, (), "(home=...): latitude must be in -90..90"),
    ({"home": "1,2"}, (), "(home=...): expected (lat, lon, alt[, yaw])"),
    ({"home": "north,2,3"}, (), "(home=...): expected (lat, lon, alt[, yaw])"),
    ({"seed": -1}, (), "(seed=...): expected an integer in 0..2**31-1"),
    ({"seed": 2 ** 31}, (), "(seed=...): expected an integer"),
    ({"seed": 1.5}, (), "(seed=...): expected an integer"),
    ({"seed": True}, (), "(seed=...): expected an integer"),
    ({"params": {"WPNAV_SPEED": math.nan}}, (), "(params=...)['WPNAV_SPEED']: expected a finite number"),
    ({"params": {"WPNAV_SPEED": "750"}}, (), "(params=...)['WPNAV_SPEED']: expected a finite number"),
    ({"params": {"A" * 17: 1}}, (), "(params=...): 'AAAAAAAAAAAAAAAAA' is not a parameter name"),
    ({"params": {"": 1}}, (), "(params=...): '' is not a parameter name"),
    ({"params": [("WPNAV_SPEED", 1)]}, (), "(params=...): expected a dict"),
    ({"faults": {"WPNAV_SPEED": 1}}, (), "(faults=...): WPNAV_SPEED is not a SIM_* parameter"),
    ({"faults": {"SIM_GPS_DISABLE": True}}, (), "(faults=...)['SIM_GPS_DISABLE']: expected a finite number"),
    ({"count": 0}, (), "(count=...): expected an integer in 1..1000"),
    ({"count": 1001}, (), "(count=...): expected an integer in 1..1000"),
    ({"count": True}, (), "(count=...): expected an integer"),
    ({"airborne": 0.5}, (), "(airborne=...): expected a height in 1..500 m"),
    ({"airborne": "10"}, (), "(airborne=...): expected a finite number"),
    ({"startup": "slow"}, (), "(startup=...): expected 'instant' or 'realistic'"),
    ({}, (10,), "takes keywords only"),
])
def test_a_bad_marker_is_one_line_naming_the_marker_and_the_key(tmp_path, kwargs, args, says):
    """What the test's setup error shows: one line, starting with the marker, saying which key
    is wrong and why."""
    with pytest.raises(SettingsError) as caught:
        settings(kwargs, RUN_DEFAULTS, tmp_path, args)
    text = str(caught.value)
    assert text.startswith("@pytest.mark.firefly") and says in text and "\n" not in text, text


# ----- the command line and the seed ---------------------------------------------------------
@pytest.mark.parametrize("given_value, speedup", [("inf", math.inf), (" INF ", math.inf), ("50", 50.0),
                                                  ("0.5", 0.5), (10, 10.0)])
def test_the_speedup_option_takes_a_positive_number_or_inf(given_value, speedup):
    assert parse_speedup(given_value, "--firefly-speedup") == speedup


@pytest.mark.parametrize("given_value", ["fast", "0", "-3", "nan", "-inf", ""])
def test_a_bad_speedup_option_names_the_option(given_value):
    with pytest.raises(SettingsError, match=r"^--firefly-speedup: expected a positive number or 'inf', got "):
        parse_speedup(given_value, "--firefly-speedup")


@pytest.mark.parametrize("speedup, text", [(10.0, "10"), (2.5, "2.5"), (math.inf, "inf")])
def test_the_speedup_is_passed_to_the_autopilot_as_it_reads_it(speedup, text):
    assert FireflySettings(speedup=speedup).speedup_text == text


def test_a_test_always_gets_the_same_seed_and_two_tests_get_different_ones():
    assert seed_for("tests.test_app::test_a") == seed_for("tests.test_app::test_a")
    assert seed_for("tests.test_app::test_a") != seed_for("tests.test_app::test_b")
    assert seed_for("tests.test_app::test_a[1]") != seed_for("tests.test_app::test_a[2]")


@given(st.text())
def test_a_seed_is_one_the_autopilot_and_the_marker_accept(identity):
    assert 0 <= seed_for(identity) < 2 ** 31


# ----- the state log -------------------------------------------------------------------------
def state_line(time_s: float, north_m: float = 0.0, east_m: float = 0.0, down_m: float = 0.0,
               on_ground: bool = True, armed: bool = False, mode: int = 0,
               home: tuple | None = (0.0, 0.0, 0.0), yaw_deg: float = 0.0) -> str:
    """One line as autopilot/io/state_log.py writes it (every column, in its order)."""
    half_yaw = math.radians(yaw_deg) / 2
    values = {"time_s": time_s, "n_m": north_m, "e_m": east_m, "d_m": down_m,
              "vn_m_s": 3.0, "ve_m_s": 4.0, "vd_m_s": 0.0,
              "qw": math.cos(half_yaw), "qx": 0.0, "qy": 0.0, "qz": math.sin(half_yaw),
              "p_rad_s": 0.0, "q_rad_s": 0.0, "r_rad_s": 0.0,
              "on_ground": int(on_ground), "armed": int(armed), "mode": mode}
    if home is not None:
        values.update(home_n_m=home[0], home_e_m=home[1], home_d_m=home[2])
    return ",".join(repr(values[c]) if c in values else "" for c in COLUMNS) + "\n"


LOG = HEADER + "".join(state_line(round(0.1 * k, 1), down_m=-0.5 * k) for k in range(1, 8))


def times(states) -> list[float]:
    return [s.time_s for s in states]


def test_a_reader_waits_for_the_file_and_its_whole_header(tmp_path):
    """The autopilot may not have created the file, or written all of the header, when the test
    first looks: the reader returns nothing and reads the header again next time."""
    path = tmp_path / "state.csv"
    reader = StateLogReader(path)
    assert reader.new_states() == [] and reader.latest_state() is None  # no file yet
    path.write_text(HEADER[:25])
    assert reader.new_states() == []  # half a header
    path.write_text(HEADER)
    assert reader.new_states() == []  # a header and no state yet
    path.write_text(HEADER + state_line(0.1))
    assert times(reader.new_states()) == [0.1]


def test_a_reader_keeps_a_half_written_line_until_it_is_whole(tmp_path):
    path = tmp_path / "state.csv"
    second = state_line(0.2, armed=True)
    with open(path, "w") as log:
        log.write(HEADER + state_line(0.1) + second[:17])
        log.flush()
        reader = StateLogReader(path)
        assert times(reader.new_states()) == [0.1]
        assert reader.new_states() == []  # still half a line
        log.write(second[17:-1])
        log.flush()
        assert reader.new_states() == []  # all but its newline
        log.write("\n" + state_line(0.3))
        log.flush()
        states = reader.new_states()
    assert times(states) == [0.2, 0.3] and states[0].armed
    assert reader.latest is states[-1]


@given(st.lists(st.integers(min_value=0, max_value=len(LOG)), max_size=12))
def test_however_the_writes_are_cut_a_reader_sees_every_state_once_in_order(tmp_path_factory, cuts):
    """Whatever points the file grows at between reads (in the header, mid-line, mid-number),
    the states read add up to the whole log."""
    path = tmp_path_factory.mktemp("log") / "state.csv"
    reader = StateLogReader(path)
    seen = []
    with open(path, "w") as log:
        written = 0
        for cut in sorted(cuts) + [len(LOG)]:
            log.write(LOG[written:cut])
            log.flush()
            written = cut
            seen += reader.new_states()
    assert times(seen) == [round(0.1 * k, 1) for k in range(1, 8)]


def test_a_reader_from_the_end_skips_the_line_it_starts_in(tmp_path):
    """A wait's reader starts at the end of the log: a line half written when it starts is older
    than the wait, so its rest is skipped and the next whole line is the first state it sees."""
    path = tmp_path / "state.csv"
    with open(path, "w") as log:
        log.write(HEADER + state_line(0.1) + state_line(0.2)[:20])
        log.flush()
        reader = StateLogReader(path, from_end=True)
        assert reader.new_states() == []
        log.write(state_line(0.2)[20:30])
        log.flush()
        assert reader.new_states() == []  # still the skipped line
        log.write(state_line(0.2)[30:] + state_line(0.3))
        log.flush()
        assert times(reader.new_states()) == [0.3]


@pytest.mark.parametrize("before, then", [
    (HEADER + state_line(0.1) + state_line(0.2), 0.3),  # at a line end: the next line
    (HEADER, 0.1),  # a header-only log: the first state
], ids=["at a line end", "after the header only"])
def test_a_reader_from_the_end_takes_only_what_comes_after_it(tmp_path, before, then):
    path = tmp_path / "state.csv"
    with open(path, "w") as log:
        log.write(before)
        log.flush()
        reader = StateLogReader(path, from_end=True)
        assert reader.new_states() == []  # nothing older than the reader
        log.write(state_line(then))
        log.flush()
        assert times(reader.new_states()) == [then]


def test_the_latest_state_is_the_newest_whole_line(tmp_path):
    path = tmp_path / "state.csv"
    with open(path, "w") as log:
        log.write(HEADER + state_line(0.1) + state_line(0.2) + state_line(0.3)[:10])
        log.flush()
        reader = StateLogReader(path)
        assert reader.latest_state().time_s == 0.2
        assert reader.latest_state().time_s == 0.2  # nothing new: the same state again
        log.write(state_line(0.3)[10:])
        log.flush()
        assert reader.latest_state().time_s == 0.3


# ----- what a state says ---------------------------------------------------------------------
def test_altitude_and_distance_are_from_home(tmp_path):
    path = tmp_path / "state.csv"
    path.write_text(HEADER + state_line(1.0, north_m=13.0, east_m=14.0, down_m=-12.0, on_ground=False,
                                        armed=True, mode=4, home=(10.0, 10.0, -2.0), yaw_deg=90.0))
    state = StateLogReader(path).latest_state()
    assert state.altitude_m == pytest.approx(10.0)  # 12 m up, home 2 m up
    assert state.distance_from_home_m == pytest.approx(5.0)  # 3 m north and 4 m east of home
    assert state.ground_speed_m_s == pytest.approx(5.0)
    assert state.yaw_deg == pytest.approx(90.0)
    assert state.mode == "GUIDED" and state.armed and not state.landed
    assert "GUIDED armed" in str(state) and "altitude 10.00 m" in str(state)


def test_before_home_is_set_the_origin_stands_in_for_it(tmp_path):
    path = tmp_path / "state.csv"
    path.write_text(HEADER + state_line(0.1, north_m=3.0, east_m=4.0, down_m=-1.0, home=None))
    state = StateLogReader(path).latest_state()
    assert state.home_ned_m is None
    assert state.altitude_m == pytest.approx(1.0) and state.distance_from_home_m == pytest.approx(5.0)


def test_landed_means_on_the_ground_and_disarmed(tmp_path):
    path = tmp_path / "state.csv"
    path.write_text(HEADER + state_line(0.1, on_ground=True, armed=True) + state_line(0.2, on_ground=False)
                    + state_line(0.3, on_ground=True, armed=False, mode=9))
    armed_on_ground, falling, landed = StateLogReader(path).new_states()
    assert not armed_on_ground.landed and not falling.landed and landed.landed
    assert landed.mode == "LAND"


def test_a_mode_firefly_has_no_name_for_shows_its_number(tmp_path):
    path = tmp_path / "state.csv"
    path.write_text(HEADER + state_line(0.1, mode=99))
    assert StateLogReader(path).latest_state().mode == "99"
