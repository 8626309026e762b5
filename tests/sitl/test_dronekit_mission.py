"""DroneKit's vehicle API uploads, downloads and flies a mission on Firefly (issue 29).

The script is written as DroneKit's own `mission_basic.py` example is: `connect(..., wait_ready=True)`
to SITL's TCP SERIAL0 (or the UDP port SITL sends to), `commands.clear()`, `add(Command(...))`,
`upload()`, `download()` and `wait_ready()`, arm in GUIDED and `simple_takeoff`, then
`commands.next = 0` and AUTO, watching `commands.next` until the vehicle lands and disarms.
DroneKit 2.9 runs here through tests/sitl/dronekit_compat.py (the `collections.MutableMapping`
alias Python 3.10 removed).

The vehicle is taken off in GUIDED first, as the example does, because ArduCopter's AUTO does not
start a takeoff from the ground until the throttle is raised (`Copter::update_auto_armed` wants
`!ap.throttle_zero`): with no RC the script's AUTO sits at "Mission: 1 Takeoff" and the vehicle
disarms on the ground, on ArduCopter and on Firefly alike. The mission's takeoff (10 m) is above
the GUIDED one (5 m) so that item flies for a while and `commands.next` shows it.

The same script against the reference ArduCopter (4.7.0-dev 90700977, instance 1, speedup 10,
DroneKit on `udpin`) saw MISSION_CURRENT 1, 2, 3, 4, 5 and 0 after the disarm; the items
downloaded equal the uploaded ones (MISSION_ITEM's float32 coordinates) except the RTL's frame:
ArduCopter gave frame 0 where Firefly gave back the uploaded 3, fixed with this test; both vehicles say
"got MISSION_REQUEST; use MISSION_REQUEST_INT!" and "got MISSION_ITEM; GCS should send
MISSION_ITEM_INT" at upload, as DroneKit speaks the float protocol. Sim seconds from AUTO to the
disarm after RTL (GUIDED takeoff to 4.75 m, mission takeoff to 10 m, three 22 m legs, RTL from
22 m): ArduCopter 69.8 s, Firefly 65.8 s (earlier runs with a 9.5 m GUIDED takeoff: 65.2 and
62.8); ArduCopter landed 0.03 m from home, Firefly on it.
"""
from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest
from pymavlink import mavutil

from .conftest import free_udp_port  # noqa: F401 - the tests' names
from .dronekit_compat import Command, VehicleMode, connect
from .test_links import free_tcp_port

pytestmark = pytest.mark.sitl

mav = mavutil.mavlink
RELATIVE = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT
LEG_DEG = 0.0002  # about 22 m of latitude or longitude
GUIDED_TAKEOFF_M = 5.0
MISSION_ALT_M = 10.0
# Sim seconds from AUTO to the disarm: ArduCopter took 69.8 and Firefly 65.8; a mission that stalls
# or loiters somewhere takes far longer.
MISSION_SIM_S = 90.0
WALL_S = 120.0  # wall budget per wait: the vehicle runs at 10x, the machine may be busy


class Watch:
    """What the script's message listeners saw, and a wait on it that wakes on every message.

    DroneKit calls listeners on its own thread after it has updated its attributes, so a predicate
    over `vehicle.armed` or `vehicle.location` is fresh when a message wakes the wait."""

    def __init__(self, vehicle):
        self.vehicle = vehicle
        self.boot_ms = 0
        self.currents: list[int] = []  # MISSION_CURRENT's seq each time it changed
        self.texts: list[str] = []
        self._cond = threading.Condition()
        vehicle.add_message_listener("*", self._on_message)

    def _on_message(self, _vehicle, name, msg):
        with self._cond:
            if name == "SYSTEM_TIME":
                self.boot_ms = msg.time_boot_ms
            elif name == "MISSION_CURRENT" and (not self.currents or self.currents[-1] != msg.seq):
                self.currents.append(msg.seq)
            elif name == "STATUSTEXT":
                self.texts.append(msg.text)
            self._cond.notify_all()

    def until(self, predicate, what: str, timeout: float = WALL_S):
        with self._cond:
            if not self._cond.wait_for(predicate, timeout):
                raise AssertionError(f"timed out after {timeout:g} s waiting for {what}; "
                                     f"MISSION_CURRENT {self.currents}, texts {self.texts[-8:]}")

    def sim_s(self) -> float:
        with self._cond:
            return self.boot_ms / 1000.0


def item(command: int, lat: float = 0.0, lon: float = 0.0, alt: float = 0.0) -> Command:
    return Command(0, 0, 0, RELATIVE, command, 0, 0, 0, 0, 0, 0, lat, lon, alt)


def as_float32(x: float) -> float:
    """What a float survives MISSION_ITEM (float32 x, y, z) as."""
    return float(np.float32(x))


def fields(cmd: Command) -> tuple:
    return (cmd.command, cmd.frame, cmd.param1, cmd.param2, cmd.param3, cmd.param4, cmd.x, cmd.y, cmd.z)


def metres(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    north = (lat2 - lat1) * 111_319.5
    east = (lon2 - lon1) * 111_319.5 * math.cos(math.radians(lat1))
    return math.hypot(north, east)


@pytest.fixture(params=["tcp", "udp"])
def dronekit_url(request, autopilot_factory):
    """Where a DroneKit user connects: SITL's TCP SERIAL0, or udpin on the port it sends to."""
    if request.param == "tcp":
        port = free_tcp_port()
        autopilot_factory("10", ("--serial0", f"tcp:127.0.0.1:{port}"))
        return f"tcp:127.0.0.1:{port}"
    ap = autopilot_factory("10")
    return f"udpin:127.0.0.1:{ap.port}"


def connect_when_listening(url: str, timeout: float = 30.0):
    """DroneKit's `connect`, tried again while the autopilot's TCP port is not yet listening (as a
    user's script is started again); pymavlink's own few retries may come too soon."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            return connect(url, wait_ready=True, heartbeat_timeout=30)
        except ConnectionRefusedError:
            if time.monotonic() > deadline:
                raise


def test_dronekit_uploads_downloads_and_flies_a_mission(dronekit_url):
    vehicle = connect_when_listening(dronekit_url)
    try:
        fly_mission(vehicle, Watch(vehicle))
    finally:
        vehicle.close()


def fly_mission(vehicle, watch: Watch) -> None:
    cmds = vehicle.commands
    cmds.download()
    cmds.wait_ready()
    home = vehicle.home_location
    assert home is not None, "DroneKit got no home from the mission download"

    cmds.clear()
    uploaded = [
        item(mav.MAV_CMD_NAV_TAKEOFF, alt=MISSION_ALT_M),
        item(mav.MAV_CMD_NAV_WAYPOINT, home.lat + LEG_DEG, home.lon, MISSION_ALT_M),
        item(mav.MAV_CMD_NAV_WAYPOINT, home.lat + LEG_DEG, home.lon + LEG_DEG, MISSION_ALT_M),
        item(mav.MAV_CMD_NAV_WAYPOINT, home.lat, home.lon + LEG_DEG, MISSION_ALT_M),
        item(mav.MAV_CMD_NAV_RETURN_TO_LAUNCH),
    ]
    for cmd in uploaded:
        cmds.add(cmd)
    cmds.upload(timeout=30)
    watch.until(lambda: "Flight plan received" in watch.texts, "the upload's text")  # may follow the ACK

    cmds.download()
    cmds.wait_ready()
    downloaded = [fields(c) for c in cmds]
    expected = [tuple(as_float32(v) if i >= 6 else v for i, v in enumerate(fields(c))) for c in uploaded]
    # ArduCopter keeps a frame only for items stored with a location: the RTL comes back in frame 0.
    expected[-1] = (mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, mav.MAV_FRAME_GLOBAL, *expected[-1][2:])
    assert downloaded == expected, (downloaded, expected)
    assert cmds.count == len(uploaded)

    watch.until(lambda: vehicle.is_armable, "armable")
    vehicle.mode = VehicleMode("GUIDED")
    watch.until(lambda: vehicle.mode.name == "GUIDED", "GUIDED")
    vehicle.armed = True
    watch.until(lambda: vehicle.armed, "armed")
    vehicle.simple_takeoff(GUIDED_TAKEOFF_M)
    watch.until(lambda: vehicle.location.global_relative_frame.alt >= 0.95 * GUIDED_TAKEOFF_M,
                f"the GUIDED takeoff to {GUIDED_TAKEOFF_M:g} m")

    cmds.next = 0
    vehicle.mode = VehicleMode("AUTO")
    watch.until(lambda: vehicle.mode.name == "AUTO", "AUTO")
    started_s = watch.sim_s()
    nexts = []

    def landed_and_disarmed() -> bool:
        if not nexts or nexts[-1] != cmds.next:
            nexts.append(cmds.next)
        return not vehicle.armed

    watch.until(landed_and_disarmed, "the mission to end with the vehicle landed and disarmed")
    flown_s = watch.sim_s() - started_s
    # The reset to 0 comes with the next MISSION_CURRENT, which a busy machine can deliver after
    # the wait above has woken on the HEARTBEAT that showed the disarm.
    watch.until(lambda: watch.currents[-1] == 0, "MISSION_CURRENT 0 after the disarm", timeout=10)

    # Every item was current in turn; ArduCopter sets the mission back to 0 when it disarms.
    flown = [seq for seq in watch.currents if seq]
    assert 1 in flown and flown[flown.index(1):] == [1, 2, 3, 4, 5], watch.currents
    assert watch.currents[-1] == 0
    assert [n for n in nexts if n] == [1, 2, 3, 4, 5], nexts  # as the user's script reads it
    for text in ("Mission: 1 Takeoff", "Reached command #2", "Reached command #4", "Mission: 5 RTL"):
        assert text in watch.texts
    assert flown_s < MISSION_SIM_S, f"the mission took {flown_s:.1f} sim s"

    end = vehicle.location.global_relative_frame
    assert abs(end.alt) < 0.5
    assert metres(home.lat, home.lon, end.lat, end.lon) < 2.0


# A Mission Planner `.waypoints` file (QGC WPL 110): line 0 is home, then one item a line, tab
# separated: seq, current, frame, command, param1..4, x (lat), y (lon), z (alt), autocontinue.
WAYPOINTS = """QGC WPL 110
0\t1\t0\t16\t0\t0\t0\t0\t-35.363261\t149.165230\t584.000000\t1
1\t0\t3\t22\t0\t0\t0\t0\t0\t0\t15\t1
2\t0\t3\t16\t2\t0\t0\t0\t-35.362900\t149.165230\t15\t1
3\t0\t3\t178\t0\t3\t-1\t0\t0\t0\t0\t1
4\t0\t3\t82\t0\t0\t0\t0\t-35.362900\t149.165600\t20\t1
5\t0\t3\t17\t0\t0\t0\t0\t-35.363261\t149.165600\t20\t1
6\t0\t0\t20\t0\t0\t0\t0\t0\t0\t0\t1
"""


def read_waypoints(text: str) -> list[Command]:
    """Commands from a `.waypoints` file as DroneKit's mission_import_export example reads one,
    without its home line: the vehicle keeps its own home at seq 0."""
    lines = text.splitlines()
    assert lines[0].startswith("QGC WPL 110")
    commands = []
    for line in lines[2:]:
        f = line.split("\t")
        commands.append(Command(0, 0, 0, int(f[2]), int(f[3]), int(f[1]), int(f[11]),
                                *(float(v) for v in f[4:11])))
    return commands


def write_waypoints(home, commands) -> str:
    """The example's export: home as line 0, then the downloaded items."""
    rows = [f"0\t1\t0\t16\t0\t0\t0\t0\t{home.lat}\t{home.lon}\t{home.alt}\t1"]
    rows += ["\t".join(str(v) for v in (c.seq, c.current, c.frame, c.command, c.param1, c.param2, c.param3,
                                         c.param4, c.x, c.y, c.z, c.autocontinue)) for c in commands]
    return "QGC WPL 110\n" + "\n".join(rows) + "\n"


def test_a_waypoints_file_goes_up_and_comes_back_through_dronekit(dronekit_url):
    """Import, upload, download, export: passed unchanged against the reference ArduCopter
    (instance 1, udpin), DO_CHANGE_SPEED's frame 0 included."""
    vehicle = connect_when_listening(dronekit_url)
    try:
        watch = Watch(vehicle)
        cmds = vehicle.commands
        cmds.download()
        cmds.wait_ready()
        cmds.clear()
        imported = read_waypoints(WAYPOINTS)
        for cmd in imported:
            cmds.add(cmd)
        cmds.upload(timeout=30)
        watch.until(lambda: "Flight plan received" in watch.texts, "the upload's text")
        cmds.download()
        cmds.wait_ready()
        exported = write_waypoints(vehicle.home_location, list(cmds))
    finally:
        vehicle.close()
    again = read_waypoints(exported)
    assert [c.seq for c in cmds] == [1, 2, 3, 4, 5, 6]
    expected = [tuple(as_float32(v) if i >= 6 else v for i, v in enumerate(fields(c))) for c in imported]
    # ArduCopter keeps a frame only for items stored with a location: DO_CHANGE_SPEED comes back in 0.
    expected[2] = (mav.MAV_CMD_DO_CHANGE_SPEED, mav.MAV_FRAME_GLOBAL, *expected[2][2:])
    assert [fields(c) for c in again] == expected
