"""MAVLink 2 signing on the real process: only a client with the key commands the vehicle.

The signing ground station listens on the vehicle's --out port, so it hears everything the vehicle
sends. Intruders send from their own sockets. Whether an intruder's frame was dropped is judged
without waiting out a timeout: the signing client sends a probe command right after it, and the
vehicle answers in arrival order, so an answer to the intruder would come before the probe's ACK.
"""
from __future__ import annotations

import hashlib
import socket
import time

import pytest
from pymavlink import mavutil

from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
ARM = mav.MAV_CMD_COMPONENT_ARM_DISARM
PROBE = 31999  # a command the vehicle answers UNSUPPORTED
PASSPHRASE = "firefly-test-passphrase"
KEY = hashlib.sha256(PASSPHRASE.encode()).digest()  # what the key file's passphrase stands for


def signing_now() -> int:
    return int((time.time() - 1420070400) * 100_000)


@pytest.fixture
def key_file(tmp_path):
    path = tmp_path / "vehicle.key"
    path.write_text(PASSPHRASE + "\n")
    return path


def signing_gcs(url: str, key: bytes = KEY) -> Gcs:
    """A ground station that signs what it sends and accepts only frames signed with `key`."""
    gcs = Gcs(url)
    gcs.conn.setup_signing(key, sign_outgoing=True, link_id=1)
    return gcs


def intruder(gcs: Gcs, key: bytes | None = None):
    """Another client, same ids as the ground station, sending to the vehicle from its own socket."""
    host, port = next(iter(gcs.conn.clients))  # the vehicle's address, learnt from its frames
    conn = mavutil.mavlink_connection(f"udpout:{host}:{port}", source_system=255, source_component=190,
                                      dialect="ardupilotmega")
    if key is not None:
        conn.setup_signing(key, sign_outgoing=True, link_id=2)
    return conn


def answers_before_probe(gcs: Gcs) -> list:
    """Send the probe and return every COMMAND_ACK the vehicle sent before the probe's own."""
    gcs.mav.command_long_send(1, 1, PROBE, 0, 0, 0, 0, 0, 0, 0, 0)
    before = []
    while True:
        ack = gcs.recv("COMMAND_ACK", 5)
        assert ack is not None, "no ACK for the probe: the signing client itself was not answered"
        if ack.command == PROBE:
            return before
        before.append(ack)


def armed(gcs: Gcs) -> bool:
    hb = gcs.recv("HEARTBEAT", 5, lambda m: m.get_srcSystem() == 1)
    assert hb is not None, "no signed HEARTBEAT"
    assert hb.get_signed()
    return bool(hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED)


def test_only_a_client_with_the_key_can_arm(autopilot_factory, key_file):
    ap = autopilot_factory(extra=("--signing-key", str(key_file)))
    gcs = signing_gcs(ap.pymavlink_url)
    unsigned, wrong_key = intruder(gcs), intruder(gcs, hashlib.sha256(b"guess").digest())
    try:
        for conn in (unsigned, wrong_key):
            conn.mav.command_long_send(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
        unsigned.mav.setup_signing_send(1, 1, [0] * 32, 0)  # nor may they turn signing off
        assert answers_before_probe(gcs) == []
        assert not armed(gcs)  # still signed, still disarmed

        assert gcs.command(ARM, 1) == mav.MAV_RESULT_ACCEPTED
        assert gcs.recv("HEARTBEAT", 5, lambda m: m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED) is not None
    finally:
        unsigned.close()
        wrong_key.close()
        gcs.close()


def test_a_replayed_signed_arm_is_dropped(autopilot_factory, key_file):
    ap = autopilot_factory(extra=("--signing-key", str(key_file)))
    gcs = signing_gcs(ap.pymavlink_url)
    try:
        arm = gcs.mav.command_long_encode(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
        gcs.mav.send(arm)
        assert gcs.recv("COMMAND_ACK", 5, lambda m: m.command == ARM).result == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(ARM, 0) == mav.MAV_RESULT_ACCEPTED
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as attacker:
            attacker.sendto(bytes(arm.get_msgbuf()), next(iter(gcs.conn.clients)))
        assert answers_before_probe(gcs) == []
        assert not armed(gcs)
    finally:
        gcs.close()


def test_setup_signing_turns_signing_on_across_a_restart_and_off_again(autopilot_factory):
    first = autopilot_factory()
    gcs = Gcs(first.pymavlink_url)  # as MAVProxy's `signing setup`: send the key, then sign
    try:
        gcs.mav.setup_signing_send(1, 1, list(KEY), signing_now())
        gcs.conn.setup_signing(KEY, sign_outgoing=True, link_id=1)
        assert not armed(gcs)  # a signed heartbeat: the vehicle took the key
        unsigned = intruder(gcs)
        unsigned.mav.command_long_send(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
        unsigned.close()
        assert answers_before_probe(gcs) == []

        uptime_ms = gcs.recv("ATTITUDE", 5).time_boot_ms
        first.stop()
        autopilot_factory(port=first.port, wipe=False)  # same state dir, no --signing-key
        # A frame of the new process (its boot clock restarted), signed with the kept key and
        # past pymavlink's check that drops a known stream's frames whose timestamp went back.
        fresh = gcs.recv("ATTITUDE", 10, lambda m: m.time_boot_ms < uptime_ms)
        assert fresh is not None and fresh.get_signed()
        gcs.mav.setup_signing_send(1, 1, [0] * 32, 0)  # signed with the key: accepted, signing off
        gcs.conn.disable_signing()
        assert gcs.command(PROBE) == mav.MAV_RESULT_UNSUPPORTED  # unsigned commands are answered
        hb = gcs.recv("HEARTBEAT", 5)
        assert hb is not None and not hb.get_signed()
    finally:
        gcs.close()


def test_a_command_right_behind_setup_signing_is_judged_with_the_new_key(autopilot_factory):
    ap = autopilot_factory()
    gcs = Gcs(ap.pymavlink_url)
    try:
        plain = mavutil.mavlink.MAVLink(None, 255, 190)
        datagram = (plain.setup_signing_encode(1, 1, list(KEY), signing_now()).pack(plain)
                    + plain.command_long_encode(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0).pack(plain))
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sender:  # both in one datagram
            sender.sendto(datagram, next(iter(gcs.conn.clients)))
        gcs.conn.setup_signing(KEY, sign_outgoing=True, link_id=1)
        assert answers_before_probe(gcs) == []
        assert not armed(gcs)
    finally:
        gcs.close()
