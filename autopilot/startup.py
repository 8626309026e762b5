"""A realistic start-up, for testing "wait until armable" code: the stages ArduCopter goes
through after power-on before it can arm, what it says meanwhile, and what refuses an ARM.

Firefly's default is armable at once (GPS fix, EKF and home from the first tick): its one
deliberate difference from ArduCopter here. With a `StartupTimeline` the vehicle instead boots
as ArduCopter SITL was measured to (vehicle seconds after boot; ArduCopter 4.7.0-dev SITL,
`--model quad`, copter.parm; the parity suite's `startup` area compares the two):

  0     "ArduPilot Ready"; an ARM gets "Arm: System not initialised" alone
  2.6   initialised: an ARM gets every failing check, "Arm: Accels inconsistent",
        "Arm: EKF attitude is bad", "Arm: AHRS: not using configured AHRS type"
  4.4   "EKF3 IMU0 initialised", "AHRS: EKF3 active" (the AHRS complaint is now "EKF3 still
        initialising")
  5.7   tilt and yaw alignment complete: the attitude is known
  9.7   "GPS 1: detected u-blox"; a 3D fix at 10.2
  12    the accelerometers agree; the gyros still do not ("Arm: Gyros inconsistent")
  19.9  "EKF3 IMU0 origin set", "Field Elevation Set: ...m": home is set
  22.5  the gyros agree: STABILIZE and ALT_HOLD arm; modes that fly by position still refuse,
        "Arm: AHRS: waiting for home" before 19.9, "Arm: Need Position Estimate" after
  41.4  "EKF3 IMU0 is using GPS": the position estimate is good; every mode arms

The IMUs' disagreement is ArduCopter SITL's (its simulated sensors start with offsets that settle);
it is kept because it is what decides when the reference first arms in STABILIZE.
"""
from __future__ import annotations

import math

from dataclasses import dataclass

from .results import Severity
from .views import Notify


ORIGIN_LANE_GAP_S = 0.25  # the second EKF lane sets its origin a moment after the first


@dataclass(frozen=True)
class StartupTimeline:
    """Seconds after power-on at which each stage is reached."""
    initialised_s: float = 2.6
    ekf_started_s: float = 4.4
    attitude_s: float = 5.7
    gps_detected_s: float = 9.7
    gps_fix_s: float = 10.2
    origin_s: float = 19.9
    gps_in_use_s: float = 41.4
    accels_consistent_s: float = 12.0
    gyros_consistent_s: float = 22.5

    def __post_init__(self):
        stages = [self.initialised_s, self.ekf_started_s, self.attitude_s, self.origin_s, self.gps_in_use_s]
        if any(t < 0 for t in stages + [self.gps_detected_s, self.gps_fix_s, self.accels_consistent_s]):
            raise ValueError("start-up times must not be negative")
        if stages != sorted(stages) or not self.gps_detected_s <= self.gps_fix_s <= self.origin_s \
                or not self.accels_consistent_s <= self.gyros_consistent_s:
            raise ValueError("start-up stages must come in order: initialised <= ekf_started <= attitude "
                             "<= origin <= gps_in_use, gps_detected <= gps_fix <= origin, and "
                             "accels_consistent <= gyros_consistent")


class Startup:
    """Where a vehicle is in its start-up; `timeline` None = ready at once."""

    def __init__(self, timeline: StartupTimeline | None):
        self.timeline = timeline
        self._said = 0
        self._due: list[tuple[float, str]] | None = None  # the milestones, built at the first say_due
        self.next_due_s = -math.inf if timeline is not None else math.inf  # when the next milestone is

    def _at_least(self, t_s: float, stage_s: float) -> bool:
        return self.timeline is None or t_s >= stage_s

    def attitude_known(self, t_s: float) -> bool:
        return self._at_least(t_s, self.timeline.attitude_s if self.timeline else 0.0)

    def gps_powered_up(self, t_s: float) -> bool:
        """Whether the receiver has its first fix (before, it reports no fix and no satellites)."""
        return self._at_least(t_s, self.timeline.gps_fix_s if self.timeline else 0.0)

    def origin_set(self, t_s: float) -> bool:
        """Whether the EKF has set its origin from the GPS (and so home can be set)."""
        return self._at_least(t_s, self.timeline.origin_s if self.timeline else 0.0)

    def gps_in_use(self, t_s: float) -> bool:
        """Whether the EKF uses the GPS: a position estimate exists."""
        return self._at_least(t_s, self.timeline.gps_in_use_s if self.timeline else 0.0)

    def initialising(self, t_s: float) -> bool:
        """Before the autopilot has initialised: an ARM gets "System not initialised" alone."""
        return self.timeline is not None and t_s < self.timeline.initialised_s

    def arm_blockers(self, t_s: float) -> list[str]:
        """What refuses an ARM at this stage, in ArduCopter's order: the IMUs, then the EKF."""
        tl = self.timeline
        if tl is None:
            return []
        out = []
        if t_s < tl.accels_consistent_s:
            out.append("Accels inconsistent")
        elif t_s < tl.gyros_consistent_s:
            out.append("Gyros inconsistent")
        if t_s < tl.attitude_s:
            out.append("EKF attitude is bad")
        if t_s < tl.ekf_started_s:
            out.append("AHRS: not using configured AHRS type")
        elif t_s < tl.attitude_s:
            out.append("AHRS: EKF3 still initialising")
        return out

    def milestones(self, field_elevation_m: float) -> list[tuple[float, str]]:
        """What ArduCopter SITL says as it starts (its two EKF lanes, IMU0 and IMU1, each report);
        nothing without a start-up timeline."""
        tl = self.timeline
        if tl is None:
            return []
        lanes = ("IMU0", "IMU1")
        return [(0.0, "Barometer 1 calibration complete"), (0.0, "Barometer 2 calibration complete"),
                (0.0, "ArduPilot Ready"), (0.0, "AHRS: DCM active"),
                *[(tl.ekf_started_s, f"EKF3 {lane} initialised") for lane in lanes],
                (tl.ekf_started_s, "AHRS: EKF3 active"),
                *[(tl.attitude_s, f"EKF3 {lane} tilt alignment complete") for lane in lanes],
                *[(tl.attitude_s, f"EKF3 {lane} MAG0 initial yaw alignment complete") for lane in lanes],
                (tl.gps_detected_s, "GPS 1: probing for u-blox at 230400 baud"),
                (tl.gps_detected_s, "GPS 1: detected u-blox"),
                (tl.origin_s, "EKF3 IMU0 origin set"), (tl.origin_s, f"Field Elevation Set: {field_elevation_m:.0f}m"),
                (tl.origin_s + ORIGIN_LANE_GAP_S, "EKF3 IMU1 origin set"),
                *[(tl.gps_in_use_s, f"EKF3 {lane} is using GPS") for lane in lanes]]

    def say_due(self, t_s: float, field_elevation_m: float, notify: Notify) -> None:
        """Say each start-up milestone once its time has come (called at the flight-mode rate:
        nothing is built until the next one is due)."""
        if t_s < self.next_due_s:
            return
        if self._due is None:  # the field elevation is the vehicle's origin's: it does not change
            self._due = self.milestones(field_elevation_m)
        due = self._due
        while self._said < len(due) and due[self._said][0] <= t_s:
            notify(due[self._said][1], Severity.INFO)
            self._said += 1
        self.next_due_s = due[self._said][0] if self._said < len(due) else math.inf
