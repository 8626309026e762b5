"""ParamStore: defaults, range checks, integer rounding, persistence and wipe; the served set
(the reference's parameters, then Firefly's own) and its recorded differences."""
from __future__ import annotations

import json
import math

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.params import PARAM_TABLE, SERVED, SPEC_BY_NAME, ParamError, ParamStore
from firefly.autopilot.params_differences import (DEFAULT_DIFFERENCES, FIREFLY_ONLY, IN_PROCESS_ONLY, OLD_NAMES,
                                                  SEMANTIC_DIFFERENCES)
from firefly.autopilot.reference_params import recording, reference_params

REFERENCE = {ref.name: ref for ref in reference_params()}


def test_table_defaults_are_within_their_own_ranges_and_names_fit_mavlink():
    names = [spec.name for spec in PARAM_TABLE]
    assert len(names) == len(set(names))
    for spec in PARAM_TABLE:
        assert spec.low <= spec.default <= spec.high, spec.name
        assert len(spec.name) <= 16, spec.name  # PARAM_VALUE.param_id is char[16]
        if spec.is_int:
            assert spec.default == int(spec.default), spec.name


def test_store_starts_at_defaults_and_indexes_in_served_order():
    store = ParamStore()
    assert len(store) == len(SERVED) == len(set(store.names()))
    assert store.names() == [spec.name for spec in SERVED]
    for i, spec in enumerate(SERVED):
        assert store[spec.name] == spec.default
        assert store.index_of(spec.name) == i
    assert store.get("NOT_A_PARAM", 42) == 42


def test_the_reference_recording_is_whole():
    header = recording()
    assert header["commit"] == "90700977c553d2dfd95a305acf1c3e098e4d9477"
    assert len(reference_params()) == header["param_count"] >= 1300
    for name in ("ARMING_CHECK", "FS_THR_ENABLE", "FLTMODE1", "BATT_MONITOR", "SERIAL1_PROTOCOL"):
        assert name in REFERENCE


def test_every_reference_parameter_is_served_first_in_its_order_with_its_type():
    store = ParamStore()
    names = store.names()
    assert names[:len(REFERENCE)] == [ref.name for ref in reference_params()]
    for ref in reference_params():
        assert store.mav_type(ref.name) == ref.mav_type, ref.name
    # then Firefly's own, each with its reason; the other modelled names the reference does not
    # have (4.5's) are known in-process only
    assert set(names[len(REFERENCE):]) == set(FIREFLY_ONLY)
    assert {s.name for s in PARAM_TABLE} - set(REFERENCE) == set(FIREFLY_ONLY) | (set(IN_PROCESS_ONLY) - set(OLD_NAMES))
    assert set(OLD_NAMES) <= set(IN_PROCESS_ONLY)
    assert all(FIREFLY_ONLY.values()) and all(IN_PROCESS_ONLY.values())
    for name in IN_PROCESS_ONLY:
        assert name not in store and name not in names
        store.set(name, store[name])  # known to set() and reads
    for name in FIREFLY_ONLY:
        # ArduCopter's own type where it was measured (the rangefinder's), else int32 or float
        expected = SPEC_BY_NAME[name].mav_type or (mav.MAV_PARAM_TYPE_INT32 if SPEC_BY_NAME[name].is_int
                                                   else mav.MAV_PARAM_TYPE_REAL32)
        assert store.mav_type(name) == expected


def test_defaults_are_the_references_but_where_a_difference_is_written_down():
    store = ParamStore()
    differing = {name for name, ref in REFERENCE.items()
                 if not math.isclose(store[name], ref.default, rel_tol=1e-6, abs_tol=1e-9)}
    assert differing == set(DEFAULT_DIFFERENCES)  # each difference listed, and each listed one real
    assert all(DEFAULT_DIFFERENCES.values()) and all(SEMANTIC_DIFFERENCES.values())
    assert set(SEMANTIC_DIFFERENCES) <= set(REFERENCE) & set(SPEC_BY_NAME)


def test_an_old_name_shares_the_references_value_in_process_only(tmp_path):
    assert set(OLD_NAMES.values()) <= set(REFERENCE) & set(SPEC_BY_NAME) and not set(OLD_NAMES) & set(REFERENCE)
    store = ParamStore(tmp_path / "params.json")
    heard = []
    store.on_change(lambda name, value: heard.append((name, value)))
    assert "SR0_EXTRA1" not in store  # not served: the reference's name is
    assert store.set("SR0_EXTRA1", 20) == 20.0  # as a scenario written for 4.5 sets it
    assert store["SR0_EXTRA1"] == store["MAV1_EXTRA1"] == 20.0
    assert heard == [("MAV1_EXTRA1", 20.0)]  # the vehicle's code reads the reference's name
    with pytest.raises(ParamError, match="MAV1_EXTRA1"):
        store.set("MAV1_EXTRA1", 51)  # the modelled range
    assert ParamStore(tmp_path / "params.json")["MAV1_EXTRA1"] == 20.0
    # a file saved under the old name (before Firefly served 4.7's names) is taken up
    (tmp_path / "old.json").write_text(json.dumps({"SR0_EXTRA1": 7}))
    assert ParamStore(tmp_path / "old.json")["MAV1_EXTRA1"] == 7.0


def test_a_parameter_firefly_does_not_model_is_stored_checked_and_persisted(tmp_path):
    path = tmp_path / "params.json"
    store = ParamStore(path)
    assert not store.acts("SUPER_SIMPLE") and store.acts("RTL_ALT") and store.acts("MAV_SYSID")
    assert store["SUPER_SIMPLE"] == REFERENCE["SUPER_SIMPLE"].default
    assert store.set("SUPER_SIMPLE", 4.4) == 4.0  # INT8: rounded
    with pytest.raises(ParamError, match="SUPER_SIMPLE: 300 out of range -128..127"):
        store.set("SUPER_SIMPLE", 300)  # beyond what an INT8 holds
    ranged = REFERENCE["PILOT_THR_FILT"]  # documented @Range 0..10
    with pytest.raises(ParamError, match="out of range"):
        store.set("PILOT_THR_FILT", ranged.high + 1)
    store.set("PILOT_THR_FILT", ranged.high)
    assert json.loads(path.read_text()) == {"SUPER_SIMPLE": 4.0, "PILOT_THR_FILT": ranged.high}
    again = ParamStore(path)
    assert again["SUPER_SIMPLE"] == 4.0 and again["PILOT_THR_FILT"] == ranged.high


def test_a_documented_range_that_excludes_the_references_default_is_widened_to_hold_it():
    for spec in SERVED:
        assert spec.low <= spec.default <= spec.high, spec.name


def test_reference_sim_parameters_are_not_saved_either(tmp_path):
    path = tmp_path / "params.json"
    ParamStore(path).set("SIM_SONAR_GLITCH", 0.5)
    assert ParamStore(path)["SIM_SONAR_GLITCH"] == REFERENCE["SIM_SONAR_GLITCH"].default


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
    first.set("MAV1_EXTRA1", 20)
    assert path.exists()
    second = ParamStore(path)
    assert second["RTL_ALT"] == 3000.0
    assert second["MAV1_EXTRA1"] == 20.0
    assert second["WPNAV_SPEED"] == SPEC_BY_NAME["WPNAV_SPEED"].default
    # Only changed values are written.
    assert set(json.loads(path.read_text())) == {"RTL_ALT", "MAV1_EXTRA1"}


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


def test_a_store_writes_at_most_once_per_interval_and_the_last_change_after_it(tmp_path):
    from firefly.autopilot.io.persist import JsonFile
    (tmp_path / "d").mkdir()
    f = JsonFile(tmp_path / "d" / "x.json")
    now = [100.0]
    f.min_interval_s, f.clock = 0.5, lambda: now[0]
    assert f.save(lambda: {"v": 1}) and json.loads((tmp_path / "d" / "x.json").read_text()) == {"v": 1}
    for v in range(2, 50):  # a flood within the interval: nothing written yet, the last one waits
        f.save(lambda v=v: {"v": v})
    assert json.loads((tmp_path / "d" / "x.json").read_text()) == {"v": 1} and f.pending and f in f.waiting
    f.poll(100.3)
    assert f.pending
    f.poll(100.6)
    assert json.loads((tmp_path / "d" / "x.json").read_text()) == {"v": 49} and not f.pending and not f.waiting
    now[0] = 200.0  # after a quiet spell the next change is written at once, and its failure told
    for leftover in (tmp_path / "d").iterdir():
        leftover.unlink()
    (tmp_path / "d").rmdir()
    (tmp_path / "d").write_text("a file where the directory was")
    assert f.save(lambda: {"v": 50}) is False and not f.pending and f.save_errors == 1
