"""SIM_* faults: the simulator parameters a user of ArduPilot SITL sets to make a test fail
(tests/parity/surface/sim_faults.toml lists them), each set the way a user's test sets it, with
ArduPilot SITL's own defaults otherwise (its pack, its voltages, its failsafe settings).

One trace per parameter; facts are "<scenario>.<fact>". A scenario starts hovering in GUIDED at
HOVER_M above home (a companion computer's or a test script's mode: ArduCopter SITL's simulated
RC holds the throttle stick at 1000 µs, so a pilot mode such as LOITER would descend), sets the
fault, and watches a fixed window of vehicle time:
  mode_after, armed_after, flying_after   the state at the end of the window (a fresh HEARTBEAT)
  failsafe_after_s                        vehicle seconds from the setting to the first HEARTBEAT
                                          in another mode (None: the mode held)
  said                                    what the vehicle said in the window, numbers as '#'
plus, where the fault is about a number a client reads, that number (voltage, tilt, drift).

Scenarios that may end a vehicle (a failsafe, a crash) boot their own; the sensor faults an
ArduCopter with redundant sensors flies through share one, each fault undone after its window.
"""
from __future__ import annotations

import math
import re

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import GUIDED, mode_name, reach_flying
from .texts import said as said_all

AREA = "surface_sim_faults"
KIND = "sim_faults"
HOVER_M = 15.0
EARTH_M_PER_DEG = 111_195.0
NOT_REACHED = "<start state not reached>"

# A mode change is seen in the next 1 Hz HEARTBEAT (up to 1 s late on either vehicle), after the
# fault itself was applied within a tick of its PARAM_SET.
HEARTBEAT_TOL = Tol(abs=1.5, why="the mode change is seen in 1 Hz HEARTBEATs: up to 1 s late on either vehicle")
# The low-battery failsafe fires after BATT_LOW_TIMER (10 s) of readings below BATT_LOW_VOLT.
BATTERY_TOL = Tol(abs=2.0, why="BATT_LOW_TIMER's 10 s counted from the first low reading, seen in 1 Hz HEARTBEATs")
# Losing the GPS, ArduCopter's EKF dead-reckons until its position variance passes FS_EKF_THRESH:
# seconds that depend on the estimator's state when the GPS went.
EKF_TOL = Tol(abs=3.0, rel=0.3, why="the EKF failsafe fires when the estimate's variance passes FS_EKF_THRESH: "
                                    "how fast it grows depends on each estimator, not only on the fault")
VOLTS_TOL = Tol(abs=0.4, why="ArduCopter SITL's pack reports SIM_BATT_VOLTAGE itself; a pack that sags under "
                             "the hover current reads a few tenths lower")
TILT_TOL = Tol(abs=3.0, rel=0.5, why="the lean that holds a hover against wind is the airframe's drag over its "
                                     "weight: two airframes, two drag models")
DRIFT_TOL = Tol(abs=3.0, rel=0.5, why="how far the wind pushes before the position loop holds is each "
                                      "controller's tuning")
HEIGHT_TOL = Tol(abs=3.0, rel=0.5, why="read while the vehicle still sinks at up to 1 m/s from 5 Hz GPS fixes: "
                                       "ArduCopter read -5.4 to -7.7 m in three recordings, Firefly -7.8 to "
                                       "-12 m (its height is the barometer's alone; ArduCopter's EKF blends)")
# A jammed GPS's readings are drawn at random on both vehicles (SITL's and Firefly's jamming
# alike), and with them when the failsafe trips and how often it clears and trips again.
JAM_TOL = Tol(abs=5.0, why="chance: ArduCopter tripped 4.3 to 7.5 s after the jamming in six flights; Firefly's "
                           "model 3.5 to 6.6 s for half of 100 seeds, 12.5 s at most")
# So the jammed scenario's texts are the set said: the failsafe's clearing and tripping again
# come on both, in numbers that vary. Vibration compensation is left out of that set: it comes
# when the velocity variance stays high for a second, which chance decides (ArduCopter: in each
# of four flights, 5.6 to 17.2 s in; Firefly's model: 98 of 100 seeds within 20 s).
VIBRATION = re.compile(r"^Vibration compensation")
NUMBER = re.compile(r"-?\d+(\.\d+)?")
# ArduCopter's EKF runs a lane per IMU and says when it makes another lane primary: the internals
# of a multi-lane estimator, on its own timing, not a reaction a client acts on.
LANE_SWITCH = re.compile(r"^EKF primary changed")


def said(texts: list[str]) -> list[str]:
    """What was said, with numbers (volts, mAh, seconds) as '#': the words decide a client's logic."""
    return [NUMBER.sub("#", t) for t in said_all(texts) if not LANE_SWITCH.search(t)]


# ----- vehicles ---------------------------------------------------------------------------------
class Vehicle:
    """The target's present vehicle, hovering in GUIDED; booted again when it cannot be."""

    def __init__(self, target):
        self.target = target
        self.c: Client | None = None

    def hovering(self, params: dict | None = None, sim_params: dict | None = None) -> Client | None:
        """A vehicle hovering at HOVER_M in GUIDED: this one when it still can, else a new one
        (sim_params from power-on, params set after boot); None when two boots could not."""
        for fresh in (params is not None or sim_params is not None or self.c is None, True):
            try:
                if fresh:
                    self.lost()
                    self.c = self.target.boot(params=sim_params)
                    for name, value in (params or {}).items():
                        if not self.c.set_param(name, value):
                            raise ProbeTimeout(f"{name} not set")
                reach_flying(self.c, HOVER_M)
                self.c.wait(lambda: abs(self.c.rel_alt_m() - HOVER_M) < 1.0, 30, what="the hover height")
                self.c.idle(2.0)
                return self.c
            except ProbeTimeout:
                self.lost()
        return None

    def lost(self) -> None:
        if self.c is not None:
            self.c.close()
        self.c = None


def gps_position(c: Client) -> tuple[float, float, float]:
    """North, east, up (m) of the GPS's own fix (the true position, as near as a client sees
    it: not the estimate), from an arbitrary origin."""
    g = c.last["GPS_RAW_INT"]
    north = g.lat * 1e-7 * EARTH_M_PER_DEG
    east = g.lon * 1e-7 * EARTH_M_PER_DEG * math.cos(math.radians(g.lat * 1e-7))
    return north, east, g.alt / 1000.0


def battery_volts(c: Client) -> float:
    c.fresh("SYS_STATUS")
    return round(c.last["SYS_STATUS"].voltage_battery / 1000.0, 1)


def tilt_deg(c: Client) -> float:
    a = c.last["ATTITUDE"]
    return round(math.degrees(math.acos(max(-1.0, min(1.0, math.cos(a.roll) * math.cos(a.pitch))))), 1)


def watch(c: Client, trace: Trace, scenario: str, sets: list[tuple[str, float]], window_s: float,
          tol: Tol = HEARTBEAT_TOL, during=None, early=None, said_as=None) -> None:
    """Set each (name, value), then watch `window_s` of vehicle time: the facts listed in the
    module's docstring under `scenario.`; `during(c)` adds facts of its own at the end, `early`
    = (seconds, fn) facts of fn(c) that many seconds into the window; `said_as` reduces what
    was said in another way than said()."""
    start_mode = c.mode
    t0 = c.now_ms
    changed: list[float] = []
    extra: dict = {}

    def seen(msg) -> None:
        if msg.get_type() == "HEARTBEAT" and not changed and msg.custom_mode != start_mode:
            changed.append((c.now_ms - t0) / 1000.0)
    with c.listening(seen):
        for name, value in sets:
            c.set_param(name, value)
        if early is not None:
            c.wait(lambda: c.now_ms >= t0 + early[0] * 1000, early[0] + 10, what="the early sample")
            extra.update(early[1](c))
        c.wait(lambda: c.now_ms >= t0 + window_s * 1000, window_s + 10, what="the end of the window")
        c.fresh_heartbeat()
    extra.update(during(c) if during is not None else {})
    trace.fact(f"{scenario}.failsafe_after_s", changed[0] if changed else None, tol)
    trace.fact(f"{scenario}.mode_after", mode_name(c.mode))
    trace.fact(f"{scenario}.armed_after", c.armed)
    trace.fact(f"{scenario}.flying_after", c.armed and c.rel_alt_m() > 2.0)
    trace.fact(f"{scenario}.said", (said_as or said)(c.texts_since(t0)))
    for name, (value, value_tol) in extra.items():
        trace.fact(f"{scenario}.{name}", value, value_tol)


def unreached(trace: Trace, scenario: str) -> None:
    trace.fact(f"{scenario}.start", NOT_REACHED)


# ----- the faults -------------------------------------------------------------------------------
def battery(vehicle: Vehicle) -> dict[str, Trace]:
    """SIM_BATT_VOLTAGE: the reported voltage follows it. 11 V (above BATT_LOW_VOLT's default
    10.5 V) trips nothing; 10 V trips the low-battery failsafe after BATT_LOW_TIMER, here RTL."""
    trace = Trace()
    c = vehicle.hovering(params={"BATT_FS_LOW_ACT": 2})
    if c is None:
        unreached(trace, "hover")
        return {"SIM_BATT_VOLTAGE": trace}
    trace.fact("hover.volts", battery_volts(c), VOLTS_TOL)
    # the reading 2 s after the setting: ArduCopter SITL's pack is constant, a pack that drains
    # (Firefly's) is nearly empty at 10 V and sinks to its floor within the window
    volts = (2.0, lambda c: {"volts_2s": (battery_volts(c), VOLTS_TOL)})
    watch(c, trace, "set_11v", [("SIM_BATT_VOLTAGE", 11.0)], 14.0, BATTERY_TOL, early=volts)
    watch(c, trace, "set_10v", [("SIM_BATT_VOLTAGE", 10.0)], 14.0, BATTERY_TOL, early=volts)
    vehicle.lost()
    return {"SIM_BATT_VOLTAGE": trace}


def one_fault(name: str, scenario: str, value: float, window_s: float, tol: Tol, said_as=None):
    """A part of the area: `name` set to `value` on a fresh hovering vehicle."""
    def part(vehicle: Vehicle) -> dict[str, Trace]:
        trace = Trace()
        c = vehicle.hovering(params={})
        if c is None:
            unreached(trace, scenario)
        else:
            watch(c, trace, scenario, [(name, value)], window_s, tol, said_as=said_as)
        vehicle.lost()
        return {name: trace}
    return part


# the GPS goes silent; its latitude jumps by 0.001 deg (111 m north); its fix wanders as jammed
gps_off = one_fault("SIM_GPS1_ENABLE", "gps_off", 0, 14.0, EKF_TOL)  # LAND at 8 s, still descending
gps_glitch = one_fault("SIM_GPS1_GLTCH_X", "jump_111m", 0.001, 15.0, EKF_TOL)
gps_jam = one_fault("SIM_GPS1_JAM", "jammed", 1, 20.0, JAM_TOL, said_as=lambda texts: sorted(set(said(
    [t for t in texts if not VIBRATION.search(t)]))))


def rc_fail(vehicle: Vehicle) -> dict[str, Trace]:
    """SIM_RC_FAIL with FS_THR_ENABLE 1 (RTL; ArduCopter's default): 1 = no pulses (the radio
    failsafe after RC_FS_TIMEOUT), 0 again (cleared), 2 = throttle at 950 µs (below FS_THR_VALUE)."""
    trace = Trace()
    c = vehicle.hovering(params={"FS_THR_ENABLE": 1})
    if c is None:
        unreached(trace, "no_pulses")
        return {"SIM_RC_FAIL": trace}
    watch(c, trace, "no_pulses", [("SIM_RC_FAIL", 1)], 6.0)
    watch(c, trace, "restored", [("SIM_RC_FAIL", 0)], 3.0)
    c.set_mode(GUIDED)
    c.try_wait(lambda: c.mode == GUIDED, 3)
    watch(c, trace, "throttle_950", [("SIM_RC_FAIL", 2)], 6.0)
    vehicle.lost()
    return {"SIM_RC_FAIL": trace}


def engines(vehicle: Vehicle) -> dict[str, Trace]:
    """SIM_ENGINE_FAIL (ArduCopter 4.7: a mask of motors) and SIM_ENGINE_MUL (their thrust
    multiplier): MUL 0 alone touches no motor (the mask is 0); motor 1 at 60 % of its thrust;
    motor 1 dead."""
    fail, mul = Trace(), Trace()
    c = vehicle.hovering(params={})
    if c is None:
        unreached(fail, "mul_0_mask_0")
    else:
        watch(c, fail, "mul_0_mask_0", [("SIM_ENGINE_MUL", 0.0)], 8.0)
    c = vehicle.hovering(params={})
    if c is None:
        unreached(mul, "motor1_60pct")
    else:
        watch(c, mul, "motor1_60pct", [("SIM_ENGINE_MUL", 0.6), ("SIM_ENGINE_FAIL", 1)], 8.0)
        watch(c, mul, "motor1_dead", [("SIM_ENGINE_MUL", 0.0)], 10.0)
    vehicle.lost()
    return {"SIM_ENGINE_FAIL": fail, "SIM_ENGINE_MUL": mul}


def baro_height(c: Client, h0: float) -> dict:
    return {"gps_height_change_m": (round(gps_position(c)[2] - h0, 1) + 0.0, HEIGHT_TOL)}


def wind_facts(c: Client, where: tuple) -> dict:
    n, e, _ = gps_position(c)
    return {"tilt_deg": (tilt_deg(c), TILT_TOL),
            "drift_m": (round(math.hypot(n - where[0], e - where[1]), 1), DRIFT_TOL)}


# name -> (scenario, value set, value that undoes it, window s, extra facts or None)
SENSOR_FAULTS = {
    "SIM_BARO_DISABLE": ("disabled", 1, 0, 8.0),
    "SIM_BARO_GLITCH": ("glitch_20m", 20, 0, 8.0),
    "SIM_BARO_FREEZE": ("frozen", 1, 0, 8.0),
    "SIM_MAG1_FAIL": ("failed", 1, 0, 8.0),
    "SIM_ACCEL1_FAIL": ("failed", 1, 0, 8.0),
    "SIM_ACC_FAIL_MSK": ("imu1_accel_stopped", 1, 0, 8.0),
    "SIM_GYR_FAIL_MSK": ("imu1_gyro_stopped", 1, 0, 8.0),
    "SIM_GPS1_NUMSATS": ("three_sats", 3, 10, 8.0),
}


def sensors(vehicle: Vehicle) -> dict[str, Trace]:
    """Faults of one sensor among redundant ones, each on the same hovering vehicle (a new one
    if the last fault ended it), undone after its window; then the barometer's drift and wind."""
    traces = {}
    for name, (scenario, value, undo, window_s) in SENSOR_FAULTS.items():
        trace = traces[name] = Trace()
        c = vehicle.hovering()
        if c is None:
            unreached(trace, scenario)
            continue
        watch(c, trace, scenario, [(name, value)], window_s)
        c.set_param(name, undo)
        if c.mode != GUIDED or not c.armed:
            vehicle.lost()
    trace = traces["SIM_BARO_DRIFT"] = Trace()
    c = vehicle.hovering()
    if c is None:
        unreached(trace, "drift_1m_s")
    else:
        h0 = gps_position(c)[2]
        watch(c, trace, "drift_1m_s", [("SIM_BARO_DRIFT", 1.0)], 10.0, during=lambda c: baro_height(c, h0))
        c.set_param("SIM_BARO_DRIFT", 0)
        vehicle.lost()  # the estimate's height is off now
    trace = traces["SIM_WIND_SPD"] = Trace()
    c = vehicle.hovering()
    if c is None:
        unreached(trace, "wind_10m_s")
    else:
        where = gps_position(c)
        watch(c, trace, "wind_10m_s", [("SIM_WIND_SPD", 10.0)], 10.0, during=lambda c: wind_facts(c, where))
    vehicle.lost()
    return traces


def run(target) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    vehicle = Vehicle(target)
    try:
        for part in (battery, rc_fail, gps_off, gps_glitch, gps_jam, engines, sensors):
            traces.update(part(vehicle))
    finally:
        vehicle.lost()
        target.close()
    return traces
