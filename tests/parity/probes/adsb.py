"""ADS-B traffic (AP_ADSB) and avoidance (AP_Avoidance) as ArduCopter runs them (issue 31).

receive     ADSB_TYPE 1: three aircraft a ground station reports at 1 Hz come back in the ADSB
            stream (which fields, how often); reports the list refuses (too far, too old, an ICAO
            past 24 bits, no position flags, all zero) and one with coordinates alone; how long
            an aircraft stays listed once its reports stop; DO_ADSB_OUT_IDENT; the AVOID_ADSB aux
            function (38) switching avoidance on (an intruder overhead is then reported) and off.
disabled    ADSB_TYPE 0 (the default): nothing comes back; IDENT fails, the aux switch says so.
threat      AVD_ENABLE 1, AVD_F_ACTION 2, on the ground: an intruder 10 m overhead is a HIGH threat
            (COLLISION, the heartbeat CRITICAL, arming refused) until its reports have stopped long
            enough; an intruder 1 km away after a threat gets a few cleared reports, then none.
report      AVD_F_ACTION 1: the same intruder is reported, and nothing else changes.
climb       AVD_F_ACTION 2 in flight: an intruder above makes it descend in AVOID_ADSB, held at
            RTL_ALT; when it goes, AVD_F_RCVRY 2 brings RTL.
sideways    AVD_F_ACTION 3 in flight: a slow intruder at its height, 30 m east, sends it west at
            WPNAV_SPEED.
sim_traffic SITL's simulated traffic (SIM_ADSB_COUNT 5 at boot) listed with ADSB_TYPE 1 and no
            radius: what its reports carry (drawn at random on both sides: their kinds, not values).
sim_forward the same traffic with ADSB_TYPE 0: forwarded as SITL's transceiver sent it.
dev_options AVD_ENABLE 1 and DEV_OPTIONS 1: another system's GLOBAL_POSITION_INT 10 m overhead is a
            threat too (no ADS-B receiver set).
"""
from __future__ import annotations

import math
import statistics

from ..client import Client, mav
from ..facts import Tol, Trace
from .booting import each_on_a_fresh_vehicle
from .states import GUIDED, LOITER, reach_armed_on_ground

AREA = "adsb"
AUX_AVOID_ADSB = 38  # RC_Channel's AUX_FUNC::AVOID_ADSB
M_PER_DEG = 111319.5
FLAGS_ALL = 0x1FF
AVOID_ADSB, RTL = 19, 6
PROBES_PARAMS = {
    "receive": {"ADSB_TYPE": 1},
    "disabled": None,
    "threat": {"ADSB_TYPE": 1, "AVD_ENABLE": 1, "AVD_F_ACTION": 2},
    "report": {"ADSB_TYPE": 1, "AVD_ENABLE": 1, "AVD_F_ACTION": 1},
    "climb": {"ADSB_TYPE": 1, "AVD_ENABLE": 1, "AVD_F_ACTION": 2},
    "sideways": {"ADSB_TYPE": 1, "AVD_ENABLE": 1, "AVD_F_ACTION": 3},
    "sim_traffic": {"SIM_ADSB_COUNT": 5, "ADSB_TYPE": 1, "ADSB_LIST_RADIUS": 0},
    "sim_forward": {"SIM_ADSB_COUNT": 5},
    "dev_options": {"AVD_ENABLE": 1, "DEV_OPTIONS": 1},
}
SIM_COUNT = 5
TICK = Tol(abs=0.25, why="ADS-B and avoidance run on 100 ms ticks, the client's reports land between them")


def _home(c: Client):
    c.wait(lambda: "HOME_POSITION" in c.last, 90, what="home")
    return c.last["HOME_POSITION"]


def _report(c: Client, icao: int, north_m: float = 0.0, east_m: float = 0.0, up_m: float = 0.0, *,
            tslc: int = 1, flags: int = FLAGS_ALL, heading_cdeg: int = 0, hor_cms: int = 0, zero: bool = False):
    h = c.last["HOME_POSITION"]
    lat = h.latitude + round(north_m / M_PER_DEG * 1e7)
    lon = h.longitude + round(east_m / (M_PER_DEG * math.cos(math.radians(h.latitude * 1e-7))) * 1e7)
    alt = h.altitude + round(up_m * 1000)
    if zero:
        lat = lon = alt = 0
    c.conn.mav.adsb_vehicle_send(icao, lat, lon, mav.ADSB_ALTITUDE_TYPE_PRESSURE_QNH, alt, heading_cdeg, hor_cms, 0,
                                 b"FF%d" % icao, mav.ADSB_EMITTER_TYPE_LIGHT, tslc, flags, 1200)


def _collect(c: Client, kinds: tuple[str, ...]):
    """Messages of these kinds, stamped with vehicle time, while the block listens."""
    got: list = []
    return got, (lambda m: got.append((c.now_ms, m)) if m.get_type() in kinds else None)


def _reporting(c: Client, seconds: int, reports) -> int:
    """Send `reports()` once a vehicle second for `seconds`; the vehicle time of the last [ms]."""
    sent_ms = c.now_ms
    for _ in range(seconds):
        sent_ms = c.now_ms
        reports()
        c.idle(1.0)
    return sent_ms


def receive(c: Client, trace: Trace) -> None:
    _home(c)
    c.idle(2.0)
    got, listener = _collect(c, ("ADSB_VEHICLE",))
    with c.listening(listener):
        _reporting(c, 6, lambda: [_report(c, 100 + i, north_m=d, up_m=50) for i, d in enumerate((300, 800, 1200))])
    window = [(t, m) for t, m in got if t >= got[0][0] + 2000] if got else []
    trace.fact("listed.icaos", sorted({m.ICAO_address for _, m in got}))
    span_s = (window[-1][0] - window[0][0]) / 1000 if len(window) > 1 else 0
    trace.fact("listed.per_second", round(len(window) / max(span_s, 1e-3), 1) if window else 0,
               Tol(abs=0.8, why="three a second; a window's ends cut a pass"))
    one = next((m for _, m in got if m.ICAO_address == 101), None)
    for field in ("lat", "lon", "altitude_type", "altitude", "heading", "hor_velocity", "ver_velocity", "callsign",
                  "emitter_type", "tslc", "flags", "squawk"):
        trace.fact(f"listed.{field}_as_sent", None if one is None else getattr(one, field) == getattr(
            _sent_fields(c, 101, 800, 50), field))
    got.clear()
    refused = {200: dict(north_m=2500), 201: dict(tslc=6), 0x1000000: dict(), 203: dict(flags=0),
               204: dict(flags=mav.ADSB_FLAGS_VALID_HEADING), 205: dict(zero=True),
               206: dict(flags=mav.ADSB_FLAGS_VALID_COORDS), 207: dict(flags=mav.ADSB_FLAGS_VALID_ALTITUDE)}
    with c.listening(listener):
        last_report_ms = _reporting(c, 4, lambda: [_report(c, icao, **kw) for icao, kw in refused.items()])
        c.idle(7.0)
    trace.fact("filtered.icaos", sorted({m.ICAO_address for _, m in got}))
    listed_until = max((t for t, m in got if m.ICAO_address == 206), default=None)
    trace.fact("expiry.listed_s_after_last_report",
               None if listed_until is None else round((listed_until - last_report_ms) / 1000, 1),
               Tol(abs=0.6, why="the last re-send falls within the stream's pass after the 5 s timeout"))
    _switches(c, trace)


def _switches(c: Client, trace: Trace) -> None:
    """DO_ADSB_OUT_IDENT, then the AVOID_ADSB aux function high (with an intruder overhead) and low."""
    since = c.now_ms
    trace.fact("ident.result", c.command(mav.MAV_CMD_DO_ADSB_OUT_IDENT))
    c.idle(0.5)
    trace.fact("ident.texts", [t for t in c.texts_since(since) if "ADSB" in t])
    got, listener = _collect(c, ("COLLISION",))
    for position, name in ((2, "aux_high"), (0, "aux_low")):
        since = c.now_ms
        trace.fact(f"{name}.result", c.command(mav.MAV_CMD_DO_AUX_FUNCTION, AUX_AVOID_ADSB, position))
        with c.listening(listener):
            _reporting(c, 3, lambda: _report(c, 9, up_m=10))
        trace.fact(f"{name}.texts", [t for t in c.texts_since(since) if "ADSB" in t])
        trace.fact(f"{name}.collisions", len(got) > 0)
        got.clear()
        c.idle(6.0)  # the intruder goes stale before the next
        got.clear()


def _sent_fields(c: Client, icao: int, north_m: float, up_m: float):
    """The fields _report sends, decoded as the vehicle would see them."""
    h = c.last["HOME_POSITION"]
    return mav.MAVLink_adsb_vehicle_message(icao, h.latitude + round(north_m / M_PER_DEG * 1e7), h.longitude,
                                            mav.ADSB_ALTITUDE_TYPE_PRESSURE_QNH, h.altitude + round(up_m * 1000),
                                            0, 0, 0, b"FF%d" % icao, mav.ADSB_EMITTER_TYPE_LIGHT, 1, FLAGS_ALL, 1200)


def disabled(c: Client, trace: Trace) -> None:
    _home(c)
    got, listener = _collect(c, ("ADSB_VEHICLE", "COLLISION"))
    with c.listening(listener):
        _reporting(c, 4, lambda: _report(c, 100, north_m=300, up_m=10))
    trace.fact("sent_back", sorted({m.get_type() for _, m in got}))
    _switches(c, trace)


def _collision_facts(trace: Trace, name: str, got: list, closing: Tol = Tol(abs=0.1)) -> None:
    collisions = [(t, m) for t, m in got if m.get_type() == "COLLISION"]
    trace.fact(f"{name}.collisions", bool(collisions))
    if not collisions:
        return
    m = collisions[-1][1]
    for field in ("src", "id", "action", "threat_level"):
        trace.fact(f"{name}.{field}", getattr(m, field))
    trace.fact(f"{name}.altitude_minimum_delta", round(m.altitude_minimum_delta, 2), Tol(abs=0.1))
    trace.fact(f"{name}.horizontal_minimum_delta", round(m.horizontal_minimum_delta, 2), Tol(abs=0.1))
    trace.fact(f"{name}.time_to_minimum_delta", round(m.time_to_minimum_delta, 2), closing)
    gaps = [(b - a) / 1000 for (a, _), (b, _) in zip(collisions, collisions[1:])]
    trace.fact(f"{name}.interval_s", round(statistics.median(gaps), 2) if gaps else None, TICK)


def _arm_texts(c: Client) -> tuple[int | None, list[str]]:
    since = c.now_ms
    result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.idle(0.5)
    return result, [t for t in c.texts_since(since) if "ADSB" in t]


def _ready(c: Client) -> None:
    _home(c)
    c.wait(lambda: c.last["GPS_RAW_INT"].fix_type >= 3, 90, what="a fix")
    c.set_mode(GUIDED)
    c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
    c.idle(20.0)  # past the EKF's settling: ARM's only refusal is then the threat's


def _overhead(c: Client, trace: Trace) -> int:
    """An intruder 10 m overhead for 5 s, on the ground: what comes of it; its last report [ms]."""
    _ready(c)
    got, listener = _collect(c, ("COLLISION",))
    with c.listening(listener):
        last_report_ms = _reporting(c, 5, lambda: _report(c, 7, up_m=10))
        c.fresh_heartbeat()
        trace.fact("overhead.system_status", c.system_status)
        result, texts = _arm_texts(c)
        trace.fact("overhead.arm", result)
        trace.fact("overhead.arm_texts", texts)
    _collision_facts(trace, "overhead", got)
    return last_report_ms


def threat(c: Client, trace: Trace) -> None:
    last_report_ms = _overhead(c, trace)
    got, listener = _collect(c, ("COLLISION",))
    c.wait(lambda: c.system_status == mav.MAV_STATE_STANDBY, 20, what="the threat to clear")
    trace.fact("overhead.cleared_after_s", round((c.now_ms - last_report_ms) / 1000, 1),
               Tol(abs=1.1, why="heartbeats come once a second"))
    with c.listening(listener):
        _reporting(c, 3, lambda: _report(c, 7, up_m=10))
        _reporting(c, 9, lambda: _report(c, 7, north_m=1000, up_m=10))
    cleared = [(t, m) for t, m in got if m.threat_level == 0]
    trace.fact("away.cleared_reports", len(cleared), Tol(abs=1, why="one every 1.1 s for 5 s"))
    trace.fact("away.cleared_id", cleared[-1][1].id if cleared else None)


def report(c: Client, trace: Trace) -> None:
    _overhead(c, trace)


def _flying_in_loiter(c: Client, alt_m: float) -> None:
    _ready(c)
    reach_armed_on_ground(c, GUIDED)
    c.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt_m)
    c.wait(lambda: c.rel_alt_m() > alt_m - 0.5, 60, what="takeoff altitude")
    c.set_mode(LOITER)
    c.wait(lambda: c.mode == LOITER, 5, what="LOITER")
    c.idle(2.0)


def climb(c: Client, trace: Trace) -> None:
    _flying_in_loiter(c, 25.0)
    got, listener = _collect(c, ("COLLISION", "GLOBAL_POSITION_INT"))
    with c.listening(listener):
        _reporting(c, 8, lambda: _report(c, 7, up_m=c.rel_alt_m() + 10))
        trace.fact("above.mode", c.mode)
        descending = [m.vz / 100 for t, m in got if m.get_type() == "GLOBAL_POSITION_INT" and m.vz > 50]
        trace.fact("above.descent_m_s", round(statistics.median(descending), 2) if descending else None,
                   Tol(abs=0.3, why="WPNAV_SPEED_DN, reached by the position controller's own ramp"))
        trace.fact("above.held_at_m", round(c.rel_alt_m(), 1), Tol(abs=1.5, why="RTL_ALT, where it stops"))
        trace.fact("above.system_status", c.system_status)
        c.wait(lambda: c.mode == RTL, 20, what="RTL after the threat")
        trace.fact("gone.mode", c.mode)
    _collision_facts(trace, "above", got, Tol(abs=5.0, why="a hover's centimetres from the closest approach "
                                                            "over its centimetres per second: noise"))


def sideways(c: Client, trace: Trace) -> None:
    _flying_in_loiter(c, 20.0)
    got, listener = _collect(c, ("GLOBAL_POSITION_INT",))
    with c.listening(listener):
        _reporting(c, 6, lambda: _report(c, 7, east_m=30, up_m=c.rel_alt_m()))
    trace.fact("east.mode", c.mode)
    trace.fact("east.fastest_west_m_s", round(max(-m.vy for _, m in got) / 100, 1),
               Tol(abs=1.0, why="WPNAV_SPEED, as each velocity controller reaches it"))
    trace.fact("east.most_north_m_s", round(max(abs(m.vx) for _, m in got) / 100, 1),
               Tol(abs=1.0, why="straight west: what the controllers let through"))


def sim_traffic(c: Client, trace: Trace) -> None:
    _home(c)
    got, listener = _collect(c, ("ADSB_VEHICLE",))
    with c.listening(listener):
        c.wait(lambda: c.now_ms > 12_000 and got, 60, what="simulated traffic")
        trace.fact("first_after_s", got[0][0] >= 10_000)
        c.idle(20.0)
    reports = [m for _, m in got]
    trace.fact("icaos_below_10000", all(m.ICAO_address < 10000 for m in reports))
    trace.fact("callsigns_sim_icao", all(m.callsign == f"SIM{m.ICAO_address}" for m in reports))
    for field in ("flags", "tslc", "squawk", "altitude_type"):
        trace.fact(f"{field}_values", sorted({getattr(m, field) for m in reports}))
    trace.fact("emitter_types_in_range", all(0 <= m.emitter_type < 20 for m in reports))
    trace.fact("median_altitude_m", round(statistics.median(m.altitude for m in reports) / 1000),
               Tol(abs=200, why="SIM_ADSB_ALT 1000 m at spawn, then each climbs at a random N(3, 3) m/s"))
    last_pass = {m.ICAO_address for t, m in got if t >= got[-1][0] - 1500}
    trace.fact("listed_at_once", len(last_pass), Tol(abs=1, why="one respawned within 5 s is still listed"))
    by_icao: dict = {}
    for t, m in got:
        by_icao.setdefault(m.ICAO_address, []).append(t)
    gaps = [(b - a) / 1000 for times in by_icao.values() for a, b in zip(times, times[1:])]
    trace.fact("update_interval_s", round(statistics.median(gaps), 1), Tol(abs=0.15))


def sim_forward(c: Client, trace: Trace) -> None:
    _home(c)
    sources: dict = {}
    take = c._take

    def counting(msg):  # the client keeps only the autopilot's own messages: count before it does
        if msg.get_type() == "ADSB_VEHICLE":
            key = f"{msg.get_srcSystem()}/{msg.get_srcComponent()}"
            sources[key] = sources.get(key, 0) + 1
        take(msg)
    c._take = counting
    try:
        c.wait(lambda: c.now_ms > 12_000, 60, what="time for the traffic")
        start_ms, before = c.now_ms, dict(sources)
        c.idle(10.0)
    finally:
        c._take = take
    trace.fact("sources", sorted(sources))
    rate = (sources.get("1/156", 0) - before.get("1/156", 0)) / ((c.now_ms - start_ms) / 1000)
    trace.fact("forwarded_per_second", round(rate, 1), Tol(abs=1.0, why=f"{SIM_COUNT} a second, less respawns"))


def dev_options(c: Client, trace: Trace) -> None:
    _ready(c)
    h = c.last["HOME_POSITION"]
    got, listener = _collect(c, ("COLLISION",))

    def position():
        c.conn.mav.srcSystem = 7  # another vehicle's report
        try:
            c.conn.mav.global_position_int_send(0, h.latitude, h.longitude, h.altitude + 10_000, 10_000, 0, 0, 0, 0)
        finally:
            c.conn.mav.srcSystem = 255
    with c.listening(listener):
        _reporting(c, 5, position)
        c.fresh_heartbeat()
        trace.fact("overhead.system_status", c.system_status)
    _collision_facts(trace, "overhead", got)


PROBES = {"receive": receive, "disabled": disabled, "threat": threat, "report": report, "climb": climb,
          "sideways": sideways, "sim_traffic": sim_traffic, "sim_forward": sim_forward,
          "dev_options": dev_options}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, PROBES_PARAMS)
