"""Shared helpers for the unit tests: building vehicles and flying them in sim time only."""
from __future__ import annotations

import math

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import Guided
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

GCS_SYSTEM, GCS_COMPONENT = 255, 190


def ready_vehicle(boot_params: dict | None = None, **config) -> Vehicle:
    """A default vehicle that has had time to get a GPS fix and set home; with boot_params, those
    parameters set before it boots (what it makes at boot: a camera, a rangefinder)."""
    params = ParamStore()
    for name, value in (boot_params or {}).items():
        params.set(name, value)
    v = Vehicle(VehicleConfig(**config), params)
    v.run_until(0.5)
    return v


def altitude(v: Vehicle) -> float:
    """Height above home [m]."""
    return v.home_ned[2] - v.body.d_m


def fly_until(v: Vehicle, predicate, timeout_s: float, step_s: float = 0.05) -> bool:
    """Advance sim time in small chunks until predicate(v) or timeout; returns predicate(v)."""
    end = v.time_s + timeout_s
    while not predicate(v) and v.time_s < end - 1e-9:
        v.run_until(v.time_s + step_s)
    return predicate(v)


def hovering_vehicle(alt_m: float = 10.0, **config) -> Vehicle:
    """A vehicle in GUIDED, armed, settled at alt_m above home."""
    v = ready_vehicle(**config)
    assert v.set_mode(Guided.number) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.takeoff(alt_m) == Result.ACCEPTED
    settled = fly_until(v, lambda x: abs(altitude(x) - alt_m) < 0.1 and abs(x.body.vd_m_s) < 0.05,
                        30.0)
    assert settled, "takeoff did not settle"
    v.run_until(v.time_s + 1.0)
    return v


def throttle_at_mid(v: Vehicle) -> Vehicle:
    """A pilot holding the sticks centred and the throttle at mid for good (overrides that never
    lapse): ALT_HOLD and the other climb-rate modes hold the height, where SITL's idle receiver
    (throttle closed) makes them descend."""
    v.params.set("RC_OVERRIDE_TIME", -1)
    v.rc.hold_sticks(0.0, 0.0, 0.0, 0.5, v.time_s)
    return v


def body_speed(v: Vehicle) -> float:
    b = v.body
    return math.sqrt(b.vn_m_s ** 2 + b.ve_m_s ** 2 + b.vd_m_s ** 2)


# ----- MAVLink client side -------------------------------------------------------------------
def client_codec():
    return new_codec(GCS_SYSTEM, GCS_COMPONENT)


def wire(msg, codec=None):
    """Pack with a ground-station codec and decode with a fresh one, as the socket layer would,
    so the message carries its header source ids (255/190)."""
    codec = codec or client_codec()
    decoded = new_codec(0, 0).parse_buffer(msg.pack(codec))
    assert decoded is not None and len(decoded) == 1
    return decoded[0]


def command_long(command: int, *params, target_system: int = 1, confirmation: int = 0):
    p = list(params) + [0.0] * (7 - len(params))
    return wire(client_codec().command_long_encode(target_system, 1, command, confirmation, *p))


def of_type(messages, type_name: str) -> list:
    return [m for m in messages if m.get_type() == type_name]


def statustexts(messages) -> list[str]:
    out = []
    for m in of_type(messages, "STATUSTEXT"):
        text = m.text
        if isinstance(text, bytes):
            text = text.decode()
        out.append(text.rstrip("\0"))
    return out


__all__ = ["mav", "ready_vehicle", "altitude", "fly_until", "hovering_vehicle", "body_speed",
           "client_codec", "wire", "command_long", "of_type", "statustexts",
           "GCS_SYSTEM", "GCS_COMPONENT"]


class FakeSocketPort:
    """A stand-in for the vehicle's UDP socket or a TCP server: what the command line bound, no socket."""

    def __init__(self, bind, outs=()):
        self.bind, self.outs = bind, list(outs)
        self.address = bind
        self.peers = self.outs
        self.connections: list = []

    def fileno(self) -> int:
        return -1

    def filenos(self) -> list[int]:
        return []

    def close(self) -> None:
        pass


def no_sockets(monkeypatch) -> None:
    """Build vehicles from the command line without opening a socket."""
    monkeypatch.setattr("firefly.autopilot.io.udp.UdpEndpoint", FakeSocketPort)
    monkeypatch.setattr("firefly.autopilot.io.tcp.TcpServer", FakeSocketPort)
