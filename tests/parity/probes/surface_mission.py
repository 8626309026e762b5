"""ArduCopter's mission commands, each uploaded in a mission and flown in AUTO (issue 26).

For every in-scope entry of kind "mission_commands" (surface/arducopter.json less scope.toml's
[[out]]), a fresh vehicle gets the mission a ground station would build to try that command:

    0 home, 1 NAV_TAKEOFF 10 m, 2 NAV_WAYPOINT A (20 m north), 3 the command under test,
    4 NAV_WAYPOINT B (20 m north, 20 m east), 5 NAV_LAND

(a command that ends the flight, NAV_LAND or NAV_RETURN_TO_LAUNCH, is the last item). It is armed
in GUIDED and started with MISSION_START, as missions.py does, and watched until the vehicle
disarms, the final item has been current for FINAL_HOLD_S, the command under test (one that never
ends by itself) has been current for its hold, or a vehicle-time limit.

Facts per entry, all under the scenario "auto": the MISSION_ACK of the upload, MISSION_START's
ACK, the MISSION_ITEM_REACHED seqs, the MISSION_CURRENT seqs as they changed, the texts said, mode
and arming at the end; and where the command does something a client can see: how far the vehicle
went off the straight leg A-B (a positional item is placed 10 m off it, so flying it shows), the
time its item was current, the highest or lowest altitude, the heading on reaching B, the
groundspeed in the middle of the leg after it, servo 9's outputs, CAMERA_FEEDBACKs, the fence's
enabled bit and the home position at the end. A relay's state is not watched: RELAY_STATUS is a
MAVLink 2 message (id 376) the harness's MAVLink 1 dialect cannot decode; the relay commands'
facts are the mission's own.
"""
from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..client import Client, mav
from ..facts import Tol, Trace
from .missions import EARTH_M_PER_DEG, REL, upload
from .states import GUIDED, mode_name
from .texts import said

AREA = "surface_mission"
KIND = "mission_commands"
SCENARIO = "auto"
SURFACE_DIR = Path(__file__).resolve().parent.parent / "surface"

ALT_M = 10.0
LEG_A = (20.0, 0.0)      # (north, east) metres from home: the waypoint before the command
LEG_B = (20.0, 20.0)     # the waypoint after it: the leg A-B runs east
OFF_PATH = (30.0, 10.0)  # where a positional command is placed: 10 m north of the leg's middle
ROI = (20.0, -30.0)      # a region of interest due west of the whole leg: facing it is heading 270
NEW_HOME = (-10.0, 10.0)
JUMP_TAG = 7
FINAL_HOLD_S = 2.0       # the final item current this long: the command's part is over
DISARMED_HOLD_S = 1.0    # watched this long past the first disarmed HEARTBEAT: what disarming resets
LIMIT_S = 70.0           # vehicle seconds from MISSION_START: takeoff, two 20 m legs and the command
SERVO = 9                # the first output ArduCopter's quad leaves free (SERVO9_FUNCTION 0)
FENCE_BIT = mav.MAV_SYS_STATUS_GEOFENCE


@dataclass(frozen=True)
class Spec:
    """How the command under test is put in the mission and what is watched for it."""
    params: tuple = (0, 0, 0, 0)      # param1..4 as a ground station fills them
    at: tuple | None = None            # (north, east) for a positional command, else lat/lon 0
    alt: float = 0.0                   # z: altitude (relative frame), or the item's 7th param
    x: int | None = None               # x (param5) when it is not a latitude
    ends_flight: bool = False          # the last item: nothing after it, watched until disarmed
    hold_s: float | None = None        # a command that never ends: watched this long once current
    limit_s: float = LIMIT_S
    watch: frozenset = field(default_factory=frozenset)


def _spec(*params, watch=(), **kw) -> Spec:
    return Spec(params=tuple((list(params) + [0, 0, 0, 0])[:4]), watch=frozenset(watch), **kw)


# What a ground station puts in each command's item; the comment says why where the choice matters.
SPECS: dict[str, Spec] = {
    "MAV_CMD_NAV_WAYPOINT": _spec(0, at=OFF_PATH, alt=ALT_M, watch={"track"}),  # no hold time
    "MAV_CMD_NAV_LOITER_UNLIM": _spec(0, 0, 0, at=OFF_PATH, alt=ALT_M, hold_s=8.0, watch={"track"}),
    # one turn of 5 m: a circle short enough to finish within the limit
    "MAV_CMD_NAV_LOITER_TURNS": _spec(1, 0, 5, 0, at=OFF_PATH, alt=ALT_M, limit_s=100.0,
                                      watch={"track", "time"}),
    "MAV_CMD_NAV_LOITER_TIME": _spec(5, 0, 0, 0, at=OFF_PATH, alt=ALT_M, watch={"track", "time"}),
    "MAV_CMD_NAV_RETURN_TO_LAUNCH": _spec(ends_flight=True, limit_s=150.0, watch={"track"}),
    "MAV_CMD_NAV_LAND": _spec(at=OFF_PATH, ends_flight=True, limit_s=150.0, watch={"track", "min_alt"}),
    # a second takeoff in the air, higher than the first: climbs, or counts as done at once
    "MAV_CMD_NAV_TAKEOFF": _spec(alt=15.0, watch={"max_alt"}),
    "MAV_CMD_NAV_VTOL_TAKEOFF": _spec(alt=15.0, watch={"max_alt"}),
    "MAV_CMD_NAV_VTOL_LAND": _spec(at=OFF_PATH, ends_flight=True, limit_s=150.0, watch={"track", "min_alt"}),
    "MAV_CMD_NAV_CONTINUE_AND_CHANGE_ALT": _spec(0, alt=15.0, watch={"max_alt"}),  # p1 0: neutral
    "MAV_CMD_NAV_LOITER_TO_ALT": _spec(0, 0, 0, 0, at=OFF_PATH, alt=15.0, watch={"track", "max_alt"}),
    "MAV_CMD_NAV_SPLINE_WAYPOINT": _spec(0, at=OFF_PATH, alt=ALT_M, watch={"track"}),
    # p1 1 hands control to an external computer; with no limits it holds until told otherwise
    "MAV_CMD_NAV_GUIDED_ENABLE": _spec(1, hold_s=8.0, watch={"track"}),
    # p2..p4 -1: a delay in seconds, not until a time of day
    "MAV_CMD_NAV_DELAY": _spec(3, -1, -1, -1, watch={"time"}),
    # p1 0: descend until the payload touches down, no limit on the descent
    "MAV_CMD_NAV_PAYLOAD_PLACE": _spec(0, at=OFF_PATH, alt=ALT_M, limit_s=120.0,
                                       watch={"track", "min_alt", "time"}),
    # 3 s level, facing south, no climb: the vehicle holds that attitude and drifts little
    "MAV_CMD_NAV_ATTITUDE_TIME": _spec(3, 0, 0, 180, x=0, watch={"time"}),
    # command 0, 3 s timeout: no script takes it, so the timeout ends it
    "MAV_CMD_NAV_SCRIPT_TIME": _spec(0, 3, 0, 0, watch={"time"}),
    "MAV_CMD_CONDITION_DELAY": _spec(3),
    "MAV_CMD_CONDITION_DISTANCE": _spec(5),
    # south (180), default rate, absolute: away from the leg's own heading (east, 90)
    "MAV_CMD_CONDITION_YAW": _spec(180, 0, 0, 0, watch={"heading"}),
    "MAV_CMD_DO_JUMP": _spec(2, 1),  # back to waypoint A once
    "MAV_CMD_DO_CHANGE_SPEED": _spec(1, 3, -1, 0, watch={"speed"}),  # groundspeed 3 m/s
    # p1 0: the location given (p1 1 would be the vehicle's own)
    "MAV_CMD_DO_SET_HOME": _spec(0, at=NEW_HOME, alt=0.0, watch={"home"}),
    "MAV_CMD_DO_SET_RELAY": _spec(0, 1),  # relay 0 on
    "MAV_CMD_DO_REPEAT_RELAY": _spec(0, 2, 1),  # relay 0 toggled twice, 1 s cycle
    "MAV_CMD_DO_SET_SERVO": _spec(SERVO, 1700, watch={"servo"}),
    "MAV_CMD_DO_REPEAT_SERVO": _spec(SERVO, 1700, 2, 1, watch={"servo"}),  # twice, 1 s cycle
    "MAV_CMD_DO_RETURN_PATH_START": _spec(),
    "MAV_CMD_DO_LAND_START": _spec(),
    "MAV_CMD_DO_SET_ROI_LOCATION": _spec(0, at=ROI, alt=0.0, watch={"heading"}),  # gimbal 0: all
    "MAV_CMD_DO_SET_ROI_NONE": _spec(watch={"heading"}),
    "MAV_CMD_DO_SET_ROI": _spec(mav.MAV_ROI_LOCATION, at=ROI, alt=0.0, watch={"heading"}),
    # auto mode, 1/125 s, f/4, ISO 100
    "MAV_CMD_DO_DIGICAM_CONFIGURE": _spec(1, 125, 4, 100, watch={"camera"}),
    "MAV_CMD_DO_DIGICAM_CONTROL": _spec(0, 0, 0, 0, x=1, watch={"camera"}),  # x 1: take a picture
    # pitch -30, yaw 180; z is the mount mode: MAVLink targeting
    "MAV_CMD_DO_MOUNT_CONTROL": _spec(-30, 0, 180, 0, alt=mav.MAV_MOUNT_MODE_MAVLINK_TARGETING, watch={"heading"}),
    # a picture every 5 m, and one at once (p3 1)
    "MAV_CMD_DO_SET_CAM_TRIGG_DIST": _spec(5, 0, 1, watch={"camera"}),
    "MAV_CMD_DO_FENCE_ENABLE": _spec(1, watch={"fence"}),
    "MAV_CMD_DO_PARACHUTE": _spec(1),  # enable: a release would end the flight
    "MAV_CMD_DO_GRIPPER": _spec(1, 0),  # gripper 1, release
    "MAV_CMD_DO_SET_RESUME_REPEAT_DIST": _spec(10),
    "MAV_CMD_DO_SPRAYER": _spec(1),
    "MAV_CMD_DO_SEND_SCRIPT_MESSAGE": _spec(1, 2, 3, 4),
    # RC aux function 28 (relay 1) switched high: the same relay DO_SET_RELAY drives
    "MAV_CMD_DO_AUX_FUNCTION": _spec(28, 2),
    # 10 s, 5-50 m, 100 m: limits for a later NAV_GUIDED_ENABLE, nothing to see by themselves
    "MAV_CMD_DO_GUIDED_LIMITS": _spec(10, 5, 50, 100),
    "MAV_CMD_SET_CAMERA_ZOOM": _spec(mav.ZOOM_TYPE_RANGE, 50, watch={"camera"}),
    "MAV_CMD_SET_CAMERA_FOCUS": _spec(mav.FOCUS_TYPE_AUTO, 0, watch={"camera"}),
    "MAV_CMD_SET_CAMERA_SOURCE": _spec(0, 1, 0, watch={"camera"}),
    "MAV_CMD_JUMP_TAG": _spec(JUMP_TAG),
    "MAV_CMD_DO_JUMP_TAG": _spec(JUMP_TAG, 1),  # the mission gets a JUMP_TAG before waypoint A
    # pitch -30, yaw 0 (ahead), rates 0, flags 0, gimbal 0 (the primary)
    "MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW": _spec(-30, 0, 0, 0, x=0, watch={"heading"}),
    # camera 0 (all), a picture every 1 s, 3 of them
    "MAV_CMD_IMAGE_START_CAPTURE": _spec(0, 1, 3, 0, watch={"camera"}),
    "MAV_CMD_IMAGE_STOP_CAPTURE": _spec(0, watch={"camera"}),
    "MAV_CMD_VIDEO_START_CAPTURE": _spec(0, watch={"camera"}),
    "MAV_CMD_VIDEO_STOP_CAPTURE": _spec(0, watch={"camera"}),
    # winch 1, length control: 2 m out at 0.5 m/s
    "MAV_CMD_DO_WINCH": _spec(1, 1, 2, 0.5),
}
DEFAULT_SPEC = _spec()  # a command listed on the surface with no row here: zeros, as a bare GCS item

TOL_TRACK = Tol(abs=3.0, why="cornering at A and B and where an item counts as reached differ by a "
                             "metre or two between controllers; an item flown or skipped differs by 10 m")
TOL_TIME = Tol(abs=3.0, rel=0.2, why="the item's time includes flying to its position at the "
                                    "controller's own speed; the timer itself is exact")
TOL_ALT = Tol(abs=1.0, why="altitude overshoot and where a climb counts as done differ by under a metre")
TOL_HEADING = Tol(abs=15.0, why="yaw still settling when B is reached: a turn done or not differs by 90 degrees")
TOL_SPEED = Tol(abs=0.8, why="mid-leg speed settles on the limit within half a metre per second; the limit set "
                             "and the default differ by several m/s")
TOL_HOME = Tol(abs=1.5, why="home moved or not differs by 14 m; the conversion to metres is exact")


# ----- the surface --------------------------------------------------------------------------------
def in_scope() -> list[str]:
    """The in-scope mission commands, in arducopter.json's order."""
    doc = json.loads((SURFACE_DIR / "arducopter.json").read_text())
    scope = SURFACE_DIR / "scope.toml"
    out = set()
    if scope.exists():
        for block in tomllib.loads(scope.read_text()).get("out", []):
            if block.get("kind") == KIND:
                out.update(block["names"])
    return [e["name"] for e in doc[KIND] if e["name"] not in out]


# ----- the mission --------------------------------------------------------------------------------
class Geometry:
    """Metres north and east of home to the item's latitude and longitude, and back."""

    def __init__(self, lat_e7: int, lon_e7: int):
        self.lat, self.lon = lat_e7, lon_e7
        self.m_per_deg_lon = EARTH_M_PER_DEG * math.cos(math.radians(lat_e7 * 1e-7))

    def latlon(self, ne: tuple) -> tuple[int, int]:
        return (self.lat + int(round(ne[0] / EARTH_M_PER_DEG * 1e7)),
                self.lon + int(round(ne[1] / self.m_per_deg_lon * 1e7)))

    def ne(self, lat_e7: int, lon_e7: int) -> tuple[float, float]:
        return ((lat_e7 - self.lat) * 1e-7 * EARTH_M_PER_DEG, (lon_e7 - self.lon) * 1e-7 * self.m_per_deg_lon)


def item(command: int, geo: Geometry, params=(0, 0, 0, 0), at=None, alt=0.0, x=None) -> tuple:
    lat, lon = geo.latlon(at) if at is not None else (0, 0)
    if x is not None:
        lat = x
    return (command, REL, *params, lat, lon, alt)


def build(name: str, spec: Spec, geo: Geometry) -> tuple[list, int, int | None]:
    """The mission's items after home, the seq of the command under test and of waypoint B."""
    command = getattr(mav, name)
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=ALT_M)]
    if name == "MAV_CMD_DO_JUMP_TAG":
        items.append(item(mav.MAV_CMD_JUMP_TAG, geo, (JUMP_TAG, 0, 0, 0)))
    items.append(item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=LEG_A, alt=ALT_M))
    params = spec.params
    if name == "MAV_CMD_DO_JUMP":
        params = (len(items), *params[1:])  # to waypoint A's seq (home is seq 0)
    items.append(item(command, geo, params, spec.at, spec.alt, spec.x))
    seq = len(items)
    if spec.ends_flight:
        return items, seq, None
    items.append(item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=LEG_B, alt=ALT_M))
    b_seq = len(items)
    items.append(item(mav.MAV_CMD_NAV_LAND, geo))
    return items, seq, b_seq


# ----- watching -----------------------------------------------------------------------------------
def off_segment_m(p: tuple, a: tuple, b: tuple) -> float:
    """Distance from point p to the segment a-b (all (north, east) metres)."""
    ax, ay = b[0] - a[0], b[1] - a[1]
    t = max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / (ax * ax + ay * ay)))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay)


def deduped(values: list) -> list:
    out: list = []
    for v in values:
        if not out or out[-1] != v:
            out.append(v)
    return out


def held_seqs(seqs: list[int]) -> list[int]:
    """MISSION_CURRENT seqs as they changed, each counted once seen in two beats in a row: an item
    over within one 10 Hz beat shows in one vehicle's stream and not the other's by timing alone."""
    changes: list[int] = []
    for prev, cur in zip(seqs, seqs[1:]):
        if prev == cur and (not changes or changes[-1] != cur):
            changes.append(cur)
    return changes


class Window:
    """Where the flight's window ends, decided message by message in the order they came (a
    listener), so a client that reads a burst of seconds at once under load still cuts the window
    at the same vehicle moment: disarmed for DISARMED_HOLD_S, the final item or a mission complete
    held FINAL_HOLD_S, a never-ending command held its hold, or the limit.

    Disarmed is held a second, not cut at the first disarmed HEARTBEAT: the 1 Hz HEARTBEAT falls
    anywhere up to a second after the disarm, so a window cut there saw the mission's reset on
    disarming (MISSION_CURRENT back to 1) for ten beats or for none, by the client's timing."""

    def __init__(self, client: Client, spec: Spec, seq: int, final_seq: int):
        self.c, self.spec, self.seq, self.final_seq = client, spec, seq, final_seq
        self.start_ms = client.now_ms
        self.current, self.since_ms, self.complete = None, client.now_ms, False
        self.disarmed_ms: int | None = None
        self.end: int | None = None  # length of client.log when the window ended

    def __call__(self, msg) -> None:
        if self.end is not None:
            return
        now = self.c.now_ms
        if msg.get_type() == "MISSION_CURRENT" and (msg.seq != self.current or
                                                    (msg.mission_state == mav.MISSION_STATE_COMPLETE) != self.complete):
            self.current, self.since_ms = msg.seq, now
            self.complete = msg.mission_state == mav.MISSION_STATE_COMPLETE
        held = (now - self.since_ms) / 1000.0
        if self.disarmed_ms is None and now - self.start_ms > 3000 and not self.c.armed:
            self.disarmed_ms = now
        if (self.disarmed_ms is not None and now - self.disarmed_ms >= DISARMED_HOLD_S * 1000) \
                or now - self.start_ms >= self.spec.limit_s * 1000 \
                or (not self.spec.ends_flight and (self.current == self.final_seq or self.complete)
                    and held >= FINAL_HOLD_S) \
                or (self.spec.hold_s is not None and self.current == self.seq and held >= self.spec.hold_s):
            self.end = len(self.c.log)


def fly_mission(client: Client, items: list, spec: Spec, seq: int) -> tuple[int | None, int | None, list]:
    """Upload the items, arm in GUIDED, start the mission and watch it until its Window ends (seq:
    the command under test's): the upload's MISSION_ACK, MISSION_START's ACK and the window's log."""
    uploaded = upload(client, items)
    client.set_mode(GUIDED)
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    client.try_wait(lambda: client.armed, 10)
    client.log.clear()
    client.logging = True
    window = Window(client, spec, seq, len(items))
    with client.listening(window):
        started = client.command(mav.MAV_CMD_MISSION_START)
        client.wait(lambda: window.end is not None, spec.limit_s + 10, what="the mission's end")
    client.logging = False
    return uploaded, started, client.log[:window.end]


def fly(client: Client, name: str, spec: Spec, trace: Trace) -> None:
    pos0 = client.last["GLOBAL_POSITION_INT"]
    geo = Geometry(pos0.lat, pos0.lon)
    items, seq, b_seq = build(name, spec, geo)
    f = lambda fact: f"{SCENARIO}.{fact}"  # noqa: E731 - the scenario's fact names

    uploaded, started, log = fly_mission(client, items, spec, seq)
    trace.fact(f("upload"), uploaded)
    trace.fact(f("start"), started)

    def of(kind):
        return [(t, m) for t, m in log if m.get_type() == kind]

    currents = of("MISSION_CURRENT")
    heartbeats = of("HEARTBEAT")
    trace.fact(f("reached"), [m.seq for _, m in of("MISSION_ITEM_REACHED")])
    trace.fact(f("current_seq_seen"), held_seqs([m.seq for _, m in currents]))
    trace.fact(f("said"), said([m.text for _, m in of("STATUSTEXT")]))
    last_beat = heartbeats[-1][1] if heartbeats else None
    trace.fact(f("mode_end"), mode_name(last_beat.custom_mode) if last_beat else None)
    trace.fact(f("armed_end"), bool(last_beat.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED) if last_beat else None)

    # The leg after waypoint A, by MISSION_CURRENT's beats (a MISSION_ITEM_REACHED can be lost on a
    # busy link; the 10 Hz stream cannot): from the first beat past A to the first beat past B.
    end_ms = log[-1][0] if log else client.now_ms
    a_seq = seq - 1
    leg_start = next((t for t, m in currents if m.seq > a_seq), end_ms + 1)
    leg_end = end_ms if b_seq is None else next((t for t, m in currents if t >= leg_start and m.seq > b_seq), end_ms)
    positions = [(t, geo.ne(m.lat, m.lon), m.relative_alt / 1000.0, math.hypot(m.vx, m.vy) / 100.0, m.hdg)
                 for t, m in of("GLOBAL_POSITION_INT")]
    on_leg = [p for p in positions if leg_start <= p[0] <= leg_end]

    if "track" in spec.watch:
        trace.fact(f("off_path_max_m"), round(max((off_segment_m(p[1], LEG_A, LEG_B) for p in on_leg), default=0.0), 1),
                   TOL_TRACK)
    if "time" in spec.watch:
        # from the first beat the item is current to the first beat another one is
        first = next((t for t, m in currents if m.seq == seq), None)
        last = next((t for t, m in currents if first is not None and t > first and m.seq != seq), end_ms)
        trace.fact(f("seconds_current"), round((last - first) / 1000.0, 1) if first is not None else 0.0, TOL_TIME)
    if "max_alt" in spec.watch:
        trace.fact(f("max_alt_m"), round(max((p[2] for p in on_leg), default=0.0), 1), TOL_ALT)
    if "min_alt" in spec.watch:
        trace.fact(f("min_alt_m"), round(min((p[2] for p in on_leg), default=ALT_M), 1), TOL_ALT)
    if "speed" in spec.watch:
        # the middle fifth of the leg A-B: past the turn at A, before slowing for B
        middle = [p[3] for p in on_leg if 0.4 <= (p[1][1] - LEG_A[1]) / (LEG_B[1] - LEG_A[1]) <= 0.6]
        trace.fact(f("speed_mid_leg_ms"), round(sum(middle) / len(middle), 1) if middle else None, TOL_SPEED)
    if "heading" in spec.watch:
        known = [p[4] for p in on_leg if p[4] != 65535]  # hdg: centidegrees, UINT16_MAX unknown
        trace.fact(f("heading_at_b_deg"), round(known[-1] / 100.0) % 360 if known else None, TOL_HEADING)
    if "servo" in spec.watch:
        trace.fact(f"{SCENARIO}.servo{SERVO}_seen",
                   deduped([getattr(m, f"servo{SERVO}_raw", None) for _, m in of("SERVO_OUTPUT_RAW")]))
    if "camera" in spec.watch:
        trace.fact(f("camera_feedbacks"), len(of("CAMERA_FEEDBACK")))
    if "fence" in spec.watch:
        sys_status = of("SYS_STATUS")
        trace.fact(f("fence_enabled_end"),
                   bool(sys_status and sys_status[-1][1].onboard_control_sensors_enabled & FENCE_BIT))
    if "home" in spec.watch:
        trace.fact(f("home_ne_m"), home_ne(client, geo), TOL_HOME)


def home_ne(client: Client, geo: Geometry) -> list | None:
    """HOME_POSITION asked for now, as metres north and east of the home the vehicle booted with."""
    seen = client.received.get("HOME_POSITION", 0)
    client.command(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_HOME_POSITION)
    if not client.try_wait(lambda: client.received.get("HOME_POSITION", 0) > seen, 5):
        return None
    home = client.last["HOME_POSITION"]
    return [round(v, 1) for v in geo.ne(home.latitude, home.longitude)]


BACKGROUND_HZ = 2  # every stream, slowed from the boot's 10 Hz: less for the link and the client to carry
STREAMS_US = {  # message -> interval: the mission's progress and position (heading too) at 10 Hz
    mav.MAVLINK_MSG_ID_MISSION_CURRENT: 100_000,
    mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: 100_000,
}
SERVO_STREAM_US = 100_000  # servo outputs at 10 Hz where a servo is watched: a 1 s cycle has 0.5 s halves


def boot_watched(target, streams: dict) -> Client:
    """A fresh vehicle streaming slowly but for `streams` (message id -> interval [us]), once its
    mission state and position have come."""
    client = target.boot()
    client.request_streams(BACKGROUND_HZ)
    for msg_id, interval in streams.items():
        client.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, msg_id, interval)
    client.wait(lambda: "MISSION_CURRENT" in client.last and "GLOBAL_POSITION_INT" in client.last,
                10, what="MISSION_CURRENT and position")
    return client


def run(target) -> dict[str, Trace]:
    traces = {}
    try:
        for name in in_scope():
            spec = SPECS.get(name, DEFAULT_SPEC)
            streams = dict(STREAMS_US)
            if "servo" in spec.watch:
                streams[mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW] = SERVO_STREAM_US
            client = boot_watched(target, streams)
            trace = traces[name] = Trace()
            fly(client, name, spec, trace)
    finally:
        target.close()
    return traces
