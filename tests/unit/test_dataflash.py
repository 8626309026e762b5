"""The dataflash log, sans-IO and its files: the self-description round-trips through pymavlink's
DFReader, a flown vehicle's records hold its state, and the files are numbered, rotated and
erased as ArduPilot's file backend does."""
from __future__ import annotations

import math

import pytest
from pymavlink import DFReader

from firefly.autopilot.dataflash.encoding import LogFormat
from firefly.autopilot.dataflash.messages import MESSAGES, MULTS, UNITS
from firefly.autopilot.dataflash.recorder import ARM_PERSIST_S, Recorder
from firefly.autopilot.io.dataflash_files import LogFiles
from firefly.autopilot.modes import Guided, Land
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result

from ._util import fly_until, ready_vehicle

TICK_S = 0.01


class MemorySink:
    """A LogSink that keeps each log's bytes in memory."""

    def __init__(self):
        self.logs: list[bytearray] = []
        self.open = False
        self.paused = False

    def start(self):
        self.logs.append(bytearray())
        self.open = True

    def write(self, data):
        assert self.open
        self.logs[-1] += data

    def stop(self):
        self.open = False


def run(vehicle, recorder, seconds):
    end = vehicle.time_s + seconds
    while vehicle.time_s < end - 1e-9:
        vehicle.run_until(vehicle.time_s + TICK_S)
        recorder.tick()


def read_log(tmp_path, data: bytes) -> dict[str, list]:
    path = tmp_path / "log.BIN"
    path.write_bytes(bytes(data))
    log = DFReader.DFReader_binary(str(path))
    out: dict[str, list] = {}
    while (m := log.recv_msg()) is not None:
        out.setdefault(m.get_type(), []).append(m)
    return out


def flown_log(tmp_path, **params):
    v = ready_vehicle()
    for name, value in params.items():
        v.params.set(name, value)
    sink = MemorySink()
    rec = Recorder(v, sink)
    v.text_listener = rec.text
    run(v, rec, 1.0)
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.takeoff(5.0) == Result.ACCEPTED
    for _ in range(1200):
        run(v, rec, 0.05)
        if v.home_ned[2] - v.body.d_m > 4.8:
            break
    run(v, rec, 2.0)
    assert v.set_mode(Land.number) == Result.ACCEPTED
    for _ in range(1200):
        run(v, rec, 0.1)
        if not v.armed:
            break
    assert not v.armed
    return v, sink


def test_every_format_round_trips_through_dfreader(tmp_path):
    v, sink = flown_log(tmp_path)
    msgs = read_log(tmp_path, sink.logs[0])
    fmts = {m.Name: m for m in msgs["FMT"]}
    for name, message in MESSAGES.items():
        f = message.format
        assert (fmts[name].Type, fmts[name].Length, fmts[name].Format, fmts[name].Columns) == \
            (f.type_id, f.length, f.fmt, f.columns)
    units = {chr(m.Id): m.Label for m in msgs["UNIT"]}
    mults = {chr(m.Id): m.Mult for m in msgs["MULT"]}
    assert units == UNITS and mults == MULTS
    fmtu = {m.FmtType: (m.UnitIds, m.MultIds) for m in msgs["FMTU"]}
    assert all(fmtu[m.format.type_id] == (m.format.units, m.format.mults) for m in MESSAGES.values())


def test_a_flight_log_holds_the_flight(tmp_path):
    v, sink = flown_log(tmp_path)
    msgs = read_log(tmp_path, sink.logs[0])
    assert [e.Id for e in msgs["EV"]][:2] == [10, 28] and [e.Id for e in msgs["EV"]][-2:] == [18, 11]
    assert [m.ModeNum for m in msgs["MODE"]] == [Guided.number, Land.number]
    assert "Arming motors" in [m.Message for m in msgs["MSG"]]
    parm = {m.Name: m.Value for m in msgs["PARM"]}
    assert len(parm) == len(v.params) and parm["WPNAV_SPEED"] == v.params["WPNAV_SPEED"]
    alts = [p.RelHomeAlt for p in msgs["POS"]]
    assert max(alts) == pytest.approx(5.0, abs=0.3)
    home = v.home
    assert all(abs(g.Lat - home.lat_deg) < 1e-4 and abs(g.Lng - home.lon_deg) < 1e-4 for g in msgs["GPS"])
    assert all(abs(a.Roll) < 5 and abs(a.Pitch) < 5 for a in msgs["ATT"])
    for name, hz in (("ATT", 10), ("IMU", 2 * 25), ("GPS", 5), ("BARO", 2 * 10), ("BAT", 10)):
        records = msgs[name]
        span = (records[-1].TimeUS - records[0].TimeUS) / 1e6
        assert len(records) / span == pytest.approx(hz, rel=0.05), name
    times = [m.TimeUS for m in msgs["ATT"]]
    assert times == sorted(times) and all(t % 10_000 == 0 for t in times)  # sim time


def test_nothing_is_logged_disarmed_until_an_arming(tmp_path):
    v = ready_vehicle()
    sink = MemorySink()
    rec = Recorder(v, sink)
    run(v, rec, 3.0)
    assert sink.logs == []
    assert v.arm() == Result.ACCEPTED
    run(v, rec, 0.5)
    assert v.disarm() == Result.ACCEPTED
    run(v, rec, ARM_PERSIST_S - 1)
    size = len(sink.logs[0])
    run(v, rec, 2.0)  # 15 s after the disarm logging stops; the file stays open
    stopped = len(sink.logs[0])
    run(v, rec, 1.0)
    assert stopped > size and len(sink.logs[0]) == stopped and len(sink.logs) == 1 and sink.open


def test_a_recorder_sleeps_while_nothing_is_logged_and_wakes_on_arming(tmp_path):
    from firefly.autopilot.modes import Loiter, Stabilize
    v = ready_vehicle()
    sink = MemorySink()
    rec = Recorder(v, sink)
    v.text_listener = rec.text
    run(v, rec, 0.5)
    assert not rec.awake  # a never-armed vehicle's loop pays one read a tick for its log
    v.params.set("WPNAV_SPEED", 600.0)  # a PARM record to make: awake, then asleep
    assert rec.awake
    run(v, rec, 0.1)
    assert not rec.awake
    assert v.set_mode(Loiter.number) == Result.ACCEPTED and v.set_mode(Stabilize.number) == Result.ACCEPTED
    run(v, rec, 0.5)  # mode changes before the arming: not logged (nothing was), the log starts in STABILIZE
    assert v.arm() == Result.ACCEPTED
    run(v, rec, 0.5)
    assert rec.awake
    log = read_log(tmp_path, sink.logs[0])
    assert [m.Mode for m in log["MODE"]] == [Stabilize.number]
    assert [e.Id for e in log["EV"]][:1] == [10]


def test_log_disarmed_logs_from_the_start_and_backend_0_never(tmp_path):
    for params, expect_logs in (({"LOG_DISARMED": 1}, 1), ({"LOG_BACKEND_TYPE": 0, "LOG_DISARMED": 1}, 0)):
        v = ready_vehicle()
        sink = MemorySink()
        for name, value in params.items():
            v.params.set(name, value)
        rec = Recorder(v, sink)
        run(v, rec, 0.5)
        assert len(sink.logs) == expect_logs


def test_disarm_rotation_gives_each_flight_its_own_log(tmp_path):
    v = ready_vehicle()
    v.params.set("LOG_FILE_DSRMROT", 1)
    sink = MemorySink()
    rec = Recorder(v, sink)
    for _ in range(2):
        assert v.arm() == Result.ACCEPTED
        run(v, rec, 0.5)
        assert v.disarm() == Result.ACCEPTED
        run(v, rec, ARM_PERSIST_S + 1)
        assert not sink.open
    assert len(sink.logs) == 2


def test_bitmask_leaves_out_groups(tmp_path):
    v = ready_vehicle()
    v.params.set("LOG_BITMASK", 0)
    sink = MemorySink()
    rec = Recorder(v, sink)
    assert v.arm() == Result.ACCEPTED
    run(v, rec, 1.0)
    msgs = read_log(tmp_path, sink.logs[0])
    assert "ATT" in msgs and "POS" in msgs  # always logged, as ArduCopter's
    assert not {"IMU", "GPS", "RCIN", "RCOU", "BAT", "CTUN", "RATE"} & set(msgs)


def test_recording_changes_no_trajectory():
    a, b = ready_vehicle(), ready_vehicle()
    rec = Recorder(b, MemorySink())
    b.text_listener = rec.text
    for v in (a, b):
        v.set_mode(Guided.number)
        v.arm()
        v.takeoff(3.0)
    for _ in range(300):
        for v in (a, b):
            v.run_until(v.time_s + TICK_S)
        rec.tick()
    assert a.true_body == b.true_body


def test_a_format_must_agree_with_its_columns():
    with pytest.raises(ValueError):
        LogFormat(250, "BAD", "QB", "TimeUS", "s-", "F-")


# ----- the files ------------------------------------------------------------------------------
def files(tmp_path, **params) -> LogFiles:
    store = ParamStore()
    for name, value in params.items():
        store.set(name, value)
    return LogFiles(tmp_path / "logs", store)


def test_logs_are_numbered_with_lastlog(tmp_path):
    f = files(tmp_path)
    for payload in (b"one", b"two"):
        f.start()
        f.write(payload)
        f.stop()
    assert sorted(p.name for p in (tmp_path / "logs").iterdir()) == ["00000001.BIN", "00000002.BIN", "LASTLOG.TXT"]
    assert (tmp_path / "logs" / "LASTLOG.TXT").read_bytes() == b"2\r\n"
    assert f.count() == 2 and f.info(1)[0] == 3 and f.read(2, 0, 90) == b"two"
    f.start()  # an empty log is re-used
    f.stop()
    f.start()
    f.write(b"x")
    f.stop()
    assert f.last_log() == 3


def test_numbering_wraps_at_log_max_files(tmp_path):
    f = files(tmp_path, LOG_MAX_FILES=3)
    for i in range(5):
        f.start()
        f.write(bytes([i]) * (i + 1))
        f.stop()
    assert f.numbers() == [1, 2, 3] and f.last_log() == 2
    assert f.count() == 3
    # the oldest (3, written third) is entry 1; the newest (2) the last
    assert [f.number_of(k) for k in (1, 2, 3)] == [3, 1, 2]
    assert f.read(3, 0, 10) == bytes([4]) * 5


def test_erase_removes_logs_and_lastlog(tmp_path):
    f = files(tmp_path)
    f.start()
    f.write(b"abc")
    f.erase()
    assert list((tmp_path / "logs").iterdir()) == [] and f.count() == 0 and not f.open
    f.start()
    assert f.path(1).exists()


def test_reading_the_log_being_written_stops_it(tmp_path):
    f = files(tmp_path)
    f.start()
    f.write(b"data")
    assert f.info(1)[0] == 4  # buffered bytes count
    assert f.read(1, 1, 2) == b"at" and not f.open and f.paused
    f.end_transfer()
    assert not f.paused


def test_unwritable_directory_counts_an_error(tmp_path):
    (tmp_path / "logs").write_text("a file where the directory should be")
    f = files(tmp_path)
    f.start()
    f.write(b"x" * 70_000)
    f.stop()
    assert f.write_errors >= 1 and math.isfinite(f.count())


def test_an_arm_and_disarm_between_two_ticks_are_both_logged(tmp_path):
    v = ready_vehicle()
    sink = MemorySink()
    rec = Recorder(v, sink)
    run(v, rec, 0.5)
    assert v.arm() == Result.ACCEPTED and v.disarm() == Result.ACCEPTED  # both within one exchange
    run(v, rec, 0.5)
    assert [e.Id for e in read_log(tmp_path, sink.logs[0])["EV"]] == [10, 11]


def test_a_refused_arming_logs_for_15_s(tmp_path):
    v = ready_vehicle()
    sink = MemorySink()
    rec = Recorder(v, sink)
    v.text_listener = rec.text
    v.set_mode(Land.number)  # not armable
    assert v.arm() != Result.ACCEPTED
    run(v, rec, ARM_PERSIST_S - 0.5)
    size = len(sink.logs[0])
    run(v, rec, 1.0)
    assert len(sink.logs[0]) > size  # records up to the 15th second, then none
    msgs = read_log(tmp_path, sink.logs[0])
    assert msgs["MSG"][0].Message.startswith("Arm: ")
    end = msgs["ATT"][-1].TimeUS / 1e6
    run(v, rec, 1.0)
    assert read_log(tmp_path, sink.logs[0])["ATT"][-1].TimeUS / 1e6 == end


def test_mission_and_refused_modes_are_logged(tmp_path):
    from firefly.autopilot.mission import MISSION, MissionItem
    v = ready_vehicle()
    v.params.set("LOG_DISARMED", 1)
    sink = MemorySink()
    rec = Recorder(v, sink)
    v.text_listener = rec.text
    run(v, rec, 0.5)
    items = [MissionItem(16, 0, x=-353632610, y=1491652300), MissionItem(22, 3, z=10.0),
             MissionItem(16, 3, p1=2.0, x=-353630000, y=1491655000, z=20.0)]
    v.mission.replace(MISSION, items)
    assert v.arm() == Result.ACCEPTED
    run(v, rec, 0.5)
    refused = v.set_mode(3)  # AUTO, armed on the ground
    run(v, rec, 0.5)
    msgs = read_log(tmp_path, sink.logs[0])
    cmds = [(c.CTot, c.CNum, c.CId, c.Prm1, c.Lat, c.Lng, c.Alt) for c in msgs["CMD"]]
    assert cmds == [(3, 0, 16, 0.0, -35.363261, 149.16523, 0.0), (3, 1, 22, 0.0, 0.0, 0.0, 10.0),
                    (3, 2, 16, 2.0, -35.363, 149.1655, 20.0)]
    texts = [m.Message for m in msgs["MSG"]]
    assert refused != Result.ACCEPTED and "Mode change to AUTO failed" in " ".join(texts), texts
    assert [(e.Subsys, e.ECode) for e in msgs["ERR"]] == [(10, 3)]
