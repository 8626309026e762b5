"""ParamStore: defaults, range checks, integer rounding, persistence and wipe."""
from __future__ import annotations

import json
import math

import pytest

from autopilot.params import PARAM_TABLE, SPEC_BY_NAME, ParamError, ParamStore


def test_table_defaults_are_within_their_own_ranges_and_names_fit_mavlink():
    names = [spec.name for spec in PARAM_TABLE]
    assert len(names) == len(set(names))
    for spec in PARAM_TABLE:
        assert spec.low <= spec.default <= spec.high, spec.name
        assert len(spec.name) <= 16, spec.name  # PARAM_VALUE.param_id is char[16]
        if spec.is_int:
            assert spec.default == int(spec.default), spec.name


def test_store_starts_at_defaults_and_indexes_in_table_order():
    store = ParamStore()
    assert len(store) == len(PARAM_TABLE)
    assert store.names() == [spec.name for spec in PARAM_TABLE]
    for i, spec in enumerate(PARAM_TABLE):
        assert store[spec.name] == spec.default
        assert store.index_of(spec.name) == i
    assert store.get("NOT_A_PARAM", 42) == 42


def test_set_returns_and_stores_the_value_and_notifies():
    store = ParamStore()
    seen = []
    store.on_change(lambda name, value: seen.append((name, value)))
    assert store.set("RTL_ALT", 2500) == 2500.0
    assert store["RTL_ALT"] == 2500.0
    assert seen == [("RTL_ALT", 2500.0)]


@pytest.mark.parametrize("value", [10000.0, -1.0, math.nan, math.inf, -math.inf, "abc", None])
def test_bad_values_raise_and_change_nothing(value, tmp_path):
    path = tmp_path / "params.json"
    store = ParamStore(path)
    seen = []
    store.on_change(lambda *a: seen.append(a))
    before = store["WPNAV_SPEED"]
    with pytest.raises(ParamError, match="WPNAV_SPEED"):
        store.set("WPNAV_SPEED", value)
    assert store["WPNAV_SPEED"] == before
    assert seen == []
    assert not path.exists()  # nothing was saved either


def test_unknown_name_raises():
    with pytest.raises(ParamError, match="unknown parameter"):
        ParamStore().set("NOPE", 1.0)


def test_range_bounds_are_inclusive():
    store = ParamStore()
    spec = SPEC_BY_NAME["WPNAV_SPEED"]
    assert store.set("WPNAV_SPEED", spec.low) == spec.low
    assert store.set("WPNAV_SPEED", spec.high) == spec.high


@pytest.mark.parametrize("value,expected", [(3.7, 4.0), (3.2, 3.0), ("5", 5.0), (6, 6.0)])
def test_integers_are_rounded(value, expected):
    store = ParamStore()
    result = store.set("SR0_POSITION", value)
    assert result == expected and isinstance(result, float)
    assert store["SR0_POSITION"] == expected


def test_floats_are_not_rounded():
    store = ParamStore()
    assert store.set("PSC_POSXY_P", 1.37) == 1.37


def test_persistence_across_stores(tmp_path):
    path = tmp_path / "state" / "params.json"
    first = ParamStore(path)
    first.set("RTL_ALT", 3000)
    first.set("SR0_EXTRA1", 20)
    assert path.exists()
    second = ParamStore(path)
    assert second["RTL_ALT"] == 3000.0
    assert second["SR0_EXTRA1"] == 20.0
    assert second["WPNAV_SPEED"] == SPEC_BY_NAME["WPNAV_SPEED"].default
    # Only changed values are written.
    assert set(json.loads(path.read_text())) == {"RTL_ALT", "SR0_EXTRA1"}


def test_wipe_resets_to_defaults(tmp_path):
    path = tmp_path / "params.json"
    ParamStore(path).set("RTL_ALT", 3000)
    wiped = ParamStore(path, wipe=True)
    assert wiped["RTL_ALT"] == SPEC_BY_NAME["RTL_ALT"].default
    wiped.save_all()
    assert ParamStore(path)["RTL_ALT"] == SPEC_BY_NAME["RTL_ALT"].default


def test_setting_back_to_default_removes_it_from_the_file(tmp_path):
    path = tmp_path / "params.json"
    store = ParamStore(path)
    store.set("RTL_ALT", 3000)
    store.set("RTL_ALT", SPEC_BY_NAME["RTL_ALT"].default)
    assert json.loads(path.read_text()) == {}


@pytest.mark.parametrize("content", ["not json", "[1, 2]", '{"RTL_ALT": "high"}',
                                     '{"RTL_ALT": 1e9}', '{"NOPE": 1}'])
def test_unusable_saved_values_fall_back_to_defaults(tmp_path, content):
    path = tmp_path / "params.json"
    path.write_text(content)
    store = ParamStore(path)
    assert store["RTL_ALT"] == SPEC_BY_NAME["RTL_ALT"].default


def test_partly_bad_file_keeps_the_good_values(tmp_path):
    path = tmp_path / "params.json"
    path.write_text(json.dumps({"RTL_ALT": 2000, "WPNAV_SPEED": -5}))
    store = ParamStore(path)
    assert store["RTL_ALT"] == 2000.0
    assert store["WPNAV_SPEED"] == SPEC_BY_NAME["WPNAV_SPEED"].default


def test_no_temp_files_left_behind(tmp_path):
    path = tmp_path / "params.json"
    store = ParamStore(path)
    for v in (1000, 2000, 3000):
        store.set("RTL_ALT", v)
    assert [p.name for p in tmp_path.iterdir()] == ["params.json"]


def test_a_killed_writers_temporary_is_removed_at_load_and_the_file_kept(tmp_path):
    path = tmp_path / "params.json"
    ParamStore(path).set("RTL_ALT", 2500)
    torn = tmp_path / ".params.json-abc123"
    torn.write_text('{"RTL_ALT": 30')  # what a write killed half-way leaves: never the real file
    store = ParamStore(path)
    assert store["RTL_ALT"] == 2500.0
    assert not torn.exists() and path.exists()


def test_a_refusing_disk_is_counted_and_the_value_still_takes_effect(tmp_path):
    gone = tmp_path / "gone"
    gone.mkdir()
    store = ParamStore(gone / "params.json")
    seen = []
    store.on_change(lambda name, value: seen.append((name, value)))
    gone.rmdir()
    gone.write_text("a file where the state directory was")  # the save cannot create the directory
    assert store.set("WPNAV_SPEED", 600) == 600.0
    assert store["WPNAV_SPEED"] == 600.0 and seen == [("WPNAV_SPEED", 600.0)]
    assert store.save_errors == 1 and "params.json" in store.last_save_error


def test_setting_the_value_in_force_changes_nothing_and_notifies_no_one(tmp_path):
    store = ParamStore(tmp_path / "params.json")
    seen = []
    store.on_change(lambda name, value: seen.append(name))
    store.set("SIM_BATT_VOLTAGE", store["SIM_BATT_VOLTAGE"])  # a GCS re-sending its whole list
    store.set("RTL_ALT", store["RTL_ALT"])
    assert seen == []
    store.set("RTL_ALT", 2000)
    assert seen == ["RTL_ALT"]
