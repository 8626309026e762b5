"""MAVProxy's own signing commands against the real process: `signing setup PASSPHRASE` sends
SETUP_SIGNING and signs from then on; the vehicle keeps the key MAVProxy derived and still takes
MAVProxy's (now signed) commands."""
from __future__ import annotations

import hashlib
import json

import pytest

from .test_mavproxy import Observer, mavproxy_factory, two_port_autopilot  # noqa: F401 - fixtures

pytestmark = pytest.mark.sitl
ARMED_FLAG = 128
PASSPHRASE = "firefly-passphrase"


def signed(msg) -> bool:
    return bool(msg.get_msgbuf()[2] & 0x01)  # the observer does not verify; it reads the flag


def test_mavproxy_signing_setup_then_arm(two_port_autopilot, mavproxy_factory):
    ap, observer_port = two_port_autopilot
    observer = Observer(observer_port)
    try:
        assert not signed(observer.gcs.heartbeat)
        mavproxy = mavproxy_factory(ap.port)
        mavproxy.wait_output(r"Detected vehicle 1", 15)
        mavproxy.send(f"signing setup {PASSPHRASE}")
        mavproxy.wait_output("Setup signing key", 10)
        start = observer.mark()
        observer.wait("HEARTBEAT", signed, 10, "a signed HEARTBEAT", start)
        kept = json.loads((ap.state_dir / "instance-0" / "signing.json").read_text())
        assert kept["setup_key"] == hashlib.sha256(PASSPHRASE.encode()).hexdigest()  # = a key file's passphrase
        mark = mavproxy.mark()
        mavproxy.send("arm throttle")
        mavproxy.wait_output(r"COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", timeout=10, start=mark)
        observer.wait("HEARTBEAT", lambda m: signed(m) and m.base_mode & ARMED_FLAG, 10, "armed", start)
    finally:
        observer.close()
