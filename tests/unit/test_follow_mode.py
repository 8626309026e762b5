"""FOLLOW flown through the real vehicle and its MAVLink session: a lead (system 2) reports
GLOBAL_POSITION_INT or FOLLOW_TARGET at 10 Hz of vehicle time; the vehicle catches its point,
keeps it, turns per FOLL_YAW_BEHAVE, and stops and holds when the lead falls silent."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.results import Result
from firefly.sim.geo import global_from_ned

from ._session_link import Link
from ._util import altitude, hovering_vehicle, mav, ready_vehicle, wire

LEAD = 2


class Lead:
    """System 2, `start` (n, e) and `alt_m` above home at vehicle time t0, moving at (vn, ve)."""

    def __init__(self, link: Link, start: tuple[float, float], vel: tuple[float, float], alt_m: float = 10.0,
                 hdg_deg: float = 90.0):
        self.link, self.start, self.vel, self.alt_m, self.hdg = link, start, vel, alt_m, hdg_deg
        self.codec = new_codec(LEAD, 1)
        self.t0 = link.vehicle.time_s

    def at(self, t: float) -> tuple[float, float]:
        dt = t - self.t0
        return self.start[0] + self.vel[0] * dt, self.start[1] + self.vel[1] * dt

    def send(self) -> list:
        v = self.link.vehicle
        n, e = self.at(v.time_s)
        home_d = v.home_ned[2]
        p = global_from_ned(v.origin, n, e, home_d - self.alt_m)
        msg = mav.MAVLink_global_position_int_message(
            round(v.time_s * 1000), round(p.lat_deg * 1e7), round(p.lon_deg * 1e7), round(p.alt_m * 1000),
            round(self.alt_m * 1000), round(self.vel[0] * 100), round(self.vel[1] * 100), 0, round(self.hdg * 100))
        return self.link.send(wire(msg, self.codec))

    def fly(self, seconds: float, speaking: bool = True) -> None:
        v = self.link.vehicle
        end = v.time_s + seconds
        while v.time_s < end - 1e-9:
            if speaking:
                self.send()
            v.run_until(v.time_s + 0.1)


def following(**params) -> tuple[Link, Lead]:
    """Hovering at 10 m in GUIDED with FOLL_ENABLE and `params`; a lead 10 m north moving east at
    3 m/s, heard for a second before FOLLOW."""
    v = hovering_vehicle()
    v.params.set("FOLL_ENABLE", 1)
    for name, value in params.items():
        v.params.set(name, value)
    link = Link(v)
    lead = Lead(link, (v.body.n_m + 10.0, v.body.e_m), (0.0, 3.0))
    lead.fly(1.0)
    assert v.set_mode(ModeNumber.FOLLOW) == Result.ACCEPTED
    return link, lead


def distance_to(v, point: tuple[float, float]) -> float:
    return math.hypot(v.body.n_m - point[0], v.body.e_m - point[1])


def test_catches_and_keeps_the_lead_point_with_its_offset():
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6, FOLL_OFS_Z=-2)
    v = link.vehicle
    lead.fly(15.0)
    n, e = lead.at(v.time_s)
    assert distance_to(v, (n - 6.0, e)) < 0.5
    assert math.hypot(v.body.vn_m_s, v.body.ve_m_s) == pytest.approx(3.0, abs=0.3)
    assert altitude(v) == pytest.approx(12.0, abs=0.3)


def test_a_silent_lead_is_followed_three_seconds_then_the_vehicle_stops_in_follow():
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6)
    v = link.vehicle
    lead.fly(15.0)
    start = (v.body.n_m, v.body.e_m)
    lead.fly(2.0, speaking=False)
    assert distance_to(v, start) == pytest.approx(6.0, abs=0.5)  # on at the lead's 3 m/s
    lead.fly(6.0, speaking=False)
    stopped = (v.body.n_m, v.body.e_m)
    assert math.hypot(v.body.vn_m_s, v.body.ve_m_s) < 0.2
    assert 9.0 < distance_to(v, start) < 13.0  # 3 s on, then a jerk-limited stop
    lead.fly(5.0, speaking=False)
    assert distance_to(v, stopped) < 0.3 and v.mode_number == ModeNumber.FOLLOW


def test_without_offsets_it_keeps_the_distance_it_found_and_says_so():
    link, lead = following()  # FOLL_SYSID 0: the first other system heard
    v = link.vehicle
    texts = [t for _, t in v.drain_events()]
    v.run_until(v.time_s + 0.05)
    texts += [t for _, t in v.drain_events()]
    assert "N-E-D follow offset loaded" in texts
    n0, e0 = lead.at(v.time_s)
    offset = (v.body.n_m - n0, v.body.e_m - e0)
    lead.fly(10.0)
    n, e = lead.at(v.time_s)
    assert distance_to(v, (n + offset[0], e + offset[1])) < 0.5
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED
    assert v.follow_target.loaded_offset is None  # forgotten on leaving


def test_heading_same_as_the_lead_and_along_the_flight():
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6, FOLL_YAW_BEHAVE=2)
    lead.hdg = 30.0
    lead.fly(8.0)
    assert math.degrees(link.vehicle.attitude[2]) == pytest.approx(30.0, abs=2.0)
    link.vehicle.params.set("FOLL_YAW_BEHAVE", 3)
    lead.fly(8.0)
    assert math.degrees(link.vehicle.attitude[2]) == pytest.approx(90.0, abs=2.0)  # it flies east


def test_face_lead_turns_as_arducopter_does():
    """FOLL_YAW_BEHAVE 1: toward the lead's metres less the target's centimetres (measured on
    ArduCopter: about -94 degrees with the lead north-east and moving east)."""
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6)
    lead.fly(15.0)
    v = link.vehicle
    n, e = lead.at(v.time_s)
    want = math.degrees(math.atan2(e - (e * 100.0), n - (n - 6.0) * 100.0))
    assert math.degrees(v.attitude[2]) == pytest.approx(want, abs=3.0)


def test_landed_in_follow_it_stays_on_the_ground():
    v = ready_vehicle()
    v.params.set("FOLL_ENABLE", 1)
    link = Link(v)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.set_mode(ModeNumber.FOLLOW) == Result.ACCEPTED
    Lead(link, (10.0, 0.0), (0.0, 3.0)).fly(3.0)
    assert altitude(v) < 0.2


def test_follow_target_with_nan_or_beyond_any_altitude_is_ignored_and_the_vehicle_flies_on():
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6)
    v = link.vehicle
    bad = mav.MAVLink_follow_target_message(round(v.time_s * 1000), 1 | 2, 1, 1, math.nan, [math.nan] * 3,
                                            [0.0] * 3, [1.0, 0.0, 0.0, 0.0], [0.0] * 3, [0.0] * 3, 0)
    link.send(wire(bad, lead.codec))
    far = mav.MAVLink_follow_target_message(round(v.time_s * 1000), 1, 1, 1, 1e30, [0.0] * 3, [0.0] * 3,
                                            [1.0, 0.0, 0.0, 0.0], [0.0] * 3, [0.0] * 3, 0)
    link.send(wire(far, lead.codec))
    assert not v.follow_target.using_follow_target  # neither was taken
    lead.fly(3.0)
    assert link.session.counters["handler_errors"] == 0
    assert v.follow_target.valid and v.mode_number == ModeNumber.FOLLOW


def test_do_follow_names_the_lead_as_arducopter_takes_it():
    link = Link(ready_vehicle())
    assert link.command(mav.MAV_CMD_DO_FOLLOW, 7)[0].result == mav.MAV_RESULT_ACCEPTED
    assert link.vehicle.params["FOLL_SYSID"] == 7
    for refused in (0, 256, math.nan):
        assert link.command(mav.MAV_CMD_DO_FOLLOW, refused)[0].result == mav.MAV_RESULT_DENIED
    assert link.vehicle.params["FOLL_SYSID"] == 7


def test_what_it_reports_of_where_it_flies():
    """POSITION_TARGET_GLOBAL_INT: the lead's point plus offset; NAV_CONTROLLER_OUTPUT as
    ArduCopter 4.7 fills it: from the origin to that point less a hundredth of the vehicle's
    position, the bearing in centidegrees."""
    link, lead = following(FOLL_SYSID=LEAD, FOLL_OFS_X=-6)
    lead.fly(10.0)
    v = link.vehicle
    n, e, _ = v.follow_target.ofs_pos
    target = link.session.build(mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT)
    point = global_from_ned(v.origin, n, e, 0.0)
    assert (target.lat_int, target.lon_int) == (round(point.lat_deg * 1e7), round(point.lon_deg * 1e7))
    nav = link.session.build(mav.MAVLINK_MSG_ID_NAV_CONTROLLER_OUTPUT)
    dn, de = n - 0.01 * v.body.n_m, e - 0.01 * v.body.e_m
    assert nav.wp_dist == int(math.hypot(dn, de))
    assert nav.target_bearing == pytest.approx(math.degrees(math.atan2(de, dn)) * 100, abs=1)
    lead.fly(4.0, speaking=False)  # lost: nothing to report
    assert link.session.build(mav.MAVLINK_MSG_ID_POSITION_TARGET_GLOBAL_INT) is None
    assert link.session.build(mav.MAVLINK_MSG_ID_NAV_CONTROLLER_OUTPUT).wp_dist == 0


@pytest.mark.parametrize("alt_type, above_home_m", [(1, 5.0), (0, 15.0)])
def test_the_lead_height_above_home_or_above_sea_level_per_foll_alt_type(alt_type, above_home_m):
    v = ready_vehicle()
    v.params.set("FOLL_ENABLE", 1)
    v.params.set("FOLL_ALT_TYPE", alt_type)
    link = Link(v)
    home_amsl = v.origin.alt_m - v.home_ned[2]
    p = global_from_ned(v.origin, 10.0, 0.0, v.home_ned[2])
    # relative_alt says 5 m, alt says 15 m above home: which one counts is FOLL_ALT_TYPE's choice
    msg = mav.MAVLink_global_position_int_message(round(v.time_s * 1000), round(p.lat_deg * 1e7),
                                                  round(p.lon_deg * 1e7), round((home_amsl + 15.0) * 1000), 5000,
                                                  0, 0, 0, 0)
    link.send(wire(msg, new_codec(LEAD, 1)))
    assert v.home_ned[2] - v.follow_target.report_pos[2] == pytest.approx(above_home_m, abs=0.01)
