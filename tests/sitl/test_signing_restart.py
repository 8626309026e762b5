"""MAVLink 2 signing across kill -9 and restart, on the real process: the kept timestamp stays
near the clock, a signed command captured before the kill is refused after it, and a client
with a correct clock is answered.

Before the high-water mark (autopilot/mavlink/signing.py), each restart moved the timestamp about
a minute ahead of the clock (ArduPilot's rule: a minute past the timestamp saved every 30 s),
and a captured signed ARM was executed again after a kill -9 (3 of 3 tries).
"""
from __future__ import annotations

import socket
import time

import pytest
from pymavlink import mavutil

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.signing import RESERVE, TICKS_PER_S, signing_time

from .test_signing import ARM, KEY, PROBE, answers_before_probe, armed, key_file, signing_gcs  # noqa: F401

pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # signing timestamps are judged against the wall clock
mav = mavutil.mavlink
RESTARTS = 2
SLACK = TICKS_PER_S // 5  # the frame's flight and the test's own reading of the clock


def signing_now() -> int:
    return signing_time(time.time())


def stamp(msg) -> int:
    """The signing timestamp of a received signed frame."""
    return int.from_bytes(bytes(msg.get_msgbuf())[-12:-6], "little")


def correct_clock_probe(address, wait_s: float):
    """A PROBE from a client that signs with the wall clock, on a stream new to the vehicle, and
    has heard nothing from it (so has not taken up its timestamp); the COMMAND_ACK the vehicle
    sends back to that client (the link that asked) within `wait_s`, or None."""
    codec = new_codec(255, 190)  # MAVLink 2, which alone can be signed
    codec.signing.secret_key, codec.signing.sign_outgoing = KEY, True
    codec.signing.link_id, codec.signing.timestamp = 7, signing_now()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as client:
        client.sendto(bytes(codec.command_long_encode(1, 1, PROBE, 0, 0, 0, 0, 0, 0, 0, 0).pack(codec)), address)
        deadline = time.monotonic() + wait_s
        reader = new_codec(255, 190)
        while (left := deadline - time.monotonic()) > 0:
            client.settimeout(left)
            try:
                data = client.recv(65535)
            except TimeoutError:
                return None
            for msg in reader.parse_buffer(data) or []:
                if msg.get_type() == "COMMAND_ACK" and msg.command == PROBE:
                    return msg
    return None


def test_kill_9_keeps_the_timestamp_near_the_clock_and_refuses_a_captured_command(autopilot_factory, key_file):
    extra = ("--signing-key", str(key_file))
    ap = autopilot_factory(extra=extra)
    gcs = signing_gcs(ap.pymavlink_url)
    try:
        arm = gcs.mav.command_long_encode(1, 1, ARM, 0, 1, 0, 0, 0, 0, 0, 0)
        gcs.mav.send(arm)
        assert gcs.recv("COMMAND_ACK", 5, lambda m: m.command == ARM).result == mav.MAV_RESULT_ACCEPTED
        captured = bytes(arm.get_msgbuf())  # as an eavesdropper has it
        assert gcs.command(ARM, 0) == mav.MAV_RESULT_ACCEPTED
        ahead = []
        for _ in range(RESTARTS):
            gcs.close()
            ap.process.kill()  # kill -9: no exit handler saves anything
            ap.process.wait()
            ap = autopilot_factory(port=ap.port, wipe=False, extra=extra)
            gcs = signing_gcs(ap.pymavlink_url)
            hb = gcs.recv("HEARTBEAT", 10, lambda m: m.get_signed())
            assert hb is not None, "no signed HEARTBEAT after the restart"
            ahead.append(stamp(hb) - signing_now())
            vehicle = next(iter(gcs.conn.clients))
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as attacker:
                attacker.sendto(captured, vehicle)  # the replay ...
            assert answers_before_probe(gcs) == []  # ... is not answered ...
            assert not armed(gcs)  # ... nor executed
            # A client with a correct clock is answered once the clock has passed the kept mark:
            # at once after a restart slower than RESERVE, within RESERVE after a quicker one
            # (its frames are stamped below the mark until then). It resends, as clients do.
            restarted, ack = time.monotonic(), None
            while ack is None and time.monotonic() - restarted < RESERVE / TICKS_PER_S + 2.0:
                ack = correct_clock_probe(vehicle, 0.25)
            assert ack is not None and ack.result == mav.MAV_RESULT_UNSUPPORTED, "a correct clock was refused"
        # ArduPilot's rule would be a minute ahead after one restart, two after two
        assert max(ahead) <= RESERVE + SLACK, [a / TICKS_PER_S for a in ahead]
    finally:
        gcs.close()
