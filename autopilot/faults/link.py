"""Ground-station link faults: a stage of the vehicle's sans-IO link (autopilot/mavlink/link.py),
between the frames received and the session, and between the frames packed and the socket.

SIM_LINK_DOWN = S cuts the link both ways for S seconds of the link clock, then sets itself back to
0 (as ArduPilot's SIM_SHOVE_TIME ends its shove); the link clock is the monotonic wall clock the I/O
edge hands in (`advance`), because the link and the GCS failsafe that watches it (FS_GCS_TIMEOUT)
both live on wall time. SIM_LINK_LOSS = P drops P % of the frames each way, drawn from the link's
own seeded generator, one draw per frame in the order they pass. The sans-IO session never knows:
it just hears nothing, as behind a dead radio. Every dropped frame is counted.
ArduPilot has no such parameter (MAVProxy's link commands and SITL's SIM_UART_LOSS, which drops
bytes on a serial port, come closest), so these two are named in its style.
"""
from __future__ import annotations

from firefly.sim.sensors import sensor_rng


class LinkFaults:
    def __init__(self, params, seed: int):
        self._rng = sensor_rng(seed, "link")
        self.dropped = {"in": 0, "out": 0}
        self._loss = 0.0  # probability of losing one frame
        self._cut_s = 0.0  # a requested outage not yet started, in link-clock seconds
        self._down_until: float | None = None  # link clock time the outage ends
        self.rebind(params)

    def rebind(self, params) -> None:
        """Follow `params` (a rebooted vehicle's, io/reboot.py); the counts go on."""
        self.params = params
        params.on_change(self._changed)
        for name in ("SIM_LINK_DOWN", "SIM_LINK_LOSS"):
            self._changed(name, params[name])

    @property
    def active(self) -> bool:
        """Whether frames need filtering at all (the link skips the calls when not)."""
        return self._loss > 0.0 or self._cut_s > 0.0 or self._down_until is not None

    @property
    def down(self) -> bool:
        return self._down_until is not None

    def _changed(self, name: str, value: float) -> None:
        if name == "SIM_LINK_LOSS":
            self._loss = value / 100.0
        elif name == "SIM_LINK_DOWN":
            self._cut_s = value  # starts at the next advance(), so this answer still goes out
            if value == 0.0:
                self._down_until = None

    def advance(self, link_s: float) -> None:
        """Start a requested outage, or end one that is over, at link-clock time `link_s`."""
        if self._cut_s > 0.0:
            self._down_until, self._cut_s = link_s + self._cut_s, 0.0
        if self._down_until is not None and link_s >= self._down_until:
            self.params.set("SIM_LINK_DOWN", 0.0)  # the outage is over

    def lose_in(self) -> bool:
        """Whether the next received frame is lost (and counted)."""
        if self._down_until is None and (self._loss <= 0.0 or self._rng.random() >= self._loss):
            return False
        self.dropped["in"] += 1
        return True

    def pass_out(self, frames: list) -> list:
        """The frames to send that get through."""
        if self._down_until is not None:
            kept = []
        elif self._loss > 0.0:
            draw, loss = self._rng.random, self._loss
            kept = [frame for frame in frames if draw() >= loss]
        else:
            return frames
        self.dropped["out"] += len(frames) - len(kept)
        return kept
