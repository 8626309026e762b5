"""Precision landing's retry on the real process, driven by pymavlink: SITL's beacon (PLND_TYPE 4,
SIM_PLD_*) under home, LAND, the beacon switched off (PARAM_SET SIM_PLD_ENABLE 0) at 5 m, and what
a ground station sees as ArduCopter shows it (measured, parity area precland): "PrecLand: Target
Lost", "PrecLand: Retrying", a climb back over 5 m, "PrecLand: Retry Completed", "PrecLand:
Failsafe Measures", and a landing where it lost the beacon."""
from __future__ import annotations

import math

import pytest
from pymavlink import mavutil

from .pymav import Gcs, set_param, take_off

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
LAND = 9
M_PER_DEG = 111319.5
BOOT = tuple(arg for name, value in (("PLND_ENABLED", 1), ("PLND_TYPE", 4), ("RNGFND1_TYPE", 100), ("RNGFND1_MAX", 30))
             for arg in ("--param", f"{name}={value}"))  # read at boot: the sensors are made then


def text(gcs: Gcs, words: str, timeout: float = 20.0) -> None:
    said = gcs.recv("STATUSTEXT", timeout, lambda m: words in m.text)
    assert said is not None, f"no STATUSTEXT {words!r}"


def test_a_beacon_lost_in_land_is_retried_then_landed_on_where_it_was_lost(autopilot_factory):
    gcs = Gcs(autopilot_factory(speedup="10", extra=BOOT).pymavlink_url)
    try:
        for stream in (mav.MAV_DATA_STREAM_EXTENDED_STATUS, mav.MAV_DATA_STREAM_POSITION):  # few: no text lost
            gcs.mav.request_data_stream_send(1, 1, stream, 10, 1)
        home = gcs.recv("GLOBAL_POSITION_INT", 10)
        for name, value in (("SIM_PLD_LAT", home.lat * 1e-7), ("SIM_PLD_LON", home.lon * 1e-7), ("SIM_PLD_ENABLE", 1)):
            set_param(gcs, name, value)  # the beacon where the vehicle stands (within a metre: float32s)
        take_off(gcs, 10.0)
        vision = mav.MAV_SYS_STATUS_SENSOR_VISION_POSITION
        assert gcs.recv("SYS_STATUS", 10, lambda m: m.onboard_control_sensors_health & vision) is not None
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, LAND) == mav.MAV_RESULT_ACCEPTED
        assert gcs.recv("GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt < 5000) is not None
        set_param(gcs, "SIM_PLD_ENABLE", 0)
        text(gcs, "PrecLand: Target Lost")
        text(gcs, "PrecLand: Retrying")
        assert gcs.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > 5500) is not None  # climbed back
        text(gcs, "PrecLand: Retry Completed")
        text(gcs, "PrecLand: Failsafe Measures", 5.0)
        held = gcs.recv("GLOBAL_POSITION_INT", 5, lambda m: abs(m.vz) < 10)
        assert held is not None and held.relative_alt > 4000  # the failsafe's hold, 7 s
        later = gcs.recv("GLOBAL_POSITION_INT", 5, lambda m: m.time_boot_ms > held.time_boot_ms + 4000)
        assert later is not None and abs(later.relative_alt - held.relative_alt) < 300
        landed = gcs.recv("HEARTBEAT", 60, lambda m: not m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)
        assert landed is not None
        where = gcs.recv("GLOBAL_POSITION_INT", 5)
        north = (where.lat - home.lat) * 1e-7 * M_PER_DEG
        east = (where.lon - home.lon) * 1e-7 * M_PER_DEG * math.cos(math.radians(home.lat * 1e-7))
        assert math.hypot(north, east) < 1.5  # on the beacon (placed through float32s: within a metre)
    finally:
        gcs.close()
