"""The navigating modes (CIRCLE, SMART_RTL, ZIGZAG, AVOID_ADSB, AUTO_RTL) and SMART_RTL's path, flown
through the real vehicle in sim time; the path's cleanup on its own."""
from __future__ import annotations

import math

from firefly.autopilot.mission.store import MISSION, MissionItem
from firefly.autopilot.modes import ModeNumber as M
from firefly.autopilot.modes.circle import Circle
from firefly.autopilot.modes.return_path import ReturnPath
from firefly.autopilot.modes.smart_rtl import SmartRtl
from firefly.autopilot.modes.zigzag import HIGH, LOW, ZigZag
from firefly.autopilot.mavlink.statustext import StatusTexts
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, hovering_vehicle, throttle_at_mid, ready_vehicle


def texts(v) -> list[str]:
    return [t for _, t in v.drain_events()]


def horizontal(v) -> tuple[float, float]:
    return v.body.n_m, v.body.e_m


def goto(v, n: float, e: float, alt: float) -> None:
    v.guided_goto(n, e, v.home_ned[2] - alt)
    assert fly_until(v, lambda x: math.dist((*horizontal(x), altitude(x)), (n, e, alt)) < 0.5, 30)


# ----- the path ------------------------------------------------------------------------------------
def path(points_max: int = 300, accuracy: float = 2.0) -> tuple[ReturnPath, list]:
    params = ParamStore()
    params.set("SRTL_POINTS", points_max)
    params.set("SRTL_ACCURACY", accuracy)
    said: list = []
    p = ReturnPath(params, lambda text, severity: said.append(text))
    p.set_home(True, (0.0, 0.0, 0.0), 0.0)
    return p, said


def test_path_keeps_points_accuracy_apart_and_simplifies_a_straight_line():
    p, _ = path()
    for i in range(1, 121):  # 60 m north in half-metre steps: a point every 2 m
        p.update(True, True, (i * 0.5, 0.0, 0.0), i * 0.1)
    assert all(math.dist(a, b) >= 2.0 for a, b in zip(p.points, p.points[1:]))
    p.thorough_cleanup()
    assert p.points == [(0.0, 0.0, 0.0), (60.0, 0.0, 0.0)]


def test_path_cuts_a_loop_at_the_crossing():
    p, _ = path()
    route = [(0, 0, 0), (20, 0, 0), (40, 0, 0), (40, 20, 0), (20, 20, 0), (20, -10, 0), (30, -10, 0)]
    for k, (a, b) in enumerate(zip(route, route[1:])):
        for i in range(1, 11):
            p.update(True, True, tuple(x + (y - x) * i / 10 for x, y in zip(a, b)), k + i * 0.01)
    p.thorough_cleanup()
    assert not any(math.dist(q, (40.0, 0.0, 0.0)) < 3 for q in p.points), "the loop out to (40, 0) is gone"
    assert any(math.dist(q, (20.0, 0.0, 0.0)) < 1.5 for q in p.points), "cut at the crossing"


def test_path_given_up_when_full_for_15_s():
    p, said = path(points_max=5)
    for i in range(1, 200):  # a zig-zag nothing simplifies or prunes: the path fills up
        p.update(True, True, (i * 3.0, 3.0 * (i % 2), 0.0), i * 1.0)
    assert not p.active and "SmartRTL deactivated: buffer full" in said


def test_path_given_up_without_a_position_for_15_s():
    p, said = path()
    p.update(False, True, (0.0, 0.0, 0.0), 10.0)
    assert p.active
    p.update(False, True, (0.0, 0.0, 0.0), 15.5)
    assert not p.active and said == ["SmartRTL deactivated: bad position"]


# ----- SMART_RTL --------------------------------------------------------------------------------------
def test_smart_rtl_retraces_the_way_out_and_lands_at_home():
    v = hovering_vehicle(10.0)
    goto(v, 30.0, 0.0, 10.0)
    goto(v, 30.0, 20.0, 15.0)
    assert v.set_mode(M.SMART_RTL) == Result.ACCEPTED
    track = []
    assert fly_until(v, lambda x: (track.append((*horizontal(x), altitude(x))) or not x.armed), 90, 0.5)
    assert min(math.dist(t, (30.0, 0.0, 10.0)) for t in track) < 2.0, "back through the first corner"
    assert math.hypot(*horizontal(v)) < 0.5 and altitude(v) < 0.3


def test_smart_rtl_refused_without_a_path():
    v = ready_vehicle()
    v.params.set("SRTL_POINTS", 0)
    v.return_path = ReturnPath(v.params, v.notify)  # SRTL_POINTS is read at boot
    v.ctx.return_path = v.return_path
    assert v.set_mode(M.SMART_RTL) == Result.FAILED
    assert "Mode change to SMARTRTL failed: init failed" in texts(v)


def test_smart_rtl_failsafe_falls_back_to_rtl_without_a_path():
    v = hovering_vehicle(10.0)
    v.return_path.active = False  # given up during the flight
    v.params.set("FS_GCS_ENABLE", 3)  # SmartRTL or RTL
    v.failsafes.gcs_lost(v)
    assert v.mode_number == M.RTL
    assert "SmartRTL Unavailable, Trying RTL Mode" in texts(v)


def test_smart_rtl_armed_on_the_ground_climbs_and_arming_is_then_refused():
    v = ready_vehicle()
    v.set_mode(M.GUIDED)
    v.arm()
    assert v.set_mode(M.SMART_RTL) == Result.ACCEPTED
    assert fly_until(v, lambda x: altitude(x) > 1.0, 5)
    assert "Internal Errors 0x100000" in texts(v)
    assert fly_until(v, lambda x: not x.armed, 30)
    v.set_mode(M.GUIDED)
    assert v.arm() == Result.FAILED
    assert "Arm: Internal errors 0x100000 l:66 flow_of_ctrl" in texts(v)


# ----- CIRCLE -------------------------------------------------------------------------------------
def test_circle_orbits_a_centre_ahead_at_its_radius_nose_in():
    v = throttle_at_mid(hovering_vehicle(10.0))
    n0, e0 = horizontal(v)
    yaw0 = v.attitude[2]
    assert v.set_mode(M.CIRCLE) == Result.ACCEPTED
    mode = v.mode
    assert isinstance(mode, Circle)
    assert math.dist(mode.centre, (n0 + 10 * math.cos(yaw0), e0 + 10 * math.sin(yaw0))) < 0.5
    v.run_until(v.time_s + 5.0)
    distances, nose_off = [], []
    for _ in range(40):
        v.run_until(v.time_s + 0.25)
        n, e = horizontal(v)
        distances.append(math.dist((n, e), mode.centre))
        to_centre = math.atan2(mode.centre[1] - e, mode.centre[0] - n)
        nose_off.append(abs((v.attitude[2] - to_centre + math.pi) % (2 * math.pi) - math.pi))
    assert 9.0 < min(distances) and max(distances) < 10.5
    assert max(nose_off) < math.radians(8)
    assert abs(math.degrees(mode.angular_vel) - 20.0) < 0.5
    assert abs(altitude(v) - 10.0) < 0.3


def test_circle_pilot_sticks_shrink_the_radius_and_slow_the_rate():
    v = hovering_vehicle(10.0)
    v.set_mode(M.CIRCLE)
    mode = v.mode
    assert isinstance(mode, Circle)
    v.run_until(v.time_s + 3.0)
    end = v.time_s + 1.0
    while v.time_s < end:  # pitch forward (radius in at WPNAV_SPEED), roll left (rate down 1 deg/s/s)
        v.rc.hold_sticks(-1.0, 1.0, 0.0, 0.5, v.time_s)
        v.run_until(v.time_s + 0.1)
    assert 0.0 <= mode.radius_m < 1.0
    assert 18.0 < mode.rate_deg_s < 19.5


def test_circle_on_the_ground_stays_put():
    v = ready_vehicle()
    v.set_mode(M.GUIDED)
    v.arm()
    assert v.set_mode(M.CIRCLE) == Result.ACCEPTED
    v.run_until(v.time_s + 3.0)
    assert v.armed and altitude(v) < 0.1 and math.hypot(*horizontal(v)) < 0.1


# ----- ZIGZAG ---------------------------------------------------------------------------------------
def sticks(v, roll: float, pitch: float, seconds: float) -> None:
    """The pilot's sticks held for `seconds` (input refreshed as a radio would), then centred
    until the vehicle has stopped at the point LOITER holds."""
    end = v.time_s + seconds
    while v.time_s < end:
        v.rc.hold_sticks(roll, pitch, 0.0, 0.5, v.time_s)
        v.run_until(v.time_s + 0.25)
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    assert fly_until(v, lambda x: math.dist(horizontal(x), x.mode._hold_ne) < 0.1
                     and math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.05, 30)  # braked and back


def test_zigzag_stores_a_and_b_then_flies_to_the_line_through_a():
    v = throttle_at_mid(hovering_vehicle(10.0))
    assert v.set_mode(M.ZIGZAG) == Result.ACCEPTED
    zz = v.mode
    assert isinstance(zz, ZigZag)
    texts(v)
    zz.switch_save_wp(LOW)
    sticks(v, 1.0, 0.0, 5.0)  # right (east, the nose is north): B
    zz.switch_save_wp(HIGH)
    assert texts(v) == ["ZIGZAG: point A stored", "ZIGZAG: point B stored"]
    a, b = zz.point_a, zz.point_b
    assert a is not None and b is not None and math.dist(a, b) > 10
    sticks(v, 0.0, 1.0, 1.0)  # forward, off the AB line
    zz.switch_save_wp(LOW)  # both stored: to the line through A square to AB, at the nearest point
    assert texts(v) == ["ZIGZAG: moving to A"]
    assert fly_until(v, lambda x: zz.stage != "AUTO", 30)
    n, e = horizontal(v)
    assert abs(e - a[1]) < 1.0, "on the line through A"
    assert texts(v) == ["ZIGZAG: manual control"]
    v.run_until(v.time_s + 2.0)
    assert math.dist(horizontal(v), (n, e)) < 0.5, "and holds there as LOITER"


def test_zigzag_auto_steps_aside_by_its_side_distance():
    v = throttle_at_mid(hovering_vehicle(10.0))
    v.params.set("ZIGZ_AUTO_ENABLE", 1)
    v.set_mode(M.ZIGZAG)
    zz = v.mode
    assert isinstance(zz, ZigZag)
    zz.switch_save_wp(LOW)
    sticks(v, 1.0, 0.0, 5.0)  # B to the east
    zz.switch_save_wp(HIGH)
    texts(v)
    start = horizontal(v)
    zz.switch_auto(HIGH)  # ZIGZ_LINE_NUM 0: one step aside (ZIGZ_DIRECTION 0: forward), then the pilot's
    assert texts(v) == ["ZIGZAG: moving to forward"]
    assert fly_until(v, lambda x: zz.stage != "AUTO", 30)
    n, e = horizontal(v)
    assert abs(n - start[0] - 4.0) < 0.5 and abs(e - start[1]) < 0.5  # ZIGZ_SIDE_DIST 4 m, north
    assert texts(v) == ["ZIGZAG: manual control"]


# ----- AVOID_ADSB and AUTO_RTL ------------------------------------------------------------------------
def test_avoid_adsb_holds_and_may_not_be_armed_in():
    v = hovering_vehicle(10.0)
    n0, e0 = horizontal(v)
    assert v.set_mode(M.AVOID_ADSB) == Result.ACCEPTED
    v.run_until(v.time_s + 5.0)
    assert math.dist(horizontal(v), (n0, e0)) < 0.3 and abs(altitude(v) - 10.0) < 0.2
    assert not v.mode.allows_arming


def item(command: int, v, n: float = 0.0, e: float = 0.0, alt: float = 0.0) -> MissionItem:
    g = v.ned_to_global(n, e, 0.0) if (n, e) != (0.0, 0.0) else None
    x, y = (round(g.lat_deg * 1e7), round(g.lon_deg * 1e7)) if g else (0, 0)
    return MissionItem(command=command, frame=3, p1=0, p2=0, p3=0, p4=0, x=x, y=y, z=alt)


def test_auto_rtl_refused_without_a_landing_sequence():
    v = ready_vehicle()
    assert v.auto_rtl("land_start") == Result.FAILED
    assert texts(v) == ["Unable to start landing sequence",
                        "Mode change to AUTO RTL failed: No landing sequence found"]
    assert v.auto_rtl("return_path") == Result.FAILED
    assert texts(v) == ["Mode change to AUTO RTL failed: No return path found"]


def test_auto_rtl_flies_the_landing_sequence_and_reports_27_until_the_disarm():
    v = hovering_vehicle(10.0)
    v.mission.replace(MISSION, [item(22, v, alt=10), item(16, v, 40, 0, 10), item(189, v),
                                item(16, v, 15, 30, 10), item(21, v, 15, 15)])
    assert v.set_mode(M.AUTO_RTL) == Result.ACCEPTED
    assert v.mode_number == M.AUTO_RTL and v.in_mission_mode
    assert "Landing sequence start" in texts(v)
    assert fly_until(v, lambda x: not x.armed, 60)
    assert math.dist(horizontal(v), (15.0, 15.0)) < 0.5
    v.run_until(v.time_s + 0.1)
    assert v.mode_number == M.AUTO  # the landing over: AUTO again, as ArduCopter reports it


# ----- STATUSTEXT --------------------------------------------------------------------------------------
def test_long_texts_go_in_chunks_sharing_an_id():
    texts_out = StatusTexts(new_codec(1, 1))
    assert [m.id for m in texts_out.encode(4, "short")] == [0]
    long = "Mode change to AUTO RTL failed: No return path or landing sequence found"
    chunks = texts_out.encode(4, long)
    assert [(m.id, m.chunk_seq) for m in chunks] == [(1, 0), (1, 1)]
    assert b"".join(m.text if isinstance(m.text, bytes) else m.text.encode() for m in chunks).rstrip(b"\0") \
        == long.encode()
    exactly = texts_out.encode(4, "x" * 100)
    assert [(m.id, m.chunk_seq, len(m.text)) for m in exactly][-1][:2] == (2, 2)  # an empty chunk ends it


def test_smart_rtl_mode_is_registered():
    assert SmartRtl.text_name == "SMARTRTL"
