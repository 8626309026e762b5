"""Dataflash logs of the real autopilot process: a flight's .BIN is read by pymavlink's DFReader
and by mavlogdump.py, and downloaded byte for byte by LOG_REQUEST_DATA (pymavlink, MAVSDK's
LogFiles plugin, MAVProxy's `log download`) and by MAVLink FTP; the logging parameters act."""
from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from mavsdk.asyncio.plugins.log_files import LogFilesAsync
from mavsdk.plugins.log_files import LogFilesResult
from pymavlink import DFReader
from pymavlink.mavftp import MAVFTP

from firefly.groundstation.flight.reference_flight import connect

from .conftest import wait_for
from .pymav import Gcs, mav, set_param, take_off
from .test_mavproxy import MavProxy

pytestmark = pytest.mark.sitl
LAND = 9
CHUNK = 90


def logs_dir(ap) -> Path:
    """Where instance 0's logs are: <state dir>/instance-0/logs."""
    return ap.state_dir / "instance-0" / "logs"


def fly_and_land(gcs: Gcs) -> None:
    """Take off to 5 m, land, and wait until logging has stopped (15 s of vehicle time after the
    disarm), so that the log no longer grows."""
    take_off(gcs, 5.0)
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, LAND) == mav.MAV_RESULT_ACCEPTED
    disarmed = gcs.recv("HEARTBEAT", 60, lambda m: not m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
    assert disarmed is not None, "never disarmed after landing"
    at = gcs.recv("SYSTEM_TIME", 5).time_boot_ms
    assert gcs.recv("SYSTEM_TIME", 30, lambda m: m.time_boot_ms > at + 16_000) is not None


def download(gcs: Gcs, log_id: int, size: int) -> bytes:
    """LOG_REQUEST_DATA for the whole log; the chunks as they come, re-asked from the first gap."""
    data = bytearray()
    while len(data) < size:
        gcs.mav.log_request_data_send(1, 1, log_id, len(data), 0xFFFFFFFF)
        while True:
            chunk = gcs.recv("LOG_DATA", 5)
            if chunk is None or chunk.ofs != len(data):
                break
            data += bytes(chunk.data[:chunk.count])
            if chunk.count < CHUNK or len(data) >= size:  # (a log of whole chunks ends on a full one)
                break
        if chunk is None and len(data) < size:
            raise AssertionError(f"download stalled at {len(data)} of {size}")
    gcs.mav.log_request_end_send(1, 1)
    return bytes(data)


def entries(gcs: Gcs) -> list:
    gcs.mav.log_request_list_send(1, 1, 0, 0xFFFF)
    first = gcs.recv("LOG_ENTRY", 5)
    assert first is not None
    out = [first]
    while out[-1].id < out[-1].last_log_num:
        out.append(gcs.recv("LOG_ENTRY", 5))
    return out


@pytest.fixture
def flown(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    fly_and_land(gcs)
    yield autopilot, gcs
    gcs.close()


def test_a_flight_log_downloads_byte_for_byte_and_reads(flown, tmp_path):
    ap, gcs = flown
    listed = entries(gcs)
    assert [(e.id, e.num_logs) for e in listed] == [(1, 1)] and listed[0].size > 100_000
    got = download(gcs, 1, listed[0].size)
    path = logs_dir(ap) / "00000001.BIN"
    assert got == path.read_bytes()  # the download closed the log: the file is complete
    assert (logs_dir(ap) / "LASTLOG.TXT").read_bytes() == b"1\r\n"

    log = DFReader.DFReader_binary(str(path))
    seen: dict[str, list] = {}
    while (m := log.recv_msg()) is not None:
        seen.setdefault(m.get_type(), []).append(m)
    assert {"FMT", "FMTU", "UNIT", "MULT", "PARM", "MSG", "MODE", "EV", "ATT", "RATE", "POS", "GPS", "BARO",
            "IMU", "BAT", "CTUN", "PSCN", "PSCE", "PSCD", "RCIN", "RCOU"} <= set(seen)
    assert [m.ModeNum for m in seen["MODE"]] == [4, LAND]
    events = [e.Id for e in seen["EV"]]
    assert events[0] == 10 and events[-1] == 11
    assert 4.5 < max(p.RelHomeAlt for p in seen["POS"]) < 5.5
    gcs.mav.param_request_read_send(1, 1, b"WPNAV_SPEED", -1)
    served = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == "WPNAV_SPEED")
    assert {m.Name: m.Value for m in seen["PARM"]}["WPNAV_SPEED"] == served.param_value

    dump = subprocess.run([sys.executable, "-m", "pymavlink.tools.mavlogdump", "--types", "MODE,EV", str(path)],
                          capture_output=True, text=True, timeout=60)
    assert dump.returncode == 0, dump.stderr
    lines = dump.stdout.splitlines()
    assert [line for line in lines if "MODE {" in line][-1].count("ModeNum : 9") == 1
    assert any("EV {" in line and "Id : 10" in line for line in lines)


def test_ftp_reads_the_same_bytes(flown, tmp_path):
    ap, gcs = flown
    listed = entries(gcs)
    download(gcs, 1, listed[0].size)  # closes the log, so the file stops growing
    ftp = MAVFTP(gcs.conn, 1, 1)
    target = tmp_path / "ftp.BIN"
    assert ftp.cmd_get(["logs/00000001.BIN", str(target)]).error_code == 0
    result = ftp.process_ftp_reply("OpenFileRO", timeout=60)
    assert result.error_code == 0, result.display_message()
    assert target.read_bytes() == (logs_dir(ap) / "00000001.BIN").read_bytes()


async def test_mavsdk_log_files_downloads_the_log(flown, tmp_path):
    ap, gcs = flown
    gcs.close()  # MAVSDK takes the link
    mavsdk, system = await connect(ap.mavsdk_url)
    try:
        log_files = LogFilesAsync(system)
        found = await log_files.get_entries()
        assert len(found) == 1 and found[0].size_bytes > 100_000
        target = tmp_path / "mavsdk.BIN"
        last = None
        async for result, _progress in log_files.download_log_file(found[0], str(target)):
            last = result
        assert last == LogFilesResult.SUCCESS
        assert target.read_bytes() == (logs_dir(ap) / "00000001.BIN").read_bytes()
    finally:
        mavsdk.destroy()


def test_mavproxy_log_download(flown, tmp_path):
    ap, gcs = flown
    gcs.close()
    proxy = MavProxy(ap.port, tmp_path / "mavproxy")
    try:
        proxy.wait_output(r"online system 1", 30)
        start = proxy.mark()
        proxy.send("log list")
        proxy.wait_output(r"Log 1 .*numLogs 1", 30, start)
        target = tmp_path / "proxy.BIN"
        start = proxy.mark()
        proxy.send(f"log download 1 {target}")
        proxy.wait_output(r"Finished downloading", 120, start)
        wait_for(lambda: target.exists() and target.stat().st_size > 0, 10, "the downloaded file")
        assert target.read_bytes() == (logs_dir(ap) / "00000001.BIN").read_bytes()
    finally:
        proxy.stop()


def test_backend_0_writes_nothing_and_log_disarmed_logs_at_once(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    try:
        set_param(gcs, "LOG_BACKEND_TYPE", 0)
        assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
        gcs.recv("HEARTBEAT", 5, lambda m: m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
        assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0) == mav.MAV_RESULT_ACCEPTED
        gcs.recv("SYSTEM_TIME", 5)
        assert not logs_dir(autopilot).exists()
        assert entries(gcs)[0].num_logs == 0
        set_param(gcs, "LOG_BACKEND_TYPE", 1)
        set_param(gcs, "LOG_DISARMED", 1)
        wait_for(lambda: (logs_dir(autopilot) / "00000001.BIN").exists(), 10, "a log while disarmed")
    finally:
        gcs.close()


def test_armed_requests_are_refused_and_nothing_changes(flown):
    ap, gcs = flown
    assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, 4) == mav.MAV_RESULT_ACCEPTED  # LAND is not armable
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
    before = sorted(p.name for p in logs_dir(ap).iterdir())
    gcs.mav.log_erase_send(1, 1)
    text = gcs.recv("STATUSTEXT", 5, lambda m: "log" in m.text)
    assert text is not None and text.text == "Disarm for log download"
    for hostile in (lambda: gcs.mav.log_request_data_send(1, 1, 0xFFFF, 0xFFFFFFFF, 0xFFFFFFFF),
                    lambda: gcs.mav.log_request_list_send(1, 1, 0xFFFF, 0),
                    lambda: gcs.mav.log_erase_send(1, 1)):
        hostile()
    assert gcs.recv("LOG_DATA", 1) is None
    assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0) == mav.MAV_RESULT_ACCEPTED
    assert before == sorted(p.name for p in logs_dir(ap).iterdir())[:len(before)]
    assert (logs_dir(ap) / "00000001.BIN").exists()


def test_rotation_wraps_at_log_max_files(autopilot):
    """With LOG_DISARMED and LOG_FILE_DSRMROT each disarm starts a new log; past LOG_MAX_FILES the
    numbering starts again at 1 and overwrites the oldest, and the listing follows ArduPilot's:
    the oldest log first."""
    gcs = Gcs(autopilot.pymavlink_url)
    logs = logs_dir(autopilot)
    try:
        for name, value in (("LOG_MAX_FILES", 2), ("LOG_FILE_DSRMROT", 1), ("LOG_DISARMED", 1)):
            set_param(gcs, name, value)
        wait_for(lambda: (logs / "00000001.BIN").exists(), 10, "the first log")
        for cycle in range(2):
            assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
            assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0) == mav.MAV_RESULT_ACCEPTED
            wait_for(lambda: (logs / "LASTLOG.TXT").read_bytes() == f"{(cycle + 1) % 2 + 1}\r\n".encode(),
                     10, f"log {(cycle + 1) % 2 + 1}")
        assert sorted(p.name for p in logs.iterdir()) == ["00000001.BIN", "00000002.BIN", "LASTLOG.TXT"]
        listed = entries(gcs)
        assert [(e.id, e.num_logs, e.last_log_num) for e in listed] == [(1, 2, 2), (2, 2, 2)]
        assert listed[0].size == (logs / "00000002.BIN").stat().st_size  # the oldest: log 2
    finally:
        gcs.close()


def test_attitude_and_height_are_the_vehicles(autopilot_factory, tmp_path):
    """ATT and POS against the vehicle's true state (--state-log, every 0.1 s of vehicle time):
    the records at the same vehicle time hold the same attitude and height."""
    import csv
    import math

    from firefly.sim.rigid_body import euler_from_quaternion
    states = tmp_path / "state.csv"
    ap = autopilot_factory(extra=("--state-log", str(states)))
    gcs = Gcs(ap.pymavlink_url)
    try:
        fly_and_land(gcs)
    finally:
        gcs.close()
    ap.stop()  # the log is complete once the process has exited
    # the lines every 0.1 s (the state log also has one wherever the vehicle answered a client)
    truth = {round(float(r["time_s"]) * 10): r for r in csv.DictReader(states.open())
             if abs(float(r["time_s"]) * 10 - round(float(r["time_s"]) * 10)) < 1e-6}
    log = DFReader.DFReader_binary(str(logs_dir(ap) / "00000001.BIN"))
    compared = 0
    home_d = None
    while (m := log.recv_msg()) is not None:
        if m.get_type() not in ("ATT", "POS") or m.TimeUS % 100_000:
            continue
        row = truth.get(m.TimeUS // 100_000)
        if row is None:
            continue
        if m.get_type() == "ATT":
            roll, pitch, yaw = (math.degrees(a) for a in euler_from_quaternion(
                *(float(row[k]) for k in ("qw", "qx", "qy", "qz"))))
            assert (m.Roll, m.Pitch) == (pytest.approx(roll, abs=0.01), pytest.approx(pitch, abs=0.01))
            assert math.cos(math.radians(m.Yaw - yaw)) > 0.9999
        else:
            home_d = float(row["home_d_m"])
            assert m.RelHomeAlt == pytest.approx(home_d - float(row["d_m"]), abs=0.01)
        compared += 1
    assert compared > 200 and home_d is not None
