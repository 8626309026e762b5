"""External navigation: a companion's pose (visual odometry, motion capture) in place of the GPS,
as AP_VisualOdom hands it to EKF3 and the EK3_SRCn_* of the source set in use choose it.

VISO_TYPE (read at boot) makes the sensor; it then takes VISION_POSITION_ESTIMATE,
GLOBAL_VISION_POSITION_ESTIMATE, VICON_POSITION_ESTIMATE, ATT_POS_MOCAP and ODOMETRY (the
session decodes them; this module never sees MAVLink). A pose is in the companion's own frame:
metres north, east and down of wherever its zero is, which is taken to be where MAVLink's local
frame starts, times VISO_SCALE. A pose whose quality is under VISO_QUAL_MIN is counted for health
but not fused. The sensor is healthy while a pose or a speed has come within HEALTHY_S.

The estimate takes the pose when the set's POSXY is 6 (ExternalNav; the height too with its
POSZ 6): from then on where the vehicle believes it is, is where the companion says. A switch of
source set onto the pose resets the estimate to the last pose, as EKF3 resets on a source change.
Firefly's estimate is otherwise the simulator's truth (estimate.py), so what the pose adds is its
error, `offset_ned`: the pose's position less the true one at the moment it arrived, held between
poses. The vehicle flies the estimate, so a pose that reads 5 m north of the truth holds the
vehicle 5 m south of where it is asked to be, as on ArduCopter.

As EKF3 with its default gates (measured on ArduCopter SITL):
- a pose whose error jumps more than GATE_SIGMAS x VISO_POS_M_NSE from the error fused is not
  fused; after RESET_POSE_ONLY_S of poses rejected, the estimate takes the new error at once; when
  the companion sends its velocity too, only after RESET_WITH_VELOCITY_S, and then the horizontal
  position is no longer trusted, for good (ArduCopter's flags never recovered in 60 s: "Need
  Position Estimate" until a reboot), which starts the EKF failsafe;
- a pose with a NaN position is heard (the sensor stays healthy) but not fused;
- without a pose the horizontal position is dead-reckoned for DEAD_RECKONING_S
  (estimate.py), then lost, as with a GPS that stops. Firefly's dead reckoning holds the last
  error; ArduCopter's drifts (0.2 m in 5 s, measured).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .params import ParamStore

SOURCE_NONE, SOURCE_EXTNAV = 0, 6  # EK3_SRCn_POSXY values: none, external navigation
HEALTHY_S = 0.3  # AP_VisualOdom's timeout: healthy with a message this recent
GATE_SIGMAS = 5.0  # EK3_POS_I_GATE 500: five standard deviations
# Measured, a 5 m jump: with the companion's velocity too (SITL's Vicon) it is rejected 10.2 s, then
# taken with the position lost; with a pose alone it is rejected 4.3 s and then taken, the
# position still trusted (EKF3 resets a position it cannot check against a velocity)
RESET_WITH_VELOCITY_S = 10.2
RESET_POSE_ONLY_S = 4.3
VELOCITY_FRESH_S = 0.5  # a speed this recent aids the EKF


class ExternalNav:
    """VISO_TYPE's sensor, made at boot (kind 0: none, every pose ignored)."""

    def __init__(self, params: ParamStore):
        self.params = params
        self.kind = int(params["VISO_TYPE"])
        self.heard_s = -math.inf  # the last pose or speed message, fused or not
        self.fused_s = -math.inf  # the last pose fused horizontally
        # the last pose with a position, fused or held off by the gate: EKF3 keeps its position
        # trusted while the gate rejects (measured: its flags held for the 10 s until the reset)
        self.measured_s = -math.inf
        self.offset_ned: tuple[float, float, float] = (0.0, 0.0, 0.0)  # the fused pose less the truth
        self.measured_ne: tuple[float, float] | None = None  # the last pose less the truth, fused or not
        self.poses = 0  # poses fused so far
        self.speeds = 0  # speed messages heard (ODOMETRY carries one)
        self.speed_s = -math.inf  # the last one
        self.rejected_since: float | None = None  # poses rejected by the gate since then
        self.lost = False  # a rejected jump was taken in the end: the position is not trusted again
        self.reset_counter: int | None = None  # the companion's, from its last pose
        self.announced = False  # "EKF3 ... is using external nav data" said
        self.reset_pending = False  # switched onto the pose with none fresh: the next is taken as it is

    def pose(self, now_s: float, frame_origin_ned: tuple[float, float, float], xyz: tuple[float, float, float],
             truth_ned: tuple[float, float, float], quality: int = 0, reset_counter: int = 0) -> bool:
        """A pose at `now_s`: metres north, east and down in the companion's frame, whose zero lies
        at frame_origin_ned of the sim's frame (the EKF origin), with the vehicle truly at
        truth_ned. Whether it was fused horizontally."""
        if not self.kind:
            return False
        self.heard_s = now_s
        if quality < self.params["VISO_QUAL_MIN"]:
            return False
        scale = self.params["VISO_SCALE"]
        off_n, off_e, off_d = self.offset_ned
        if math.isfinite(xyz[2]):
            off_d = frame_origin_ned[2] + scale * xyz[2] - truth_ned[2]
        fused = math.isfinite(xyz[0]) and math.isfinite(xyz[1])
        if fused:
            n = frame_origin_ned[0] + scale * xyz[0] - truth_ned[0]
            e = frame_origin_ned[1] + scale * xyz[1] - truth_ned[1]
            self.measured_s, self.measured_ne = now_s, (n, e)
            fused = self._gate(now_s, n - off_n, e - off_e)
            if fused:
                off_n, off_e = n, e
                self.fused_s = now_s
                self.poses += 1
        self.offset_ned = (off_n, off_e, off_d)
        self.reset_counter = reset_counter
        return fused

    def _gate(self, now_s: float, jump_n: float, jump_e: float) -> bool:
        """Whether a pose whose error moved by (jump_n, jump_e) from the one fused is fused: within
        the gate, the first pose, once the position is lost, or after rejections for as long as
        EKF3 holds out (with a velocity the position is then lost)."""
        if not self.poses or self.lost or self.reset_pending or \
                math.hypot(jump_n, jump_e) <= GATE_SIGMAS * self.params["VISO_POS_M_NSE"]:
            self.rejected_since = None
            self.reset_pending = False
            return True
        if self.rejected_since is None:
            self.rejected_since = now_s
        aided = now_s - self.speed_s < VELOCITY_FRESH_S
        if now_s - self.rejected_since < (RESET_WITH_VELOCITY_S if aided else RESET_POSE_ONLY_S):
            return False
        self.lost = aided
        self.rejected_since = None
        return True

    def take_latest(self, now_s: float) -> None:
        """The estimate switches to this source (EKF3's posxy_source_reset): it resets to the
        pose, whatever the gate makes of it: the last one if fresh, else the next to come; the gate
        starts again from there."""
        self.rejected_since = None
        if self.measured_ne is not None and now_s - self.measured_s < HEALTHY_S:
            self.offset_ned = (*self.measured_ne, self.offset_ned[2])
        else:
            self.reset_pending = True

    def speed(self, now_s: float) -> None:
        """A VISION_SPEED_ESTIMATE: counted for the sensor's health (the estimate's velocity is
        the truth's: Firefly models no velocity error)."""
        if self.kind:
            self.heard_s = self.speed_s = now_s
            self.speeds += 1

    def healthy(self, now_s: float) -> bool:
        return bool(self.kind) and now_s - self.heard_s < HEALTHY_S
