"""Ground-station link faults, applied at the I/O edge between the UDP endpoint and the session.

SIM_LINK_DOWN = S cuts the link both ways for S wall-clock seconds, then sets itself back to 0
(as ArduPilot's SIM_SHOVE_TIME ends its shove); wall time, because the link and the GCS failsafe
that watches it (FS_GCS_TIMEOUT) both live on the wall clock. SIM_LINK_LOSS = P drops P % of the
frames each way, drawn from the link's own seeded generator. The sans-IO session never knows:
it just hears nothing, as behind a dead radio. Every dropped frame is counted.
ArduPilot has no such parameter (MAVProxy's link commands and SITL's SIM_UART_LOSS, which drops
bytes on a serial port, come closest), so these two are named in its style.
"""
from __future__ import annotations

from sim.sensors import sensor_rng


class LinkFaults:
    def __init__(self, params, seed: int):
        self.params = params
        self._rng = sensor_rng(seed, "link")
        self.dropped = {"in": 0, "out": 0}
        self._loss = 0.0  # probability of losing one frame
        self._cut_s = 0.0  # a requested outage not yet started, in wall seconds
        self._down_until: float | None = None  # wall clock time the outage ends
        params.on_change(self._changed)
        for name in ("SIM_LINK_DOWN", "SIM_LINK_LOSS"):
            self._changed(name, params[name])

    @property
    def active(self) -> bool:
        """Whether frames need filtering at all (the runner skips the calls when not)."""
        return self._loss > 0.0 or self._cut_s > 0.0 or self._down_until is not None

    @property
    def down(self) -> bool:
        return self._down_until is not None

    def _changed(self, name: str, value: float) -> None:
        if name == "SIM_LINK_LOSS":
            self._loss = value / 100.0
        elif name == "SIM_LINK_DOWN":
            self._cut_s = value  # starts with the next frames received, so this answer still goes out
            if value == 0.0:
                self._down_until = None

    def admit(self, messages: list, wall_s: float) -> list:
        """The received messages that got through."""
        if self._cut_s > 0.0:
            self._down_until, self._cut_s = wall_s + self._cut_s, 0.0
        if self._down_until is not None and wall_s >= self._down_until:
            self.params.set("SIM_LINK_DOWN", 0.0)  # the outage is over
        return self._filter(messages, "in")

    def pass_out(self, frames: list) -> list:
        """The frames to send that get through."""
        return self._filter(frames, "out")

    def _filter(self, items: list, way: str) -> list:
        if self._down_until is not None:
            kept = []
        elif self._loss > 0.0:
            draw, loss = self._rng.random, self._loss
            kept = [item for item in items if draw() >= loss]
        else:
            return items
        self.dropped[way] += len(items) - len(kept)
        return kept
