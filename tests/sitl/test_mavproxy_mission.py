"""The real MAVProxy uploads examples/square.waypoints with `wp load` and flies it as on ArduCopter.

MAVProxy is driven through its stdin and a pymavlink observer on the autopilot's second --out port
checks the vehicle independently (both helpers come from test_mavproxy.py). The observer downloads
the mission back with MISSION_REQUEST_LIST / MISSION_REQUEST_INT and compares it with the file,
then watches the flight: AUTO, MISSION_ITEM_REACHED for every item, each waypoint passed within
3 m, and the disarm after the mission's RTL within 2 m of home.
"""
from __future__ import annotations

import math
import shutil

import pytest

from .conftest import REPO
from .test_mavproxy import armed, mavproxy_factory, observer, two_port_autopilot  # noqa: F401 (fixtures)

pytestmark = pytest.mark.sitl

GUIDED, AUTO = 4, 3
NAV_WAYPOINT = 16
MAV_MISSION_TYPE_MISSION, MAV_MISSION_ACCEPTED = 0, 0
OBSERVER_SYSID, OBSERVER_COMPID = 255, 190  # tests/sitl/pymav.py's Gcs
SQUARE = REPO / "examples" / "square.waypoints"
EARTH_RADIUS_M = 6_378_137.0


def read_qgc_wpl(path) -> list[dict]:
    """The items of a "QGC WPL 110" file, independently of pymavlink's loader (MAVProxy's)."""
    lines = path.read_text().splitlines()
    assert lines[0].strip() == "QGC WPL 110"
    items = []
    for line in lines[1:]:
        if not line.strip():
            continue
        f = line.split("\t")
        assert len(f) == 12, line
        items.append({"seq": int(f[0]), "current": int(f[1]), "frame": int(f[2]), "command": int(f[3]),
                      "params": tuple(float(v) for v in f[4:8]), "lat": float(f[8]), "lon": float(f[9]),
                      "alt": float(f[10]), "autocontinue": int(f[11])})
    assert [it["seq"] for it in items] == list(range(len(items)))
    return items


def distance_m(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Horizontal distance (equirectangular: exact enough over a few hundred metres)."""
    dn = math.radians(lat2 - lat1) * EARTH_RADIUS_M
    de = math.radians(lon2 - lon1) * EARTH_RADIUS_M * math.cos(math.radians((lat1 + lat2) / 2))
    return math.hypot(dn, de)


def for_observer(m) -> bool:
    return m.target_system == OBSERVER_SYSID and m.target_component == OBSERVER_COMPID


def download_mission(observer) -> list:
    """The observer's own download: MISSION_REQUEST_LIST, then MISSION_REQUEST_INT for each seq."""
    gcs = observer.gcs
    target = (gcs.conn.target_system, gcs.conn.target_component)
    seen = observer.mark()
    gcs.mav.mission_request_list_send(*target, mission_type=MAV_MISSION_TYPE_MISSION)
    count = observer.wait("MISSION_COUNT", lambda m: for_observer(m) and m.mission_type == 0, 5,
                          "MISSION_COUNT for the observer", seen).count
    items = []
    for seq in range(count):
        seen = observer.mark()
        gcs.mav.mission_request_int_send(*target, seq, mission_type=MAV_MISSION_TYPE_MISSION)
        items.append(observer.wait("MISSION_ITEM_INT",
                                   lambda m, seq=seq: for_observer(m) and m.seq == seq and m.mission_type == 0,
                                   5, f"MISSION_ITEM_INT seq {seq}", seen))
    return items


def test_mavproxy_wp_load_then_auto_mission(two_port_autopilot, observer, mavproxy_factory, tmp_path):
    ap, _ = two_port_autopilot
    waypoints = tmp_path / "square.waypoints"
    shutil.copyfile(SQUARE, waypoints)
    planned = read_qgc_wpl(waypoints)
    n = len(planned)  # 7: home + takeoff + 4 waypoints + RTL
    square = [it for it in planned[1:] if it["command"] == NAV_WAYPOINT]
    assert len(square) == 4

    mavproxy = mavproxy_factory(ap.port)
    mavproxy.wait_output(r"Received \d+ parameters", timeout=30)  # connected, vehicle type known
    home = observer.wait("HOME_POSITION", lambda m: True, 15, "HOME_POSITION")

    # ----- upload with `wp load`: MAVProxy's own messages, then the vehicle's MISSION_ACK ---------
    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send(f"wp load {waypoints}")
    mavproxy.wait_output(rf"Loaded {n} waypoints from {waypoints}", timeout=10, start=mark)
    # mission_item_protocol.py prints this once the vehicle has requested the last item.
    mavproxy.wait_output(rf"Sent all {n} waypoints", timeout=15, start=mark)
    mavproxy.wait_output(r"Got MISSION_ACK: TYPE_MISSION: ACCEPTED", timeout=10, start=mark)
    # the transfer is MAVProxy's: the vehicle answers its link only, as ArduCopter answers a channel
    answers = ("MISSION_ACK", "MISSION_REQUEST", "MISSION_REQUEST_INT")
    assert not [m for t in answers for m in observer.of_type(t, seen) if not for_observer(m)], \
        "MAVProxy's upload was answered on the observer's link too"

    # ----- download by the observer: seq 1..n-1 are the file's items, seq 0 is the vehicle's home ----
    downloaded = download_mission(observer)
    assert len(downloaded) == n
    for item, want in zip(downloaded[1:], planned[1:]):
        # ArduCopter keeps a frame only for items stored with a location: the RTL comes back in 0.
        frame = 0 if want["command"] == 20 else want["frame"]
        assert (item.seq, item.command, item.frame, item.autocontinue) == \
            (want["seq"], want["command"], frame, want["autocontinue"]), item
        assert (item.param1, item.param2, item.param3, item.param4) == pytest.approx(want["params"]), item
        # MAVProxy converts degrees with int(deg * 1e7), truncating: 1e-7 degrees of slack.
        assert abs(item.x - round(want["lat"] * 1e7)) <= 1, item
        assert abs(item.y - round(want["lon"] * 1e7)) <= 1, item
        assert item.z == pytest.approx(want["alt"], abs=1e-3), item
    seq0 = downloaded[0]
    assert seq0.command == NAV_WAYPOINT
    assert abs(seq0.x - home.latitude) <= 1 and abs(seq0.y - home.longitude) <= 1, (seq0, home)
    assert seq0.z == pytest.approx(home.altitude / 1000.0, abs=0.01)

    # ----- fly it as a MAVProxy user does on ArduCopter ----------------------------------------------
    # Arming is refused in AUTO, so arm in GUIDED; then `mode auto`. On the ground ArduCopter's AUTO
    # only starts the mission once "auto armed": by MAV_CMD_MISSION_START (300), or on a real Copter a
    # raised throttle stick (`rc 3 1500`), which this emulator does not model. MAVProxy has no
    # `wp start`; its `long` command (mavproxy_cmdlong.py) sends a COMMAND_LONG
    # by name, so `long MISSION_START` follows `mode auto` at once: the vehicle disarms after
    # DISARM_DELAY (10 s sim, 1 s wall at speedup 10) on the ground while nothing asks it to climb.
    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send("mode guided")
    observer.wait("HEARTBEAT", lambda m: m.custom_mode == GUIDED, 10, "GUIDED (custom_mode 4)", seen)
    mavproxy.wait_output(r"COMMAND_ACK: DO_SET_MODE: ACCEPTED", timeout=10, start=mark)

    mark, seen = mavproxy.mark(), observer.mark()
    mavproxy.send("arm throttle")
    observer.wait("HEARTBEAT", armed, 10, "armed flag (base_mode & 128)", seen)
    mavproxy.send("mode auto")
    mavproxy.send("long MISSION_START")
    flight = seen
    hb = observer.wait("HEARTBEAT", lambda m: m.custom_mode == AUTO, 10, "AUTO (custom_mode 3)", seen)
    assert armed(hb)
    in_auto = observer.mark()  # disarmed HEARTBEATs sent before the arm are behind this mark
    mavproxy.wait_output(r"COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", timeout=10, start=mark)
    mavproxy.wait_output(r"COMMAND_ACK: MISSION_START: ACCEPTED", timeout=10, start=mark)
    observer.wait("GLOBAL_POSITION_INT", lambda m: m.relative_alt >= 14_000, 30,
                  "climb to the takeoff item's 15 m", flight)

    # ----- the mission to its end: every item reached, in order, then disarmed after the RTL --------
    def reached():
        seqs = [m.seq for m in observer.of_type("MISSION_ITEM_REACHED", flight)]
        return seqs if len(seqs) >= n - 1 else None
    seqs = observer.until(reached, 90, f"MISSION_ITEM_REACHED for seq 1..{n - 1}")
    assert seqs == list(range(1, n)), seqs
    hb = observer.wait("HEARTBEAT", lambda m: not armed(m), 30, "disarm after the mission's RTL", in_auto)
    assert hb.custom_mode == AUTO

    positions = [m for m in observer.of_type("GLOBAL_POSITION_INT", flight) if m.get_srcComponent() == 1]
    for k, wp in enumerate(square):
        closest = min(math.hypot(distance_m(p.lat * 1e-7, p.lon * 1e-7, wp["lat"], wp["lon"]),
                                 p.relative_alt / 1000.0 - wp["alt"]) for p in positions)
        assert closest < 3.0, f"waypoint {k + 1} ({wp['lat']}, {wp['lon']}, {wp['alt']} m): closest {closest:.2f} m"

    later = observer.mark()
    last = observer.wait("GLOBAL_POSITION_INT", lambda m: True, 5, "position after disarm", later)
    off_home = distance_m(last.lat * 1e-7, last.lon * 1e-7, home.latitude * 1e-7, home.longitude * 1e-7)
    assert off_home < 2.0, f"disarmed {off_home:.2f} m from home"
    assert abs(last.relative_alt) < 500
    mavproxy.wait_output(r"\bDISARMED\b", timeout=10, start=mark)
