"""The terrain database and a flight above terrain, with the same hill on both vehicles.

The probe is the ground station serving terrain tiles (groundstation/terrain_tiles.py, as
MAVProxy's terrain module serves SRTM): it answers every TERRAIN_REQUEST with TERRAIN_DATA from
one hill (HILL, north of home) standing on flat ground at home's altitude. ArduCopter SITL's
ground follows its terrain database (SIM_TERRAIN 1), so the served hill is its world; Firefly
boots with the same hill as its scenario's [[terrain]]. TERRAIN_SPACING 30 on both.

exchange   on the ground, before anything is served: the first TERRAIN_REQUEST (its block's corner,
           spacing, mask), TERRAIN_REPORT (spacing, pending, loaded), TERRAIN_CHECK at the hill's
           top (its report), the ARM of a mission with a waypoint above terrain in GUIDED (result,
           texts); then served until the report says nothing is pending: the report (spacing,
           terrain height, current height, pending, loaded), TERRAIN_CHECK at the top and 50 km
           away (not held: spacing 0), and the ARM again.
leg        the same mission flown: takeoff to 15 m, then a waypoint 15 m above terrain 500 m north
           across the hill (the tiles served as asked in flight): along the hill (50..450 m north)
           the height above the hill from GLOBAL_POSITION_INT's altitude AMSL, its largest and
           mean departure from 15 m, the highest AMSL, and TERRAIN_REPORT's current height
           (the vehicle's own height above its terrain) mean; whether the waypoint was reached.
leg_rangefinder  on a fresh vehicle with SITL's downward rangefinder (RNGFND1_TYPE 100, RNGFND1_MAX
           40 m; WPNAV_RFND_USE at its default 1, so the navigator follows what it sees): the
           mission's ARM before any tile is served (result, texts; disarmed again), then served
           until nothing is pending (ArduCopter's simulated ground is its database's) and the leg's
           facts as above.
"""
from __future__ import annotations

from firefly.groundstation.terrain_tiles import answer, hills_amsl
from firefly.sim.geo import GeoPoint
from firefly.sim.terrain import Hill, Terrain

from ..client import Client, mav
from ..facts import Tol, Trace
from .missions import upload
from .states import GUIDED
from .surface_mission import Geometry
from .texts import said

AREA = "terrain"
HOME = GeoPoint(-35.363261, 149.165230, 584.0)
HILL = {"north_m": 250.0, "east_m": 0.0, "height_m": 15.0, "radius_m": 200.0}
PARAMS = {"TERRAIN_SPACING": 30}
RANGEFINDER = {"RNGFND1_TYPE": 100, "RNGFND1_MAX": 40}
REL, TERRAIN_ALT = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT, mav.MAV_FRAME_GLOBAL_TERRAIN_ALT
ABOVE_M, WP_NORTH_M = 15.0, 500.0
LOAD_S, LEG_S = 90.0, 90.0
AUTO = 3

HEIGHT = Tol(abs=1.0, why="metres above the terrain where a vehicle stands or is told: the served heights are "
                          "whole metres and each interpolates its grid")
COUNT = Tol(abs=112, why="sub-grids held: which blocks each wants (around it 0.7 of a block away, 5 points "
                         "about each waypoint) lands in two more or fewer blocks by rounding")
DEVIATION = Tol(abs=1.5, why="how far each vehicle's height above the hill departs from the height asked along the "
                             "leg: two position controllers following the terrain offset, each with its lag")
AMSL = Tol(abs=2.0, why="the top of the flight over the hill: 15 m above its 15 m top, within each controller's lag")


def hill_amsl(hill: dict = HILL):
    """The served heights [m AMSL] of one hill (a probe's HILL table) on home's flat ground."""
    return hills_amsl(HOME, Terrain((Hill(**hill),)))


class TileServer:
    """Answers each TERRAIN_REQUEST the vehicle sends (a listener), counting them."""

    def __init__(self, client: Client) -> None:
        self.client, self.height, self.requests = client, hill_amsl(), 0
        self.on = False

    def __call__(self, msg) -> None:
        if self.on and msg.get_type() == "TERRAIN_REQUEST":
            self.requests += 1
            for data in answer(msg, self.height, self.client.conn.mav):
                self.client.conn.mav.send(data)


def _check(client: Client, lat: int, lon: int) -> list:
    """TERRAIN_CHECK at a point: its TERRAIN_REPORT [spacing, terrain height, pending] (the answer is
    the first report for that point; the streamed ones are for the vehicle's own place)."""
    got: list = []

    def take(msg) -> None:
        if msg.get_type() == "TERRAIN_REPORT" and msg.lat == lat and msg.lon == lon and not got:
            got.append(msg)
    with client.listening(take):
        client.conn.mav.terrain_check_send(lat, lon)
        if not client.try_wait(lambda: bool(got), 5.0):
            return ["no report"]
    r = got[0]
    return [r.spacing, round(r.terrain_height, 1), r.pending]


def _items(geo: Geometry) -> list[tuple]:
    return [(mav.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 0, 0, 0, 0, ABOVE_M),
            (mav.MAV_CMD_NAV_WAYPOINT, TERRAIN_ALT, 0, 0, 0, 0, *geo.latlon((WP_NORTH_M, 0.0)), ABOVE_M)]


CHUNK = 50  # STATUSTEXT's text: a longer one goes on in the next


def _not_prearm(texts: list[str]) -> list[str]:
    """The texts less the pre-arm reports said unasked (every 30 s), with the chunks a long one
    goes on in."""
    kept, dropping = [], False
    for text in texts:
        if text.startswith("PreArm") or dropping:
            dropping = len(text) == CHUNK
            continue
        kept.append(text)
    return kept


def arm_in_guided(client: Client, trace: Trace, name: str) -> None:
    client.set_mode(GUIDED)
    client.texts.clear()
    trace.fact(f"{name}.arm", client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    client.idle(1.0)
    trace.fact(f"{name}.arm_said", said(_not_prearm([t for _, _, t in client.texts])))
    # (HEARTBEAT says it once a second: a read cut at the idle's edge may not have it yet)
    trace.fact(f"{name}.armed", client.try_wait(lambda: client.armed, 3.0))


def run(target) -> dict[str, Trace]:
    exchange, leg, by_rangefinder = Trace(), Trace(), Trace()
    try:
        client = target.boot(params=PARAMS, world={"terrain": [HILL]})
        pos0 = client.last["GLOBAL_POSITION_INT"]
        geo = Geometry(pos0.lat, pos0.lon)
        top = geo.latlon((HILL["north_m"], HILL["east_m"]))
        far = geo.latlon((50_000.0, 0.0))
        server = TileServer(client)
        with client.listening(server):
            client.wait(lambda: "TERRAIN_REQUEST" in client.last, 10.0, what="TERRAIN_REQUEST")
            req = client.last["TERRAIN_REQUEST"]
            exchange.fact("request", [req.lat, req.lon, req.grid_spacing, req.mask])
            client.fresh("TERRAIN_REPORT")
            r = client.last["TERRAIN_REPORT"]
            exchange.fact("report_unloaded", [r.spacing, r.terrain_height, r.pending, r.loaded])
            # nothing known under it: its height above terrain is its altitude AMSL (over 0)
            exchange.fact("report_unloaded.current_height", r.current_height, HEIGHT)
            exchange.fact("check_unloaded", _check(client, *top))
            exchange.fact("upload", upload(client, _items(geo)))
            arm_in_guided(client, exchange, "unloaded")
            server.on = True
            loaded = client.try_wait(lambda: client.last["TERRAIN_REPORT"].pending == 0
                                     and client.last["TERRAIN_REPORT"].spacing > 0, LOAD_S)
            exchange.fact("loaded", loaded)
            client.fresh("TERRAIN_REPORT")
            r = client.last["TERRAIN_REPORT"]
            exchange.fact("report.spacing_pending", [r.spacing, r.pending])
            exchange.fact("report.terrain_height", r.terrain_height, HEIGHT)
            exchange.fact("report.current_height", r.current_height, HEIGHT)
            exchange.fact("report.loaded", r.loaded, COUNT)
            check = _check(client, *top)
            exchange.fact("check_top.spacing", check[0])
            exchange.fact("check_top.height", check[1] if len(check) > 1 else None, HEIGHT)
            exchange.fact("check_far", _check(client, *far)[:2])
            # the far block is wanted now (asked about): served in turn before the ARM
            exchange.fact("reloaded", client.try_wait(lambda: client.last["TERRAIN_REPORT"].pending == 0, LOAD_S))
            client.idle(1.0)
            arm_in_guided(client, exchange, "loaded")
            _fly(client, leg, geo)
        _by_rangefinder(target, by_rangefinder)
    finally:
        target.close()
    return {"exchange": exchange, "leg": leg, "leg_rangefinder": by_rangefinder}


def _by_rangefinder(target, trace: Trace) -> None:
    client = target.boot(params={**PARAMS, **RANGEFINDER}, world={"terrain": [HILL]})
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    server = TileServer(client)
    with client.listening(server):
        client.fresh("TERRAIN_REPORT")
        trace.fact("upload", upload(client, _items(geo)))
        arm_in_guided(client, trace, "unloaded")
        if client.armed:
            client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
            client.wait(lambda: not client.armed, 10.0, what="disarmed")
        server.on = True
        trace.fact("loaded", client.try_wait(lambda: client.last["TERRAIN_REPORT"].pending == 0
                                             and client.last["TERRAIN_REPORT"].spacing > 0, LOAD_S))
        arm_in_guided(client, trace, "loaded")
        _fly(client, trace, geo)


def _fly(client: Client, trace: Trace, geo: Geometry) -> None:
    hill = hill_amsl()
    client.log.clear()
    client.logging = True
    client.set_mode(AUTO)
    seen: list = []

    def take(msg) -> None:
        if msg.get_type() == "MISSION_ITEM_REACHED" and msg.seq == 2:
            seen.append(msg)
    with client.listening(take):
        trace.fact("start", client.command(mav.MAV_CMD_MISSION_START))
        reached = client.try_wait(lambda: bool(seen), LEG_S)
    client.logging = False
    trace.fact("reached", reached)
    reported = []
    for _, msg in client.log:
        if msg.get_type() == "TERRAIN_REPORT" and msg.spacing:
            n, _ = geo.ne(msg.lat, msg.lon)
            if 50.0 < n < 450.0:
                reported.append(msg.current_height)
    if hill_facts(client.log, geo, hill, ABOVE_M, (50.0, 450.0), trace):
        trace.fact("reported_above_mean_m", round(sum(reported) / len(reported), 1) if reported else None, DEVIATION)


def hill_facts(log, geo: Geometry, hill, want_m: float, north: tuple[float, float], trace: Trace) -> bool:
    """A logged flight's height above the hill (GLOBAL_POSITION_INT's altitude AMSL less `hill`
    there) between `north` metres: whether sampled, its largest and mean departure from `want_m`,
    the highest AMSL. False when it was never over the hill."""
    above, amsl = [], []
    for _, msg in log:
        if msg.get_type() == "GLOBAL_POSITION_INT":
            n, _ = geo.ne(msg.lat, msg.lon)
            if north[0] < n < north[1]:
                alt = msg.alt / 1000.0
                above.append(alt - hill(msg.lat * 1e-7, msg.lon * 1e-7))
                amsl.append(alt)
    trace.fact("samples_over_hill", len(above) > 20)
    if not above:
        return False
    deviations = [abs(h - want_m) for h in above]
    trace.fact("deviation_max_m", round(max(deviations), 2), DEVIATION)
    trace.fact("deviation_mean_m", round(sum(deviations) / len(deviations), 2), DEVIATION)
    trace.fact("highest_amsl_m", round(max(amsl), 1), AMSL)
    return True
