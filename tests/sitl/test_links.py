"""Links as ArduPilot SITL's serial ports: TCP 5760 (SERIAL0) for MAVProxy, DroneKit-style
scripts and MAVSDK; routing between links; answers to the link that asked.

ArduPilot SITL serves its first serial port on TCP 5760 + 10 * instance, and most tutorials
connect there. Its GCS_MAVLink routing forwards a message to the links where its target was
heard (broadcasts to every link heard from), so a companion and a ground station on two links
see each other. Measured on ArduCopter SITL with two links: a listener that never sent anything
got only HEARTBEATs; once it had spoken it got the PARAM_VALUE of a parameter the other link
set, never the other link's COMMAND_ACKs or the PARAM_VALUE answering its read.
"""
from __future__ import annotations

import asyncio
import re
import socket
import subprocess
import sys
import time

import pytest
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.groundstation.flight.reference_flight import connect
from firefly.groundstation.flight.vehicle_link import first

from .conftest import REPO, free_udp_port
from .pymav import GUIDED, Gcs, mav
from .test_mavproxy import Observer, mavproxy_factory  # noqa: F401 - a fixture

pytestmark = pytest.mark.sitl


def free_tcp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def tcp_autopilot(autopilot_factory):
    """An autopilot serving SERIAL0 on a free TCP port (as SITL's tcp:5760), and its --out port."""
    port = free_tcp_port()
    ap = autopilot_factory("10", ("--serial0", f"tcp:127.0.0.1:{port}"))
    ap.tcp_port = port
    return ap


def connect_tcp(port: int, timeout: float = 15.0) -> Gcs:
    """A DroneKit-style connection: `tcp:HOST:PORT`, retried until the server takes it."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            return Gcs(f"tcp:127.0.0.1:{port}", timeout=timeout)
        except (ConnectionRefusedError, OSError):
            if time.monotonic() > deadline:
                raise


def test_a_dronekit_style_script_flies_over_tcp(tcp_autopilot):
    gcs = connect_tcp(tcp_autopilot.tcp_port)
    try:
        assert gcs.heartbeat.get_srcSystem() == 1 and gcs.heartbeat.autopilot == mav.MAV_AUTOPILOT_ARDUPILOTMEGA
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 5) == mav.MAV_RESULT_ACCEPTED
        up = gcs.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > 4500)
        assert up is not None, "never climbed past 4.5 m"
    finally:
        gcs.close()


def test_mavproxy_connects_over_tcp(tcp_autopilot, mavproxy_factory):
    observer = Observer(tcp_autopilot.port)
    try:
        mavproxy = mavproxy_factory(f"tcp:127.0.0.1:{tcp_autopilot.tcp_port}")
        mavproxy.wait_output(r"Received \d+ parameters", timeout=60)
        mark = mavproxy.mark()
        mavproxy.send("mode guided")
        mavproxy.wait_output(r"COMMAND_ACK: DO_SET_MODE: ACCEPTED", timeout=10, start=mark)
        mavproxy.send("arm throttle")
        mavproxy.wait_output(r"COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", timeout=10, start=mark)
        observer.wait("HEARTBEAT", lambda m: m.base_mode & 128, 10, "an armed HEARTBEAT on the UDP link")
        assert not observer.of_type("COMMAND_ACK"), "MAVProxy's answers went to the observer's link too"
    finally:
        observer.close()


async def test_mavsdk_connects_over_tcp(tcp_autopilot):
    mavsdk, system = await connect(f"tcpout://127.0.0.1:{tcp_autopilot.tcp_port}")
    try:
        telemetry, action = TelemetryAsync(system), ActionAsync(system)
        await first(telemetry.subscribe_health(), lambda h: h.is_armable, 20, "armable")
        await action.arm()
        assert await first(telemetry.subscribe_armed(), bool, 10, "armed")
    finally:
        mavsdk.destroy()


def test_serial0_is_tcp_5760_plus_10_per_instance_and_a_taken_port_steps_aside(tmp_path):
    """Two processes started with the same options both run: the second takes the next port."""
    def start(name: str) -> subprocess.Popen:
        return subprocess.Popen(
            [sys.executable, "-m", "firefly.autopilot", "--instance", "17", "--speedup", "1", "--duration", "600",
             "--out", f"udp:127.0.0.1:{free_udp_port()}", "--state-dir", str(tmp_path / name), "--wipe"],
            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first_process = start("a")
    try:
        banner = first_process.stdout.readline()
        port = int(re.search(r"tcp:0\.0\.0\.0:(\d+)", banner).group(1))
        assert port in range(5760 + 170, 5760 + 170 + 200, 10), banner
        second = start("b")
        try:
            second_banner = second.stdout.readline()
            second_port = int(re.search(r"tcp:0\.0\.0\.0:(\d+)", second_banner).group(1))
            assert second_port > port and (second_port - port) % 10 == 0, second_banner
            gcs = connect_tcp(second_port)
            assert gcs.heartbeat.get_srcSystem() == 18
            gcs.close()
        finally:
            second.kill()
            _, said = second.communicate()
        assert f"tcp:{port} in use: tcp:" in said, said
    finally:
        first_process.kill()
        first_process.communicate()


def test_a_companion_and_a_ground_station_on_two_links_see_each_other(tcp_autopilot):
    gcs = Gcs(tcp_autopilot.pymavlink_url)
    companion = connect_tcp(tcp_autopilot.tcp_port)
    companion.conn.mav.srcSystem, companion.conn.mav.srcComponent = 1, mav.MAV_COMP_ID_ONBOARD_COMPUTER
    try:
        # routes are learned from what each link sends (a link nobody spoke on gets nothing forwarded)
        gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        def companion_heartbeat():
            companion.conn.mav.heartbeat_send(mav.MAV_TYPE_ONBOARD_CONTROLLER, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        seen = None
        for _ in range(20):  # the companion beats at 1 Hz, as one does
            companion_heartbeat()
            seen = gcs.recv("HEARTBEAT", 1.0, lambda m: m.get_srcComponent() == mav.MAV_COMP_ID_ONBOARD_COMPUTER)
            if seen is not None:
                break
        assert seen is not None and seen.type == mav.MAV_TYPE_ONBOARD_CONTROLLER, "the GCS never saw the companion"
        gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        assert companion.recv("HEARTBEAT", 5, lambda m: m.get_srcSystem() == 255) is not None, \
            "the companion never saw the GCS"
        # a command for the companion reaches it, and the vehicle does not answer it for it
        gcs.mav.command_long_send(1, mav.MAV_COMP_ID_ONBOARD_COMPUTER, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                  mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
        asked = companion.recv("COMMAND_LONG", 5, lambda m: m.target_component == mav.MAV_COMP_ID_ONBOARD_COMPUTER)
        assert asked is not None and asked.get_srcSystem() == 255
        companion.mav.command_ack_send(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAV_RESULT_UNSUPPORTED, 0, 0, 255, 190)
        ack = gcs.recv("COMMAND_ACK", 5, lambda m: m.command == mav.MAV_CMD_REQUEST_MESSAGE)
        assert ack is not None and ack.get_srcComponent() == mav.MAV_COMP_ID_ONBOARD_COMPUTER, \
            "the first ACK the GCS gets is the companion's, not the vehicle's"
    finally:
        companion.close()
        gcs.close()


def test_answers_go_to_the_link_that_asked(autopilot_factory):
    """Three --out links: the asker, a listener that has spoken, a listener that never did."""
    asker_port, spoken_port, silent_port = (free_udp_port() for _ in range(3))
    ap = autopilot_factory("10", ("--out", f"udp:127.0.0.1:{spoken_port}", "--out", f"udp:127.0.0.1:{silent_port}"),
                           port=asker_port)
    asker = Gcs(f"udpin:127.0.0.1:{asker_port}")
    spoken, silent = Observer(spoken_port), Observer(silent_port)
    spoken.gcs.mav.srcSystem = 254  # a second ground station: a route of its own (routes go by system id)
    try:
        spoken.gcs.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        asker.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        mark_spoken, mark_silent = spoken.mark(), silent.mark()
        assert asker.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        asker.mav.param_request_read_send(1, 1, b"WPNAV_ACCEL", -1)
        assert asker.recv("PARAM_VALUE", 5, lambda m: m.param_id == "WPNAV_ACCEL") is not None
        asker.mav.param_set_send(1, 1, b"WPNAV_SPEED", 777.0, mav.MAV_PARAM_TYPE_REAL32)
        assert asker.recv("PARAM_VALUE", 5, lambda m: m.param_id == "WPNAV_SPEED") is not None
        spoken.wait("PARAM_VALUE", lambda m: m.param_id == "WPNAV_SPEED", 5,
                    "the value another link set, on a link that has spoken", start=mark_spoken)
        # the asker's heartbeat reaches the one that has spoken (routing), not the silent one
        spoken.until(lambda: [m for m in spoken.messages if m.get_type() == "HEARTBEAT" and m.get_srcSystem() == 255],
                     5, "the asker's HEARTBEAT routed to the link that has spoken")
        asker.command(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION)  # one more round trip
        for observer, mark in ((spoken, mark_spoken), (silent, mark_silent)):
            got = [m.get_type() for m in observer.messages[mark:]]
            assert "COMMAND_ACK" not in got and "AUTOPILOT_VERSION" not in got
            assert not [m for m in observer.messages[mark:] if m.get_type() == "PARAM_VALUE"
                        and m.param_id == "WPNAV_ACCEL"], "the answer to a read is the reader's"
        assert not silent.of_type("PARAM_VALUE", mark_silent), "a link that never spoke hears no parameter values"
        assert not [m for m in silent.messages if m.get_srcSystem() != 1], "nothing forwarded to a silent link"
        assert silent.gcs.conn.mav_loss == 0 and spoken.gcs.conn.mav_loss == 0, \
            "each link numbers its own frames: no gaps where another link was answered"
    finally:
        asker.close()
        spoken.close()
        silent.close()


def test_a_tcpclient_port_connects_out_and_is_a_link(autopilot_factory):
    """--serial1 tcpclient:HOST:PORT, as SITL's: the vehicle connects to a waiting server (a
    ground station listening, as `mavproxy.py --master tcpin:`) and is answered over it."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as server:
        server.bind(("127.0.0.1", 0))
        server.listen(1)
        server.settimeout(20)
        autopilot_factory("10", ("--serial1", f"tcpclient:127.0.0.1:{server.getsockname()[1]}"))
        connection, _ = server.accept()
    codec = mav.MAVLink(None, srcSystem=255, srcComponent=190)
    with connection:
        connection.settimeout(10)
        connection.sendall(codec.command_long_encode(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                                     mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0).pack(codec))
        seen: set[str] = set()
        deadline = time.monotonic() + 10
        while not {"HEARTBEAT", "COMMAND_ACK", "AUTOPILOT_VERSION"} <= seen and time.monotonic() < deadline:
            seen.update(m.get_type() for m in codec.parse_buffer(connection.recv(65536)) or [])
    assert {"HEARTBEAT", "COMMAND_ACK", "AUTOPILOT_VERSION"} <= seen, seen
