"""FOLLOW against the real autopilot process over real sockets: a lead played by a pymavlink
script (system 2, GLOBAL_POSITION_INT at 10 Hz of vehicle time), and, with `--count 2`, vehicle 1
following vehicle 2 of the same process with no client in between."""
from __future__ import annotations

import math

import pytest
from pymavlink import mavutil

from firefly.autopilot.testing.run import free_port_bases

from .pymav import Gcs, set_param, take_off

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
FOLLOW, GUIDED = 23, 4
M_PER_DEG = 1.0e7 * 0.011131884502145034  # ArduPilot's LOCATION_SCALING_FACTOR, per degree


def ne_from(lat: int, lon: int, to_lat: int, to_lon: int) -> tuple[float, float]:
    """(north, east) metres from one position (degrees e7) to another."""
    return ((to_lat - lat) / 1e7 * M_PER_DEG, (to_lon - lon) / 1e7 * M_PER_DEG * math.cos(math.radians(lat / 1e7)))


def ne_between(a, b) -> tuple[float, float]:
    """(north, east) metres from GLOBAL_POSITION_INT a to b."""
    return ne_from(a.lat, a.lon, b.lat, b.lon)


def test_a_pymavlink_lead_is_followed_and_lost(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    lead = mav.MAVLink(gcs.conn, srcSystem=2, srcComponent=1)  # the lead speaks on the same link
    try:
        for name, value in (("FOLL_ENABLE", 1), ("FOLL_SYSID", 2), ("FOLL_OFS_X", -6)):
            set_param(gcs, name, value)
        take_off(gcs)
        start = gcs.recv("GLOBAL_POSITION_INT", 5)
        t0 = start.time_boot_ms

        def lead_at(t_ms: int):
            """10 m north of the start, moving east at 3 m/s."""
            east = 3.0 * (t_ms - t0) / 1000.0
            return (start.lat + round(10.0 / M_PER_DEG * 1e7),
                    start.lon + round(east / (M_PER_DEG * math.cos(math.radians(start.lat / 1e7))) * 1e7))

        def speak_until(t_end_ms: int, speaking: bool = True):
            """Send the lead's report every 100 ms of vehicle time (read from the vehicle's own
            messages) until t_end_ms; returns the vehicle's last GLOBAL_POSITION_INT."""
            sent = last = None
            while last is None or last.time_boot_ms < t_end_ms:
                msg = gcs.recv(["GLOBAL_POSITION_INT", "ATTITUDE"], 5, lambda m: m.get_srcSystem() == 1)
                assert msg is not None, "the vehicle went silent"
                now = msg.time_boot_ms
                if speaking and (sent is None or now - sent >= 100):
                    lat, lon = lead_at(now)
                    lead.global_position_int_send(now, lat, lon, start.alt, start.relative_alt, 0, 300, 0, 9000)
                    sent = now
                if msg.get_type() == "GLOBAL_POSITION_INT":
                    last = msg
            return last

        speak_until(t0 + 1000)
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, FOLLOW) == mav.MAV_RESULT_ACCEPTED
        followed = speak_until(t0 + 16_000)
        north, east = ne_from(followed.lat, followed.lon, *lead_at(followed.time_boot_ms))
        assert math.hypot(north - 6.0, east) < 1.0  # 6 m south of the lead
        assert math.hypot(followed.vx, followed.vy) / 100.0 == pytest.approx(3.0, abs=0.5)
        # Silent: on along the lead's velocity for 3 s, then a stop, still in FOLLOW
        stopped = speak_until(followed.time_boot_ms + 8000, speaking=False)
        moved = math.hypot(*ne_between(followed, stopped))
        assert 9.0 < moved < 14.0 and math.hypot(stopped.vx, stopped.vy) < 30
        hb = gcs.recv("HEARTBEAT", 5, lambda m: m.get_srcSystem() == 1)
        assert hb.custom_mode == FOLLOW
    finally:
        gcs.close()


def test_vehicle_one_follows_vehicle_two_of_the_same_process(autopilot_factory):
    (base,) = free_port_bases(1, 2)
    autopilot_factory(extra=("--count", "2"), port=base)
    one, two = Gcs(f"udpin:127.0.0.1:{base}"), Gcs(f"udpin:127.0.0.1:{base + 10}")
    try:
        set_param(one, "FOLL_ENABLE", 1)
        set_param(one, "FOLL_SYSID", 2)
        take_off(one)
        take_off(two)
        assert one.command(mav.MAV_CMD_DO_SET_MODE, 1, FOLLOW) == mav.MAV_RESULT_ACCEPTED
        text = one.recv("STATUSTEXT", 5, lambda m: "offset" in m.text)
        assert text is not None and text.text == "N-E-D follow offset loaded"
        start = two.recv("GLOBAL_POSITION_INT", 5)
        before = ne_between(start, one.recv("GLOBAL_POSITION_INT", 5, lambda m: m.time_boot_ms >= start.time_boot_ms))
        # Vehicle 2 flies 30 m north (its own local frame); vehicle 1 keeps where it was from it
        two.mav.set_position_target_local_ned_send(0, 2, 1, mav.MAV_FRAME_LOCAL_NED, 0b110111111000,
                                                   30.0, 0.0, -10.0, 0, 0, 0, 0, 0, 0, 0, 0)
        arrived = two.recv("GLOBAL_POSITION_INT", 60, lambda m: ne_between(start, m)[0] > 29.0
                           and math.hypot(m.vx, m.vy) < 20)
        assert arrived is not None, "vehicle 2 did not get there"
        lead = two.recv("GLOBAL_POSITION_INT", 5)  # still from here on

        def kept_its_place(m) -> bool:
            north, east = ne_between(lead, m)
            return math.hypot(north - before[0], east - before[1]) < 1.0 and math.hypot(m.vx, m.vy) < 30
        # it overshoots a lead that stops within the same acceleration limits, then comes back
        assert one.recv("GLOBAL_POSITION_INT", 30, kept_its_place) is not None, "vehicle 1 did not keep its place"
        hb = one.recv("HEARTBEAT", 5, lambda m: m.get_srcSystem() == 1)
        assert hb.custom_mode == FOLLOW
    finally:
        one.close()
        two.close()
