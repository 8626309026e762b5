"""ADS-B: the receiver's traffic list (adsb/traffic_list.py), avoidance's threats and COLLISION
reports (adsb/threats.py), what the copter does about a threat (adsb/escape.py), and the messages
(mavlink/adsb_messages.py). The reference's answers are in the parity area adsb; these pin the
rules between them."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.location import Loc
from firefly.autopilot.adsb.sitl_transceiver import report_of as sitl_report_of
from firefly.autopilot.adsb.threats import HIGH, LOW, NONE, Avoidance, Obstacle, closest_xy, closest_z
from firefly.autopilot.adsb.traffic_list import AdsbReport, TrafficList
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result
from firefly.autopilot.safety.arming import prearm_failure
from firefly.autopilot.vehicle import Vehicle, VehicleConfig
from firefly.sim.scenario import ScenarioError, scenario_from_dict
from firefly.sim.traffic import POINT_OBSTACLE, Aircraft, TrafficSim

from ._session_link import Link
from ._util import (GCS_COMPONENT, GCS_SYSTEM, altitude, fly_until, hovering_vehicle, mav, of_type, ready_vehicle,
                    wire)

HOME = Loc(-353632610, 1491652300, 58408)
M_PER_E7 = 0.011131884502145034


def store(**values) -> ParamStore:
    params = ParamStore()
    for name, value in values.items():
        params.set(name, value)
    return params


def report(icao: int, north_m: float = 0.0, up_m: float = 0.0, *, origin: Loc = HOME, tslc: int = 1,
           flags: int = 0x1FF, heading_cdeg: int = 0, hor_cms: int = 0, ver_cms: int = 0) -> AdsbReport:
    return AdsbReport(icao, origin.lat_e7 + round(north_m / M_PER_E7), origin.lon_e7, 0,
                      origin.alt_cm * 10 + round(up_m * 1000), heading_cdeg, hor_cms, ver_cms, b"T", 1, tslc, flags,
                      1200)


def listed(traffic: TrafficList) -> list[int]:
    return sorted(a.report.icao for a in traffic.aircraft)


# ----- the traffic list ---------------------------------------------------------------------------
def test_the_list_is_off_until_a_type_is_set_and_then_starts_without_a_reboot():
    params = store()
    traffic = TrafficList(params)
    traffic.receive(report(1, 100), 1000)
    assert traffic.aircraft == [] and not traffic.started
    params.set("ADSB_TYPE", 1)
    traffic.receive(report(1, 100), 1100)
    assert listed(traffic) == [1]


def test_refused_reports_are_not_listed_and_drop_an_aircraft_already_listed():
    traffic = TrafficList(store(ADSB_TYPE=1))
    traffic.update(0, HOME)
    refused = [report(2, 2500), report(3, tslc=6), report(0x1000000), report(5, flags=0),
               report(6, flags=4), AdsbReport(7, 0, 0, 0, 0, 0, 0, 0, b"", 0, 1, 0x1FF, 0)]
    for r in refused:
        traffic.receive(r, 10_000)
    assert traffic.aircraft == []
    for flags in (1, 2):  # the coordinates or the altitude flagged valid is enough
        traffic.receive(report(10 + flags, 100, flags=flags), 10_000)
    assert listed(traffic) == [11, 12]
    traffic.receive(report(11, 2500), 10_100)  # the same aircraft, now out of range
    assert listed(traffic) == [12]


def test_the_radius_and_altitude_band_spare_the_special_aircraft():
    traffic = TrafficList(store(ADSB_TYPE=1, ADSB_LIST_ALT=50, ADSB_ICAO_SPECL=9))
    traffic.update(0, HOME)
    traffic.receive(report(8, 3000), 1000)
    traffic.receive(report(8, 100, up_m=80), 1000)
    traffic.receive(report(9, 3000, up_m=80), 1000)
    assert listed(traffic) == [9]


def test_a_full_list_swaps_its_farthest_aircraft_for_a_nearer_one():
    traffic = TrafficList(store(ADSB_TYPE=1, ADSB_LIST_MAX=3))
    traffic.update(0, HOME)
    for icao, d in ((1, 300), (2, 900), (3, 600)):
        traffic.receive(report(icao, d), 1000)
    traffic.receive(report(4, 1000), 1000)  # farther than all: not taken
    assert listed(traffic) == [1, 2, 3]
    traffic.receive(report(5, 100), 1000)
    assert listed(traffic) == [1, 3, 5]


def test_aircraft_expire_five_seconds_after_their_last_contact():
    traffic = TrafficList(store(ADSB_TYPE=1))
    traffic.update(0, HOME)
    traffic.receive(report(1, 100, tslc=1), 10_000)  # last contact at 9 s
    traffic.receive(report(2, 100, tslc=0), 10_000)
    traffic.update(14_000, HOME)
    assert listed(traffic) == [1, 2]
    traffic.update(14_100, HOME)
    assert listed(traffic) == [2]
    traffic.update(15_100, HOME)
    assert listed(traffic) == []


def test_the_stream_sends_one_aircraft_a_message_and_a_pass_at_most_each_second():
    traffic = TrafficList(store(ADSB_TYPE=1))
    traffic.update(0, HOME)
    for icao in (1, 2, 3):
        traffic.receive(report(icao, 100), 5000)
    sent = [(t, r.icao if r else None) for t in range(5000, 7000, 100) for r in [traffic.next_to_send(t)]]
    # The first pass starts the clock at 0 (as ArduPilot's), so the second follows it at once.
    assert [icao for _, icao in sent[:7]] == [1, 2, 3, 1, 2, 3, None]
    assert [t for t, icao in sent if icao == 1] == [5000, 5300, 6300]


def test_reports_queue_for_avoidance_at_most_thirty_deep():
    traffic = TrafficList(store(ADSB_TYPE=1))
    for i in range(40):
        traffic.receive(report(1, 100), 1000 + i)
    assert len(traffic.take_samples()) == 30 and traffic.take_samples() == []


# ----- threats ------------------------------------------------------------------------------------
def obstacle(north_m: float, up_m: float = 0.0, vel=(0.0, 0.0, 0.0)) -> Obstacle:
    r = report(1, north_m, up_m)
    return Obstacle(0, 1, r.location, vel, 0)


def test_closest_approach_of_a_head_on_intruder():
    o = obstacle(1950, vel=(-50.0, 0.0, 0.0))  # 50 m/s south, towards us
    assert closest_xy(HOME, (0, 0, 0), o, 30) == pytest.approx(1950 - 1500, abs=0.5)
    assert closest_xy(HOME, (0, 0, 0), o, 40) == pytest.approx(0.0, abs=1e-6)
    away = obstacle(200, vel=(50.0, 0.0, 0.0))
    assert closest_xy(HOME, (0, 0, 0), away, 30) == pytest.approx(200, abs=0.5)


def test_closest_vertical_approach_keeps_ardupilots_units():
    # Heights in centimetres (up) against speeds in metres per second (down), as ArduPilot's: 10 m
    # above and descending reads as its height; climbing away at 1 m/s for 30 s, 30 cm more.
    assert closest_z(HOME, (0, 0, 0), obstacle(0, up_m=10, vel=(0, 0, 1.0)), 30) == pytest.approx(10.0)
    assert closest_z(HOME, (0, 0, 0), obstacle(0, up_m=10, vel=(0, 0, -1.0)), 30) == pytest.approx(10.3)


class Recorder:
    def __init__(self):
        self.acts, self.recoveries = [], []

    def act(self, threat, action):
        self.acts.append(action)
        return action

    def recover(self, recovery):
        self.recoveries.append(recovery)


def run_avoidance(params, reports_by_ms, until_ms, own=HOME):
    traffic, escape = TrafficList(params), Recorder()
    avoidance = Avoidance(params, escape)
    reports, levels, collisions = dict(reports_by_ms), [], []
    for now in range(0, until_ms, 100):
        for r in reports.pop(now, []):
            traffic.receive(r, now)
        traffic.update(now, own)
        c = avoidance.update(now, traffic.take_samples, own, (0.0, 0.0, 0.0))
        levels.append((now, avoidance.threat_level))
        if c is not None:
            collisions.append((now, c))
    return avoidance, escape, levels, collisions


def test_a_head_on_intruder_is_low_then_high_as_it_closes():
    params = store(ADSB_TYPE=1, AVD_ENABLE=1, ADSB_LIST_RADIUS=0)
    reports = {ms: [report(5, 1960 - 50 * ms / 1000, heading_cdeg=18000, hor_cms=5000)] for ms in range(0, 8000, 500)}
    _, _, levels, collisions = run_avoidance(params, reports, 8000)
    first = {level: min(t for t, lv in levels if lv >= level) for level in (LOW, HIGH)}
    # A report one second old looks 31 s ahead (1,550 m at 50 m/s): LOW once it would pass within
    # 300 m (under 1,850 m away, the report at 2.5 s), HIGH within 100 m (under 1,650 m, at 6.5 s)
    assert first[LOW] == 2500 and first[HIGH] == 6500
    assert [c.threat_level for _, c in collisions][-1] == HIGH
    assert all(b - a > 1000 for (a, _), (b, _) in zip(collisions, collisions[1:]))


def test_a_high_threat_acts_as_avd_f_action_says_and_recovers_after_it_goes():
    params = store(ADSB_TYPE=1, AVD_ENABLE=1, AVD_F_ACTION=5, AVD_F_RCVRY=1)
    reports = {ms: [report(7, up_m=10)] for ms in range(0, 3000, 1000)}
    avoidance, escape, levels, _ = run_avoidance(params, reports, 10_000)
    assert escape.acts and set(escape.acts) == {5}
    # reports stop at 2 s (last contact 1 s): stale past 6 s, then it falls at once
    assert max(t for t, lv in levels if lv == HIGH) == 6000 and escape.recoveries == [1]


def test_far_or_vertically_clear_traffic_is_no_threat_and_is_never_reported():
    params = store(ADSB_TYPE=1, AVD_ENABLE=1)
    reports = {ms: [report(1, 1000), report(2, up_m=400)] for ms in range(6000, 12_000, 1000)}
    _, escape, levels, collisions = run_avoidance(params, reports, 12_000)
    assert {lv for _, lv in levels} == {NONE} and collisions == [] and escape.acts == []


def test_switching_avoidance_off_recovers_with_rtl():
    params = store(ADSB_TYPE=1, AVD_ENABLE=1)
    escape = Recorder()
    avoidance = Avoidance(params, escape)
    avoidance.update(0, list, HOME, (0, 0, 0))
    params.set("AVD_ENABLE", 0)
    avoidance.update(100, list, HOME, (0, 0, 0))
    assert escape.recoveries == [2] and not avoidance.on


# ----- the vehicle --------------------------------------------------------------------------------
SENDER = new_codec(GCS_SYSTEM, GCS_COMPONENT)


def adsb_message(v, icao: int, north_m: float = 0.0, up_m: float = 0.0):
    home = v.home
    lat = round((home.lat_deg + north_m / 111319.5) * 1e7)
    return SENDER.adsb_vehicle_encode(icao, lat, round(home.lon_deg * 1e7), 0, round((home.alt_m + up_m) * 1000),
                                      0, 0, 0, b"T%d" % icao, 1, 1, 0x1FF, 1200)


def fly_reporting(link: Link, seconds: float, *messages) -> list:
    """Send the messages once a second for `seconds` of flight; everything the vehicle sent."""
    v, out, end = link.vehicle, [], link.vehicle.time_s + seconds
    next_report = v.time_s
    while v.time_s < end - 1e-9:
        if v.time_s >= next_report - 1e-9:
            for m in messages:
                out += link.send(m(v) if callable(m) else m)
            next_report += 1.0
        v.run_until(v.time_s + 0.1)
        out += link.poll()
    return out


def test_traffic_from_a_ground_station_comes_back_in_the_adsb_stream():
    link = Link(ready_vehicle(boot_params={"ADSB_TYPE": 1, "MAV1_ADSB": 5}))
    v = link.vehicle
    out = fly_reporting(link, 3.0, adsb_message(v, 11, 300, 50), adsb_message(v, 12, 600, 50))
    sent = of_type(out, "ADSB_VEHICLE")
    assert {m.ICAO_address for m in sent} == {11, 12} and all(m.callsign.startswith("T1") for m in sent)
    link.session.streams.param_changed("MAV1_ADSB", 0)
    assert of_type(fly_reporting(link, 2.0, adsb_message(v, 11, 300, 50)), "ADSB_VEHICLE") == []


def test_an_intruder_overhead_on_the_ground_refuses_arming_and_makes_the_heartbeat_critical():
    link = Link(ready_vehicle(boot_params={"ADSB_TYPE": 1, "AVD_ENABLE": 1, "AVD_F_ACTION": 2}))
    v = link.vehicle
    v.run_until(6.0)
    out = fly_reporting(link, 3.0, adsb_message(v, 7, up_m=10))
    collisions = of_type(out, "COLLISION")
    assert collisions and collisions[-1].id == 7 and collisions[-1].threat_level == HIGH
    assert collisions[-1].action == 0  # on the ground it disarms (there is nothing to disarm)
    assert of_type(out, "HEARTBEAT")[-1].system_status == mav.MAV_STATE_CRITICAL
    assert prearm_failure(v) == "ADSB threat detected" and v.arm() != Result.ACCEPTED
    assert fly_until(v, lambda x: not x.adsb_threat, 6.0) and v.arm() == Result.ACCEPTED


@pytest.mark.parametrize("dev_options", [0, 1])
def test_another_systems_position_is_an_obstacle_with_dev_options_bit_0(dev_options):
    link = Link(ready_vehicle(boot_params={"AVD_ENABLE": 1, "DEV_OPTIONS": dev_options}))
    v = link.vehicle
    other = new_codec(7, 1)
    home = v.home

    def position(x):
        return wire(other.global_position_int_encode(0, round(home.lat_deg * 1e7), round(home.lon_deg * 1e7),
                                                     round((home.alt_m + 10) * 1000), 10_000, 0, 0, 0, 0), other)
    collisions = of_type(fly_reporting(link, 4.0, position), "COLLISION")
    if dev_options:
        assert collisions and (collisions[-1].src, collisions[-1].id, collisions[-1].threat_level) == (0, 7, HIGH)
    else:
        assert collisions == []


@pytest.mark.parametrize("action, mode", [(5, ModeNumber.RTL), (6, ModeNumber.LOITER)])
def test_rtl_and_hover_actions_change_mode_once(action, mode):
    v = hovering_vehicle(20.0)
    v.params.set("ADSB_TYPE", 1)
    v.params.set("AVD_ENABLE", 1)
    v.params.set("AVD_F_ACTION", action)
    link = Link(v)
    fly_reporting(link, 2.0, lambda x: adsb_message(x, 7, up_m=altitude(x) + 5))
    assert v.mode_number == mode
    v.set_mode(ModeNumber.GUIDED)  # a ground station takes over: avoidance does not take it back
    fly_reporting(link, 2.0, lambda x: adsb_message(x, 7, up_m=altitude(x) + 5))
    assert v.mode_number == ModeNumber.GUIDED


def test_a_slow_intruder_alongside_sends_it_away_horizontally_and_recovery_resumes_the_mode():
    v = hovering_vehicle(20.0)
    for name, value in (("ADSB_TYPE", 1), ("AVD_ENABLE", 1), ("AVD_F_ACTION", 3), ("AVD_F_RCVRY", 1)):
        v.params.set(name, value)
    link = Link(v)
    home = v.home

    def east_of_home(x):
        lon = round((home.lon_deg + 30 / (111319.5 * math.cos(math.radians(home.lat_deg)))) * 1e7)
        return SENDER.adsb_vehicle_encode(7, round(home.lat_deg * 1e7), lon, 0, round((home.alt_m + altitude(x)) * 1000),
                                          0, 0, 0, b"T7", 1, 1, 0x1FF, 1200)
    fly_reporting(link, 4.0, east_of_home)
    assert v.mode_number == ModeNumber.AVOID_ADSB
    assert v.body.ve_m_s < -6.0 and abs(v.body.vn_m_s) < 1.0
    assert fly_until(v, lambda x: x.mode_number == ModeNumber.GUIDED, 10.0)  # AVD_F_RCVRY 1: the mode before


# ----- SITL's traffic -----------------------------------------------------------------------------
def fly(sim: TrafficSim, seconds: float, count: int = 5, radius_m: float = 10000.0, vehicle_ne=(0.0, 0.0),
        start_s: float = 0.0) -> list[Aircraft]:
    for k in range(round(seconds * 10)):
        sim.step(0.1, start_s + k * 0.1, count, vehicle_ne, radius_m, 1000.0)
    return sim.flying()


def test_traffic_is_the_same_for_the_same_seed_and_not_for_another():
    runs = [[(a.icao, round(a.n_m, 6), a.emitter_type) for a in fly(TrafficSim(seed), 30.0)] for seed in (3, 3, 4)]
    assert runs[0] == runs[1] and runs[0] != runs[2]


def test_aircraft_fly_straight_climb_and_are_replaced_beyond_the_radius():
    sim = TrafficSim(1)
    first = fly(sim, 0.1, count=20)
    # spread as far as the radius, so many spawn beyond it: those are replaced at the next step
    assert len(sim.aircraft) == 20 and 0 < len(first) < 20
    assert all(math.hypot(a.n_m, a.e_m) > 10000.0 for a in sim.aircraft if a is not None and not a.alive)
    assert all(a.callsign == f"SIM{a.icao}" and a.icao < 10000 for a in first)
    assert all(a.vn_m_s == a.ve_m_s == 0.0 for a in first if a.emitter_type == POINT_OBSTACLE)
    movers = [a for a in first if a.emitter_type < 17]
    assert movers and sum(a.vd_m_s for a in movers) / len(movers) < 0  # climbing, on the whole
    ids = {a.icao for a in first}
    later = fly(sim, 120.0, count=20, radius_m=2000.0, start_s=0.1)
    assert all(math.hypot(a.n_m, a.e_m) <= 2000.0 + 10.0 for a in later)
    assert ids - {a.icao for a in later}  # some were replaced
    assert fly(sim, 0.1, count=3, start_s=200.0) and len(sim.flying()) <= 3  # a new count: all spawned again
    assert fly(sim, 0.1, count=200, start_s=201.0) == []  # SITL's limit: taken as none


def test_the_transceiver_reports_an_aircraft_as_sitl_does():
    origin = Loc(-353632610, 1491652300, 58408)
    a = Aircraft(42, "SIM42", 1, 1000.0, -500.0, 1000.0, -10.0, 10.0, -2.5, 0.0)
    r = sitl_report_of(a, origin)
    assert r.location.lat_e7 == origin.lat_e7 + int(1000.0 / M_PER_E7)
    assert origin.ne_to(r.location)[1] == pytest.approx(-500.0, abs=0.05)
    assert (r.altitude_mm, r.heading_cdeg, r.hor_velocity_cms, r.ver_velocity_cms) == (1_000_000, 13500, 1414, 250)
    assert (r.callsign, r.tslc, r.flags, r.squawk, r.altitude_type) == (b"SIM42", 1, 0x1FF, 1200, 0)


@pytest.mark.parametrize("adsb_type", [0, 1])
def test_sitl_traffic_is_listed_with_a_receiver_and_forwarded_without(adsb_type):
    v = Vehicle(VehicleConfig(faults={"SIM_ADSB_COUNT": 3, "SIM_ADSB_RADIUS": 3000}), store(ADSB_TYPE=adsb_type))
    link = Link(v)
    link.send(SENDER.request_data_stream_encode(1, 1, 0, 10, 1))
    out = fly_reporting(link, 9.9)
    assert of_type(out, "ADSB_VEHICLE") == []  # nothing in the first 10 s
    sent = of_type(fly_reporting(link, 5.0), "ADSB_VEHICLE")
    assert sent and {m.get_srcComponent() for m in sent} == ({156} if adsb_type == 0 else {1})
    assert all(m.callsign == f"SIM{m.ICAO_address}" for m in sent)


def test_without_sim_adsb_count_at_boot_there_is_no_traffic():
    v = Vehicle(VehicleConfig(), store(ADSB_TYPE=1))
    v.params.set("SIM_ADSB_COUNT", 5)  # too late: SITL's transceiver is attached at boot
    v.run_until(15.0)
    assert v.sim.traffic.aircraft == [] and v.traffic.aircraft == []


def test_the_avoid_adsb_switch_turns_avoidance_on_and_off_until_avd_enable_is_set():
    v = ready_vehicle()
    assert v.aux_function(38, 2) == Result.ACCEPTED and v.drain_events()[-1][1] == "ADSB not available"
    v.params.set("ADSB_TYPE", 1)
    v.aux_function(38, 2)
    assert v.drain_events()[-1][1] == "ADSB Avoidance Enabled"
    v.run_until(v.time_s + 0.2)
    assert v.avoidance.on and v.params["AVD_ENABLE"] == 0  # not written to the parameter, as ArduPilot's RAM value
    v.aux_function(38, 0)
    v.run_until(v.time_s + 0.2)
    assert not v.avoidance.on and v.drain_events()[-1][1] == "ADSB Avoidance Disabled"
    v.params.set("AVD_ENABLE", 1)  # a value set again is what counts
    v.run_until(v.time_s + 0.2)
    assert v.avoidance.on


def test_ident_needs_the_adsb_list():
    link = Link(ready_vehicle())
    ack, _ = link.command(mav.MAV_CMD_DO_ADSB_OUT_IDENT)
    assert ack.result == mav.MAV_RESULT_FAILED
    link.vehicle.params.set("ADSB_TYPE", 1)
    link.vehicle.run_until(link.vehicle.time_s + 2.0)  # (a repeat sooner would be taken as a retry)
    ack, out = link.command(mav.MAV_CMD_DO_ADSB_OUT_IDENT, now=link.vehicle.time_s)
    assert ack.result == mav.MAV_RESULT_ACCEPTED
    assert "ADSB: IDENT!" in [m.text for m in of_type(out + link.poll(), "STATUSTEXT")]


@pytest.mark.parametrize("action", [2, 4, 5])
def test_hostile_traffic_reports_never_stop_the_vehicle(action):
    """Any field at any value, near and far, from ground stations and other systems: no handler
    error, no internal error, whatever avoidance does about it."""
    import random
    rng = random.Random(action)
    v = hovering_vehicle(20.0)
    for name, value in (("ADSB_TYPE", 1), ("AVD_ENABLE", 1), ("AVD_F_ACTION", action), ("ADSB_LIST_RADIUS", 0),
                        ("DEV_OPTIONS", 1)):
        v.params.set(name, value)
    link, home = Link(v), v.home
    lat0, lon0, alt0 = round(home.lat_deg * 1e7), round(home.lon_deg * 1e7), round(home.alt_m * 1000)
    for _ in range(150):
        sender = new_codec(rng.randrange(1, 255), 1)
        lat = rng.choice([rng.randrange(-2**31, 2**31), lat0 + rng.randrange(-2000, 2000), 0, 2**31 - 1])
        lon = rng.choice([rng.randrange(-2**31, 2**31), lon0 + rng.randrange(-2000, 2000), 0, -2**31])
        alt = rng.choice([rng.randrange(-2**31, 2**31), alt0 + rng.randrange(-50_000, 50_000), 0])
        if rng.random() < 0.7:
            m = sender.adsb_vehicle_encode(rng.randrange(2**32), lat, lon, rng.randrange(256), alt, rng.randrange(65536),
                                           rng.randrange(65536), rng.randrange(-32768, 32768),
                                           bytes(rng.randrange(256) for _ in range(9)), rng.randrange(256),
                                           rng.randrange(256), rng.randrange(65536), rng.randrange(65536))
        else:
            m = sender.global_position_int_encode(0, lat, lon, alt, 0, *(rng.randrange(-32768, 32768) for _ in range(3)),
                                                  0)
        link.send(wire(m, sender))
        v.run_until(v.time_s + 0.05)
        link.poll()
    assert link.session.counters["handler_errors"] == 0, link.session.last_handler_error
    assert v.internal_error_fields() == (0, 0, 0)


# ----- a scenario's own traffic -------------------------------------------------------------------
@pytest.mark.parametrize("tables, said", [
    ([{"icao": 1, "speed": 3}], "[[traffic]] 1 unknown key 'speed'"),
    ([{"north_m": 5}], "[[traffic]] 1 missing 'icao'"),
    ([{"icao": 0x1000000}], "[[traffic]] 1.icao: 16777216 is not a 24-bit address"),
    ([{"icao": 5, "callsign": "TOO-LONG-9"}], "[[traffic]] 1.callsign: 'TOO-LONG-9' is not up to 8"),
    ([{"icao": 5, "up_m": "high"}], "[[traffic]] 1.up_m: expected a finite number, got 'high'"),
    ([{"icao": 5}, {"icao": 5, "north_m": 10}], "[[traffic]] 2.icao: 5 is [[traffic]] 1's too"),
    ({"icao": 5}, "traffic is given as [[traffic]] tables"),
])
def test_a_bad_traffic_table_gets_one_line_naming_it(tables, said):
    with pytest.raises(ScenarioError) as error:
        scenario_from_dict({"traffic": tables}, "s.toml")
    assert said in str(error.value) and "\n" not in str(error.value)


def test_a_scenarios_intruder_flies_its_track_and_makes_the_vehicle_give_way():
    scenario = scenario_from_dict({"traffic": [{"icao": 4242, "callsign": "INTRUDER", "north_m": 1200, "up_m": 20,
                                                "course_deg": 180, "speed_m_s": 30}]})
    v = hovering_vehicle(20.0, sim=scenario.sim)
    for name, value in (("ADSB_TYPE", 1), ("AVD_ENABLE", 1), ("AVD_F_ACTION", 2)):
        v.params.set(name, value)
    link = Link(v)
    modes, collisions = [], []
    while v.time_s < 70.0:
        v.run_until(v.time_s + 0.5)
        collisions += of_type(link.poll(), "COLLISION")
        modes.append(v.mode_number)
        if v.time_s < 25.0:
            intruder = v.sim.traffic.tracked[0]
            assert intruder.n_m == pytest.approx(1200 - 30 * v.time_s, abs=3.1)  # flown from the start (10 Hz steps)
            listed = [a.report for a in v.traffic.aircraft if a.report.icao == 4242]
            assert not listed or (listed[0].callsign == b"INTRUDER" and  # its altitude a true one
                                  listed[0].altitude_mm == pytest.approx((v.origin.alt_m + 20) * 1000, abs=1000))
    # it gives way once the intruder is HIGH (within 100 m in 30 s), and RTLs (AVD_F_RCVRY 2) once it has gone
    assert ModeNumber.AVOID_ADSB in modes and modes[-1] == ModeNumber.RTL
    assert modes.index(ModeNumber.AVOID_ADSB) < modes.index(ModeNumber.RTL)
    assert any(c.id == 4242 and c.threat_level == HIGH for c in collisions)
