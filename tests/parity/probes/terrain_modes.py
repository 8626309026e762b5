"""Terrain outside AUTO: RTL above terrain (RTL_ALT_TYPE 1), GUIDED's targets in a terrain frame,
and the terrain failsafe, with the same hill on both vehicles (the probe serves it as tiles, as in
area terrain: ArduCopter SITL's ground is its terrain database).

prearm     RTL_ALT_TYPE 1 set once booted (TERRAIN_SPACING 30, no mission): the ARM in GUIDED with
           TERRAIN_ENABLE 0 (result, texts), then with it 1 before any tile is served, then served
           until nothing is pending (each: result, texts, armed); DO_REPOSITION in the terrain frame
           with the terrain off and with none served (its result).
guided     a takeoff to 15 m, then SET_POSITION_TARGET_GLOBAL_INT in MAV_FRAME_GLOBAL_TERRAIN_ALT_INT,
           15 m above terrain at a point 300 m north across the hill: along the hill (40..260 m north)
           the height above it (GLOBAL_POSITION_INT's altitude AMSL less the hill), its largest and mean
           departure from 15 m, the highest AMSL; whether it got there.
reposition there (flat ground), MAV_CMD_DO_REPOSITION as COMMAND_INT in the terrain frame at 25 m:
           its result and the height above home some seconds later.
rtl        RTL from there: it returns at 25 m above terrain (RTL_ALT 15 m, but never below where it
           is): along the hill the height above it, its departure from 25 m, the highest AMSL; what
           it said.
failsafe   back over flat ground in GUIDED with a terrain-frame target, TERRAIN_ENABLE 0: what it
           says and the mode it goes to (ArduCopter's GUIDED has no terrain offset: failsafe, RTL);
           then GUIDED and RTL again with the terrain still off: what RTL says.
rtl_failsafe  the terrain on again, out 120 m north above home in GUIDED, RTL (above terrain), and
           5 s into its return (under way) TERRAIN_ENABLE 0: how long until the failsafe, how far the vehicle
           went meanwhile (its navigator's target stops where it was), what it says, its mode.
prearm_rangefinder  a fresh vehicle with SITL's downward rangefinder (RNGFND1_TYPE 100, RNGFND1_MAX
           10 m) and RTL_ALT_TYPE 1: the ARM with RTL_ALT (15 m) beyond the rangefinder's range,
           then with RNGFND1_MAX 40 (no tiles served: the rangefinder needs no database).
"""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Tol, Trace
from .states import GUIDED, RTL
from .surface_mission import Geometry
from .terrain import RANGEFINDER, TileServer, arm_in_guided, hill_amsl, hill_facts
from .texts import said

AREA = "terrain_modes"
HILL = {"north_m": 150.0, "east_m": 0.0, "height_m": 12.0, "radius_m": 100.0}
PARAMS = {"TERRAIN_SPACING": 30}  # RTL_ALT_TYPE 1 is set once booted: the boot waits for the pre-arm checks
TERRAIN_ALT_INT = mav.MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
ABOVE_M, REPOSITION_M, FAR_NORTH_M, OUT_NORTH_M = 15.0, 25.0, 300.0, 120.0
FAILSAFE = "Failsafe: Terrain data missing"
RETURNING_S = 5.0
OVER_HILL = (40.0, 260.0)  # north [m]: the hill's slopes and top (it spans 50..250)
LOAD_S, LEG_S = 90.0, 80.0
POSITION_ONLY = 0b110111111000  # type_mask: position, no velocity, acceleration or yaw

SECONDS = Tol(abs=1.0, why="5 s of missing terrain (FS_TERRAIN_TIMEOUT_MS) from the parameter set, read at each "
                          "vehicle's loop rate and the probe's read")
MOVED = Tol(abs=6.0, why="the way from the terrain switched off to the failsafe: each vehicle stopping from the return's "
                         "speed at its own navigator's target, then held")
ALT = Tol(abs=1.0, why="the height a vehicle settles at, within its position controller's hold")


def run(target) -> dict[str, Trace]:
    traces = {name: Trace() for name in ("prearm", "guided", "reposition", "rtl", "failsafe", "rtl_failsafe",
                                         "prearm_rangefinder")}
    try:
        client = target.boot(params=PARAMS, world={"terrain": [HILL]})
        pos0 = client.last["GLOBAL_POSITION_INT"]
        geo = Geometry(pos0.lat, pos0.lon)
        server = TileServer(client)
        server.height = hill_amsl(HILL)
        with client.listening(server):
            _prearm(client, traces["prearm"], server)
            if client.armed:
                _fly(client, traces, geo)
        _prearm_rangefinder(target, traces["prearm_rangefinder"])
    finally:
        target.close()
    return traces


def _prearm(client: Client, trace: Trace, server: TileServer) -> None:
    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    trace.fact("rtl_alt_type", client.set_param("RTL_ALT_TYPE", 1))
    trace.fact("disable", client.set_param("TERRAIN_ENABLE", 0))
    arm_in_guided(client, trace, "disabled")
    trace.fact("disabled.reposition", _reposition(client))
    trace.fact("enable", client.set_param("TERRAIN_ENABLE", 1))
    client.idle(1.0)
    arm_in_guided(client, trace, "unloaded")
    trace.fact("unloaded.reposition", _reposition(client))
    server.on = True
    trace.fact("loaded", client.try_wait(lambda: "TERRAIN_REPORT" in client.last
                                         and client.last["TERRAIN_REPORT"].pending == 0
                                         and client.last["TERRAIN_REPORT"].spacing > 0, LOAD_S))
    client.idle(1.0)
    arm_in_guided(client, trace, "loaded")


def _reposition(client: Client) -> int | None:
    """DO_REPOSITION in the terrain frame to where the vehicle stands (on the ground, disarmed)."""
    here = client.last["GLOBAL_POSITION_INT"]
    return client.command_int(mav.MAV_CMD_DO_REPOSITION, TERRAIN_ALT_INT, -1, 0, 0, 0, here.lat, here.lon, ABOVE_M)


def _north(client: Client, geo: Geometry) -> float:
    m = client.last["GLOBAL_POSITION_INT"]
    return geo.ne(m.lat, m.lon)[0]


def _fly(client: Client, traces: dict[str, Trace], geo: Geometry) -> None:
    guided, reposition, rtl, failsafe = traces["guided"], traces["reposition"], traces["rtl"], traces["failsafe"]
    guided.fact("takeoff", client.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, ABOVE_M))
    client.wait(lambda: client.rel_alt_m() > ABOVE_M - 0.5, 30, what="takeoff altitude")
    client.idle(2.0)
    lat, lon = geo.latlon((FAR_NORTH_M, 0.0))
    client.log.clear()
    client.logging = True
    client.conn.mav.set_position_target_global_int_send(0, 1, 1, TERRAIN_ALT_INT, POSITION_ONLY, lat, lon, ABOVE_M,
                                                        0, 0, 0, 0, 0, 0, 0, 0)
    guided.fact("arrived", client.try_wait(lambda: _north(client, geo) > FAR_NORTH_M - 2.0
                                           and abs(client.last["GLOBAL_POSITION_INT"].vx) < 50, LEG_S))
    client.logging = False
    guided.fact("mode", client.mode)
    hill_facts(client.log, geo, hill_amsl(HILL), ABOVE_M, OVER_HILL, guided)

    reposition.fact("result", client.command_int(mav.MAV_CMD_DO_REPOSITION, TERRAIN_ALT_INT, -1, 0, 0, 0,
                                                 lat, lon, REPOSITION_M))
    client.idle(10.0)
    reposition.fact("rel_alt_m", round(client.rel_alt_m(), 1), ALT)

    client.texts.clear()
    client.log.clear()
    client.logging = True
    rtl.fact("mode", client.set_mode(RTL))
    rtl.fact("passed_hill", client.try_wait(lambda: _north(client, geo) < 20.0, LEG_S))
    client.logging = False
    rtl.fact("said", said([t for _, _, t in client.texts]))
    hill_facts(client.log, geo, hill_amsl(HILL), REPOSITION_M, OVER_HILL, rtl)

    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    here = client.last["GLOBAL_POSITION_INT"]
    client.conn.mav.set_position_target_global_int_send(0, 1, 1, TERRAIN_ALT_INT, POSITION_ONLY, here.lat, here.lon,
                                                        REPOSITION_M, 0, 0, 0, 0, 0, 0, 0, 0)
    client.idle(2.0)
    client.texts.clear()
    failsafe.fact("disable", client.set_param("TERRAIN_ENABLE", 0))
    failsafe.fact("rtl", client.try_wait(lambda: client.mode == RTL, 10.0))
    client.idle(2.0)
    failsafe.fact("said", said([t for _, _, t in client.texts]))
    failsafe.fact("mode", client.mode)
    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    client.texts.clear()
    failsafe.fact("rtl_again", client.set_mode(RTL))
    client.idle(1.0)
    failsafe.fact("rtl_again_said", said([t for _, _, t in client.texts]))
    _rtl_failsafe(client, traces["rtl_failsafe"], geo)


def _rtl_failsafe(client: Client, trace: Trace, geo: Geometry) -> None:
    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    trace.fact("enable", client.set_param("TERRAIN_ENABLE", 1))
    lat, lon = geo.latlon((OUT_NORTH_M, 0.0))
    client.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, POSITION_ONLY,
                                                        lat, lon, REPOSITION_M, 0, 0, 0, 0, 0, 0, 0, 0)
    trace.fact("out", client.try_wait(lambda: _north(client, geo) > OUT_NORTH_M - 2.0
                                      and abs(client.last["GLOBAL_POSITION_INT"].vx) < 50, 40.0))
    trace.fact("rtl", client.set_mode(RTL))
    client.idle(RETURNING_S)
    trace.fact("returning", _north(client, geo) < OUT_NORTH_M - 5.0)
    client.texts.clear()
    start_ms, start_n = client.now_ms, _north(client, geo)
    trace.fact("disable", client.set_param("TERRAIN_ENABLE", 0))
    failed = client.try_wait(lambda: any(t == FAILSAFE for _, _, t in client.texts), 10.0)
    trace.fact("failsafe", failed)
    if failed:
        stamp = next(s for s, _, t in client.texts if t == FAILSAFE)
        trace.fact("failsafe_after_s", round((stamp - start_ms) / 1000.0, 1), SECONDS)
        trace.fact("moved_m", round(start_n - _north(client, geo), 1), MOVED)
    client.idle(1.0)
    trace.fact("said", said([t for _, _, t in client.texts]))
    trace.fact("mode", client.mode)


def _prearm_rangefinder(target, trace: Trace) -> None:
    client = target.boot(params={**PARAMS, **RANGEFINDER, "RNGFND1_MAX": 10})
    client.set_mode(GUIDED)
    client.wait(lambda: client.mode == GUIDED, 5, what="GUIDED")
    trace.fact("rtl_alt_type", client.set_param("RTL_ALT_TYPE", 1))
    arm_in_guided(client, trace, "short")
    trace.fact("longer", client.set_param("RNGFND1_MAX", 40))
    client.idle(1.0)
    arm_in_guided(client, trace, "long")
