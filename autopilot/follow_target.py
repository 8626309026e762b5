"""Where the lead vehicle FOLLOW flies after is, as ArduCopter's AP_Follow estimates it, sans-IO.

The MAVLink layer (mavlink/follow_messages.py) hands in what the lead says of itself: a position
in this vehicle's local NED frame, a velocity, maybe an acceleration and a heading, from
GLOBAL_POSITION_INT or FOLLOW_TARGET. FOLLOW calls update() each tick, which keeps a
jerk-limited estimate of the lead (position projected on from the last report at the reported
velocity, shaped within FOLL_ACCEL_NE / FOLL_JERK_NE; heading within FOLL_ACCEL_H / FOLL_JERK_H)
and the point to fly to: the estimate plus FOLL_OFS_X/Y/Z, in NED or turned with the lead's
heading (FOLL_OFS_TYPE).

ArduCopter's rules, kept here:
  - only FOLL_SYSID is heard; with 0, the first other system heard is taken, and forgotten after
    10 s of its silence;
  - once FOLLOW_TARGET has been heard, GLOBAL_POSITION_INT is ignored (until that 10 s silence);
  - a lead silent for 3 s (FOLL_TIMEOUT in effect) is lost: the estimate is invalid, so FOLLOW
    stops and holds; until then the estimate flies on along the last velocity;
  - a lead farther than FOLL_DIST_MAX (when positive) is not followed;
  - a report too far from the estimate (beyond what FOLL_ACCEL/JERK allow in 3 s) restarts it;
  - with all offsets zero, FOLLOW loads the distance to the lead as the offset on its first
    flying tick ("N-E-D follow offset loaded") and forgets it on leaving.
Sim time is the only clock: a report is dated by its sender's timestamp, corrected for the
link's lag and jitter as ArduPilot does (jitter_correction.py), so that a burst of late reports
is not taken as a lead that jumps.
FOLL_POS_P is served but, as in ArduCopter 4.7, nothing reads it.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .control.shaping import shape_angle_vel_accel, shape_pos_vel_accel_2d, wrap_pi
from .jitter_correction import JitterCorrection
from .results import Severity
from .views import Notify, Vector3

if TYPE_CHECKING:
    from .params import ParamStore

LOST_AFTER_S = 3.0  # AP_FOLLOW_TIMEOUT_MS: no report for this long and the lead is lost
FORGET_SYSID_AFTER_S = 10.0  # AP_FOLLOW_SYSID_TIMEOUT_MS: a sysid taken automatically is forgotten
STALE_ESTIMATE_S = 0.1  # an estimate not updated for this long starts again from the last report
OFFSET_NED, OFFSET_RELATIVE = 0, 1  # FOLL_OFS_TYPE
ALT_RELATIVE = 1  # FOLL_ALT_TYPE: the lead's height above home (0: above sea level)
YAW_NONE, YAW_FACE_LEAD, YAW_SAME_AS_LEAD, YAW_DIR_OF_FLIGHT = 0, 1, 2, 3  # FOLL_YAW_BEHAVE
FLIGHT_DIRECTION_MIN_M_S = 1.0  # YAW_DIR_OF_FLIGHT turns only above this speed
ZERO3: Vector3 = (0.0, 0.0, 0.0)


def max_velocity_change(accel_max: float, jerk_max: float, duration_s: float) -> float:
    """The velocity a jerk-limited profile can gain in duration_s (ramp up, hold, ramp down)."""
    ramp_s = accel_max / jerk_max
    if duration_s >= 2.0 * ramp_s:
        return accel_max * ramp_s + accel_max * (duration_s - 2.0 * ramp_s)
    half = duration_s * 0.5
    return 0.5 * jerk_max * half * half


def turned(v: Vector3, angle_rad: float) -> Vector3:
    """v turned about the down axis by angle_rad (north toward east)."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return v[0] * c - v[1] * s, v[0] * s + v[1] * c, v[2]


class FollowTarget:
    """The lead's estimate. hear() takes reports; update() moves the estimate to `now_s`."""

    def __init__(self, params: ParamStore, notify: Notify):
        self.params = params
        self.notify = notify
        # The last report (local NED; heading in degrees)
        self.report_pos: Vector3 = ZERO3
        self.report_vel: Vector3 = ZERO3
        self.report_accel: Vector3 = ZERO3
        self.report_heading_deg = 0.0
        self.report_heading_rate_deg_s = 0.0
        self.heard_s: float | None = None  # when the last report taken was made (local time)
        self.jitter = JitterCorrection()
        self.auto_sysid = 0  # the sender taken while FOLL_SYSID is 0
        self.sysid_used = 0
        self.using_follow_target = False
        # The estimate
        self.valid = False
        self.pos: Vector3 = ZERO3
        self.vel: Vector3 = ZERO3
        self.accel: Vector3 = ZERO3
        self.heading = 0.0  # rad
        self.heading_rate = 0.0
        self.heading_accel = 0.0
        self.estimated_s = 0.0
        # The point to fly to: the estimate plus the offset
        self.ofs_pos: Vector3 = ZERO3
        self.ofs_vel: Vector3 = ZERO3
        self.ofs_accel: Vector3 = ZERO3
        self.loaded_offset: Vector3 | None = None  # the offset FOLLOW loaded itself (all FOLL_OFS_* zero)

    # ----- reports -----------------------------------------------------------------------------
    def sysid(self) -> int:
        """The system followed: FOLL_SYSID, or the one taken automatically while it is 0."""
        return int(self.params["FOLL_SYSID"]) or self.auto_sysid

    def listens_to(self, sysid: int, own_sysid: int, now_s: float) -> bool:
        """Whether a report from `sysid` is taken (AP_Follow::should_handle_message), after
        forgetting a lead silent for FORGET_SYSID_AFTER_S (as each message heard does there)."""
        if self.heard_s is None or now_s - self.heard_s > FORGET_SYSID_AFTER_S:
            self.auto_sysid = 0
            self.sysid_used = 0
            self.valid = False
            self.using_follow_target = False
        if not self.params["FOLL_ENABLE"] or sysid == own_sysid:
            return False
        followed = self.sysid()
        return followed == 0 or sysid == followed

    def hear(self, sysid: int, now_s: float, sent_s: float, pos: Vector3, vel: Vector3, accel: Vector3,
             heading_deg: float | None, heading_rate_deg_s: float | None, follow_target: bool) -> bool:
        """A report from `sysid`, already admitted by listens_to(), stamped sent_s by its
        sender's clock and heard at now_s: heading None = not given (refused with relative
        offsets, which need it); heading_rate None = keep the last. False if it was not taken."""
        if not follow_target and self.using_follow_target:
            return False
        if heading_deg is None:
            if self.params["FOLL_OFS_TYPE"] == OFFSET_RELATIVE:
                return False
            self.report_heading_rate_deg_s = 0.0
        else:
            self.report_heading_deg = heading_deg
            if heading_rate_deg_s is not None:
                self.report_heading_rate_deg_s = heading_rate_deg_s
        self.report_pos, self.report_vel, self.report_accel = pos, vel, accel
        self.heard_s = self.jitter.local_time(sent_s, now_s)
        if not self.params["FOLL_SYSID"] and not self.auto_sysid:
            self.auto_sysid = sysid
            self.sysid_used = 0
            self.valid = False
        if follow_target:
            self.using_follow_target = True
        if self._report_too_far():
            self.valid = False
        return True

    def _report_too_far(self) -> bool:
        """A report beyond what the lead could have done in LOST_AFTER_S within the shaping
        limits: the estimate starts again from it."""
        p = self.params
        accel_ne, accel_d = p["FOLL_ACCEL_NE"], p["FOLL_ACCEL_D"]
        half = (LOST_AFTER_S * 0.5) ** 2
        dv_ne = max_velocity_change(accel_ne, p["FOLL_JERK_NE"], LOST_AFTER_S) if p["FOLL_JERK_NE"] > 0 else math.inf
        dv_d = max_velocity_change(accel_d, p["FOLL_JERK_D"], LOST_AFTER_S) if p["FOLL_JERK_D"] > 0 else math.inf
        e = [a - b for a, b in zip(self.pos, self.report_pos)]
        ev = [a - b for a, b in zip(self.vel, self.report_vel)]
        return (math.hypot(e[0], e[1]) > accel_ne * half or math.hypot(ev[0], ev[1]) > dv_ne
                or abs(e[2]) > accel_d * half or abs(ev[2]) > dv_d)

    # ----- the estimate ------------------------------------------------------------------------
    def has_lead(self, now_s: float) -> bool:
        return bool(self.params["FOLL_ENABLE"]) and self.heard_s is not None and now_s - self.heard_s <= LOST_AFTER_S

    def update(self, now_s: float, own_pos: Vector3 | None) -> bool:
        """Moves the estimate to now_s (AP_Follow::update_estimates); own_pos None = this
        vehicle's position is unknown. Whether there is a point to fly to."""
        if not self.has_lead(now_s):
            self.valid = False
            return False
        assert self.heard_s is not None
        followed = self.sysid()
        if followed != self.sysid_used:
            self.sysid_used = followed
            self.valid = False
        p = self.params
        dt = now_s - self.heard_s
        rv, ra = self.report_vel, self.report_accel
        projected = tuple(x + v * dt + a * 0.5 * dt * dt for x, v, a in zip(self.report_pos, rv, ra))
        projected_vel = tuple(v + a * dt for v, a in zip(rv, ra))
        heading_rate = math.radians(self.report_heading_rate_deg_s)
        projected_heading = math.radians(self.report_heading_deg) + heading_rate * dt
        e_dt = now_s - self.estimated_s
        limits = (p["FOLL_ACCEL_NE"], p["FOLL_JERK_NE"], p["FOLL_ACCEL_D"], p["FOLL_JERK_D"],
                  p["FOLL_ACCEL_H"], p["FOLL_JERK_H"])
        shaped = min(limits) > 0.0
        if self.valid and shaped and e_dt <= STALE_ESTIMATE_S:
            self._shape(projected, projected_vel, heading_rate, projected_heading, e_dt, limits)
        else:
            self.pos, self.vel, self.accel = projected, projected_vel, ra  # type: ignore[assignment]
            self.heading, self.heading_rate, self.heading_accel = projected_heading, heading_rate, 0.0
            self.valid = True
        self._apply_offset(shaped)
        self.estimated_s = now_s
        if own_pos is None:
            self.valid = False
            return False
        dist_max = p["FOLL_DIST_MAX"]
        if dist_max > 0.0 and math.dist(self.report_pos, own_pos) > dist_max:
            self.valid = False
        return self.valid

    def _shape(self, target: tuple, target_vel: tuple, heading_rate: float, heading: float, dt: float,
               limits: tuple) -> None:
        accel_ne, jerk_ne, _, _, accel_h, jerk_h = limits
        (n, e, d), (vn, ve, vd), (an, ae, ad) = self.pos, self.vel, self.accel
        # Move on with the present acceleration, then shape it toward the projected report
        n, e, d = n + vn * dt + an * 0.5 * dt * dt, e + ve * dt + ae * 0.5 * dt * dt, d + vd * dt + ad * 0.5 * dt * dt
        vn, ve, vd = vn + an * dt, ve + ae * dt, vd + ad * dt
        an, ae = shape_pos_vel_accel_2d((target[0], target[1]), (target_vel[0], target_vel[1]),
                                        (self.report_accel[0], self.report_accel[1]), (n, e), (vn, ve), (an, ae),
                                        accel_ne, jerk_ne, dt)
        self.pos, self.vel, self.accel = (n, e, d), (vn, ve, vd), (an, ae, ad)
        self.heading_accel = shape_angle_vel_accel(heading, heading_rate, self.heading, self.heading_rate,
                                                   self.heading_accel, math.radians(accel_h), math.radians(jerk_h), dt)
        h = self.heading + self.heading_rate * dt + self.heading_accel * 0.5 * dt * dt
        self.heading_rate += self.heading_accel * dt
        self.heading = wrap_pi(h)

    def offset(self) -> Vector3:
        """FOLL_OFS_X/Y/Z, or the offset FOLLOW loaded while they are all zero."""
        p = self.params
        offset = (p["FOLL_OFS_X"], p["FOLL_OFS_Y"], p["FOLL_OFS_Z"])
        if offset == ZERO3 and self.loaded_offset is not None:
            return self.loaded_offset
        return offset

    def _apply_offset(self, shaped: bool) -> None:
        offset = self.offset()
        relative = self.params["FOLL_OFS_TYPE"] == OFFSET_RELATIVE
        if offset == ZERO3 or not relative:
            self.ofs_pos = (self.pos[0] + offset[0], self.pos[1] + offset[1], self.pos[2] + offset[2])
            self.ofs_vel, self.ofs_accel = self.vel, self.accel
            return
        ox, oy, oz = turned(offset, self.heading)
        self.ofs_pos = (self.pos[0] + ox, self.pos[1] + oy, self.pos[2] + oz)
        self.ofs_vel, self.ofs_accel = self.vel, self.accel
        if shaped:  # the offset swings round with the lead's turn (ArduPilot's own scaling: by its length)
            length = math.sqrt(ox * ox + oy * oy + oz * oz)
            cross = (oy * length, -ox * length)
            r, a = self.heading_rate, self.heading_accel
            self.ofs_vel = (self.vel[0] + cross[0] * r, self.vel[1] + cross[1] * r, self.vel[2])
            self.ofs_accel = (self.accel[0] + cross[0] * a, self.accel[1] + cross[1] * a, self.accel[2])

    # ----- FOLLOW's own offset -----------------------------------------------------------------
    def load_offset_if_needed(self, own_pos: Vector3) -> None:
        """With every FOLL_OFS_* zero, keep where the lead is from here now as the offset
        (AP_Follow::init_offsets_if_required), once a lead is known."""
        p = self.params
        if self.loaded_offset is not None or (p["FOLL_OFS_X"], p["FOLL_OFS_Y"], p["FOLL_OFS_Z"]) != ZERO3:
            return
        if not self.valid:
            return
        away: Vector3 = (own_pos[0] - self.report_pos[0], own_pos[1] - self.report_pos[1],
                         own_pos[2] - self.report_pos[2])
        if p["FOLL_OFS_TYPE"] == OFFSET_RELATIVE:
            self.loaded_offset = turned(away, -self.heading)
            self.notify("Relative follow offset loaded", Severity.INFO)
        else:
            self.loaded_offset = away
            self.notify("N-E-D follow offset loaded", Severity.INFO)

    def forget_loaded_offset(self) -> None:
        self.loaded_offset = None
