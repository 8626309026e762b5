"""`--state-log`: the vehicle's true state as CSV, one line every 0.1 s of sim time, and one more
whenever the vehicle answers a client (io/runner.py), written before the answer leaves.

What truly happened, not what the vehicle believes: the simulator's body state (metres from the
shared origin, NED), whether it rests on the ground, and beside it what the autopilot holds
(armed, flight-mode number, home). The determinism checks compare these files byte for byte (of
runs no client talks to), and
the pytest plugin (autopilot/testing) reads them to wait in vehicle time; the file is line
buffered so that a reader sees each line as it is written. time_s is the process's sim time,
which goes on across a reboot (io/reboot.py) while the rebooted vehicle's own clock starts again.
"""
from __future__ import annotations

from firefly.sim.rigid_body import BodyState

COLUMNS = ("time_s", *BodyState._fields, "on_ground", "armed", "mode", "home_n_m", "home_e_m", "home_d_m")
HEADER = ",".join(COLUMNS) + "\n"


def open_state_log(path):
    log = open(path, "w", buffering=1)
    log.write(HEADER)
    return log


def state_line(vehicle) -> str:
    sim = vehicle.sim
    home = vehicle.home_ned
    return (f"{vehicle.powered_on_at_s + sim.time_s!r}," + ",".join(repr(x) for x in sim.state.body)
            + f",{int(sim.state.on_ground)},{int(vehicle.armed)},{int(vehicle.mode.number)},"
            + (",".join(map(repr, home)) if home else ",,") + "\n")  # empty until home is set
