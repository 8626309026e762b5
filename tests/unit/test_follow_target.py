"""FOLLOW's lead estimate (autopilot/follow_target.py) on its own: whom it hears, how it
projects and shapes the lead, when it gives the lead up, the offsets; and the jitter correction
that dates the lead's reports."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.follow_target import FollowTarget, max_velocity_change
from firefly.autopilot.jitter_correction import JitterCorrection
from firefly.autopilot.modes.tilted_heading import tilted_heading
from firefly.autopilot.params import ParamStore

OWN, LEAD, OTHER = 1, 2, 3
HERE = (0.0, 0.0, -10.0)


def estimate(**params) -> tuple[FollowTarget, list[str]]:
    store = ParamStore()
    store.set("FOLL_ENABLE", 1)
    for name, value in params.items():
        store.set(name, value)
    texts: list[str] = []
    return FollowTarget(store, lambda text, severity=6: texts.append(text)), texts


def report(t: FollowTarget, now: float, pos=(10.0, 0.0, -10.0), vel=(0.0, 3.0, 0.0), sysid=LEAD,
           heading: float | None = 90.0, sent: float | None = None, follow_target=False) -> bool:
    """What the MAVLink layer does with a report: admitted, then heard."""
    if not t.listens_to(sysid, OWN, now):
        return False
    return t.hear(sysid, now, now if sent is None else sent, pos, vel, (0.0, 0.0, 0.0), heading, None,
                  follow_target)


def test_hears_only_when_enabled_and_never_itself():
    t, _ = estimate()
    t.params.set("FOLL_ENABLE", 0)
    assert not report(t, 1.0)
    t.params.set("FOLL_ENABLE", 1)
    assert not report(t, 1.0, sysid=OWN)
    assert report(t, 1.0)


def test_sysid_zero_takes_the_first_sender_and_forgets_it_after_ten_silent_seconds():
    t, _ = estimate(FOLL_SYSID=0)
    assert report(t, 1.0, sysid=OTHER)
    assert t.sysid() == OTHER
    assert not report(t, 2.0, sysid=LEAD)  # taken: the others are not heard
    assert not report(t, 10.5, sysid=LEAD)  # OTHER silent for 9.5 s: still the one followed
    assert report(t, 11.5, sysid=LEAD)  # the first report after 10 s of OTHER's silence
    assert t.sysid() == LEAD


def test_a_set_sysid_hears_that_system_only():
    t, _ = estimate(FOLL_SYSID=LEAD)
    assert not report(t, 1.0, sysid=OTHER)
    assert report(t, 1.0, sysid=LEAD)


def test_the_estimate_flies_on_along_the_last_velocity_for_three_seconds_then_the_lead_is_lost():
    t, _ = estimate()
    report(t, 1.0)
    assert t.update(1.0, HERE)
    for step in range(1, 291):
        assert t.update(1.0 + step * 0.01, HERE)
    n, e, d = t.pos
    assert (n, d) == pytest.approx((10.0, -10.0)) and e == pytest.approx(3.0 * 2.9, abs=0.01)
    assert not t.update(4.01, HERE)  # silent for more than 3 s


def test_the_estimate_is_shaped_toward_a_lead_that_turns():
    """A lead that turns from east to north at 3 m/s: the estimate's velocity turns within
    FOLL_ACCEL_NE (2.5 m/s/s), not at once."""
    t, _ = estimate()
    report(t, 0.0)
    for step in range(11):
        t.update(step * 0.01, HERE)
    report(t, 0.1, pos=(10.0, 0.3, -10.0), vel=(3.0, 0.0, 0.0))
    previous = t.vel
    for step in range(1, 21):
        t.update(0.1 + step * 0.01, HERE)
        change = math.hypot(t.vel[0] - previous[0], t.vel[1] - previous[1]) / 0.01
        assert change <= 2.5 + 1e-6
        previous = t.vel
    assert 0.0 < t.vel[0] < 3.0


def test_beyond_foll_dist_max_the_lead_is_not_followed():
    t, _ = estimate(FOLL_DIST_MAX=20)
    report(t, 1.0, pos=(30.0, 0.0, -10.0))
    assert not t.update(1.0, HERE)
    t.params.set("FOLL_DIST_MAX", 0)  # no limit
    assert t.update(1.01, HERE)


def test_without_its_own_position_the_vehicle_follows_nothing():
    t, _ = estimate()
    report(t, 1.0)
    assert not t.update(1.0, None)


def test_offsets_ned_and_turned_with_the_lead_heading():
    t, _ = estimate(FOLL_OFS_X=-5, FOLL_OFS_Z=-2)
    report(t, 1.0, vel=(0.0, 0.0, 0.0))
    t.update(1.0, HERE)
    assert t.ofs_pos == pytest.approx((5.0, 0.0, -12.0))
    t.params.set("FOLL_OFS_TYPE", 1)  # 5 m behind a lead heading east: 5 m west of it
    t.update(1.01, HERE)
    assert t.ofs_pos == pytest.approx((10.0, -5.0, -12.0), abs=1e-6)


def test_relative_offsets_need_the_lead_heading():
    t, _ = estimate(FOLL_OFS_TYPE=1, FOLL_OFS_X=-5)
    assert not report(t, 1.0, heading=None)
    assert report(t, 1.0, heading=0.0)


def test_after_follow_target_the_global_position_is_ignored():
    t, _ = estimate()
    assert report(t, 1.0, follow_target=True)
    assert not report(t, 1.1)
    assert report(t, 1.2, follow_target=True)


def test_a_report_the_lead_could_not_have_flown_to_restarts_the_estimate():
    limit = 2.5 * 1.5 ** 2  # FOLL_ACCEL_NE * (3 s / 2)^2
    t, _ = estimate()
    report(t, 1.0)
    t.update(1.0, HERE)
    report(t, 1.1, pos=(10.0, 0.3 + limit - 0.5, -10.0))
    assert t.valid
    report(t, 1.2, pos=(10.0, 0.6 + limit + 0.5, -10.0))
    assert not t.valid
    assert t.update(1.2, HERE) and t.pos[1] == pytest.approx(0.6 + limit + 0.5)
    assert max_velocity_change(2.5, 5.0, 3.0) == pytest.approx(6.25)


def test_follow_loads_the_offset_it_finds_when_none_is_set_and_forgets_it():
    t, texts = estimate()
    report(t, 1.0, vel=(0.0, 0.0, 0.0))
    t.load_offset_if_needed(HERE)
    assert texts == []  # no estimate yet
    t.update(1.0, HERE)
    t.load_offset_if_needed(HERE)
    t.load_offset_if_needed(HERE)
    assert texts == ["N-E-D follow offset loaded"]
    t.update(1.01, HERE)
    assert t.ofs_pos == pytest.approx(HERE)
    t.forget_loaded_offset()
    t.update(1.02, HERE)
    assert t.ofs_pos == pytest.approx((10.0, 0.0, -10.0))


def test_relative_offset_loaded_in_the_lead_frame():
    t, texts = estimate(FOLL_OFS_TYPE=1)
    report(t, 1.0, vel=(0.0, 0.0, 0.0), heading=90.0)
    t.update(1.0, HERE)
    t.load_offset_if_needed(HERE)
    assert texts == ["Relative follow offset loaded"]
    assert t.loaded_offset == pytest.approx((0.0, 10.0, 0.0), abs=1e-6)  # 10 m to its right
    t.update(1.01, HERE)
    assert t.ofs_pos == pytest.approx(HERE, abs=1e-6)


def test_jitter_dates_a_late_burst_by_its_senders_stamps():
    j = JitterCorrection()
    assert j.local_time(10.0, 10.05) == pytest.approx(10.05)  # first: the lag seen
    assert j.local_time(10.1, 10.12) == pytest.approx(10.12)  # less lag: taken as the link's
    # Three reports held up and arriving together are dated when they were sent
    assert [j.local_time(s, 10.6) for s in (10.2, 10.3, 10.4)] == pytest.approx([10.22, 10.32, 10.42])
    assert j.local_time(5.0, 11.0) == pytest.approx(10.5)  # never older than the half second it allows


def test_a_kept_heading_drifts_toward_the_tilt_axis_as_arducopter_rebuilds_it():
    east_lean = (0.3, 0.0, 0.0)  # rolled right, heading north: the thrust leans east, about the north axis
    assert tilted_heading((0.0, 0.0, 0.0), 0.7, 0.01) == 0.7  # level: nothing moves
    assert tilted_heading(east_lean, 0.0, 0.01) == pytest.approx(0.0)  # on the axis: it stays
    moved = tilted_heading(east_lean, math.radians(45), 0.01)
    assert 0.0 < moved < math.radians(45)
    # one rebuilding shrinks tan(heading - axis) by cos(tilt); the target takes ATC_INPUT_TC to follow
    step = math.atan(math.cos(0.3)) - math.radians(45)
    assert moved - math.radians(45) == pytest.approx(step * 0.01 / 0.15)


def test_the_lead_is_heard_even_where_mav_options_hears_only_the_ground_station():
    """ArduPilot hands every packet to AP_Follow before its GCS sysid enforcement (GCS_Common's
    packetReceived): a lead that is not the ground station is followed all the same."""
    from firefly.autopilot.mavlink.dialect import new_codec
    from firefly.autopilot.mavlink.session import Session
    from firefly.autopilot.vehicle import Vehicle, VehicleConfig
    v = Vehicle(VehicleConfig())
    session = Session(v, new_codec(1))
    v.params.set("FOLL_ENABLE", 1)
    v.params.set("MAV_OPTIONS", 1)
    v.run_until(5.0)
    lead = new_codec(7, 1)
    o = v.origin
    msg = lead.global_position_int_encode(4000, int(o.lat_deg * 1e7), int(o.lon_deg * 1e7) + 500,
                                          int(o.alt_m * 1000) + 10000, 10000, 0, 0, 0, 0)
    session.receive(new_codec(0, 0).parse_buffer(msg.pack(lead))[0], v.time_s, 1.0)
    assert v.follow_target.heard_s is not None
    ping = lead.command_long_encode(1, 1, 512, 0, 1, 0, 0, 0, 0, 0, 0)  # REQUEST_MESSAGE: not from the GCS
    assert session.receive(new_codec(0, 0).parse_buffer(ping.pack(lead))[0], v.time_s, 1.0) == []
