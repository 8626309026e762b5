"""The vehicle's true state as a test sees it: read from the autopilot's `--state-log`.

The autopilot writes a CSV line every 0.1 s of vehicle time (autopilot/io/state_log.py). A test
asserts on what truly happened (where the airframe is, whether it rests on the ground), not on
what the vehicle reports of itself, and waits are counted in the vehicle time of these lines, so
they mean the same at any speedup.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from firefly.autopilot.modes.numbers import ModeNumber
from firefly.sim.rigid_body import euler_from_quaternion


@dataclass(frozen=True)
class VehicleState:
    """One line of the state log. Positions are metres from the process's shared origin, NED."""
    time_s: float  # vehicle (sim) time
    north_m: float
    east_m: float
    down_m: float
    velocity_ned_m_s: tuple
    roll_deg: float
    pitch_deg: float
    yaw_deg: float
    on_ground: bool  # resting on the ground (the simulator's contact, not the land detector)
    armed: bool
    mode_number: int  # ArduCopter's custom_mode
    home_ned_m: tuple | None  # None until the vehicle has set home

    @property
    def mode(self) -> str:
        """The flight mode's ArduCopter name ("GUIDED"), or the number if Firefly has no such mode."""
        try:
            return ModeNumber(self.mode_number).name
        except ValueError:
            return str(self.mode_number)

    @property
    def altitude_m(self) -> float:
        """Height above home (above the origin before home is set), metres up."""
        home_d = self.home_ned_m[2] if self.home_ned_m else 0.0
        return home_d - self.down_m

    @property
    def distance_from_home_m(self) -> float:
        """Horizontal distance from home (from the origin before home is set)."""
        home_n, home_e = self.home_ned_m[:2] if self.home_ned_m else (0.0, 0.0)
        return math.hypot(self.north_m - home_n, self.east_m - home_e)

    @property
    def ground_speed_m_s(self) -> float:
        return math.hypot(*self.velocity_ned_m_s[:2])

    @property
    def landed(self) -> bool:
        """On the ground and disarmed: a flight that has ended."""
        return self.on_ground and not self.armed

    def __repr__(self) -> str:
        return f"<VehicleState {self}>"

    def __str__(self) -> str:
        return (f"t={self.time_s:.1f} s {self.mode} {'armed' if self.armed else 'disarmed'}"
                f"{' on ground' if self.on_ground else ''}, N {self.north_m:.2f} E {self.east_m:.2f} m, "
                f"altitude {self.altitude_m:.2f} m, {self.distance_from_home_m:.2f} m from home, "
                f"ground speed {self.ground_speed_m_s:.2f} m/s")


def parse_state(columns: list[str], line: str) -> VehicleState:
    row = dict(zip(columns, line.split(",")))
    f = {k: float(v) for k, v in row.items() if v != "" and k not in ("on_ground", "armed", "mode")}
    roll, pitch, yaw = euler_from_quaternion(f["qw"], f["qx"], f["qy"], f["qz"])
    home = (f["home_n_m"], f["home_e_m"], f["home_d_m"]) if "home_n_m" in f else None
    return VehicleState(f["time_s"], f["n_m"], f["e_m"], f["d_m"], (f["vn_m_s"], f["ve_m_s"], f["vd_m_s"]),
                        math.degrees(roll), math.degrees(pitch), math.degrees(yaw),
                        row["on_ground"] == "1", row["armed"] == "1", int(row["mode"]), home)


class StateLogReader:
    """Follows a growing state log. `new_states()` returns the states written since the last call;
    a reader made with `from_end` starts at the line being written when it first reads, so that
    each wait follows the log on its own from its own start."""

    def __init__(self, path: Path, from_end: bool = False):
        self.path = Path(path)
        self.from_end = from_end
        self._file: BinaryIO | None = None
        self._columns: list[str] | None = None
        self._partial: bytes | None = b""  # None: skip to the end of the line being written
        self.latest: VehicleState | None = None

    def _open(self) -> BinaryIO | None:
        """The log, open after its header, or None while it has none."""
        try:
            file = open(self.path, "rb")
        except FileNotFoundError:
            return None
        header = file.readline()
        if not header.endswith(b"\n"):  # not written yet: read it again next time
            file.close()
            return None
        self._file = file
        self._columns = header.decode().strip().split(",")
        if self.from_end:
            end = file.seek(0, 2)
            file.seek(end - 1)
            if file.read(1) != b"\n":  # mid-line: that line is older than this reader
                self._partial = None
        return file

    def _lines(self) -> list[bytes]:
        file = self._file if self._file is not None else self._open()
        if file is None:
            return []
        chunk = file.read()
        if not chunk:
            return []
        if self._partial is None:  # skip the rest of the line this reader started in
            cut = chunk.find(b"\n")
            if cut < 0:
                return []
            chunk, self._partial = chunk[cut + 1:], b""
        lines = (self._partial + chunk).split(b"\n")
        self._partial = lines.pop()  # an unfinished last line waits for the rest of it
        return lines

    def new_states(self) -> list[VehicleState]:
        lines = self._lines()
        columns = self._columns  # read with the header, before any line
        states = [parse_state(columns, line.decode()) for line in lines] if columns is not None else []
        if states:
            self.latest = states[-1]
        return states

    def latest_state(self) -> VehicleState | None:
        """The newest state, parsing only the newest line."""
        lines = self._lines()
        if lines and self._columns is not None:
            self.latest = parse_state(self._columns, lines[-1].decode())
        return self.latest

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
