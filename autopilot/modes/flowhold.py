"""FLOWHOLD: ALT_HOLD whose lean also holds the vehicle still over the ground by optical flow alone
(no GPS, no rangefinder), as ArduCopter's ModeFlowHold flies it (mode_flowhold.cpp; FHLD_* its
parameters, with its names and defaults).

Entry needs the flow sensor enabled and healthy (requires_flow: the vehicle checks it, "init failed"
otherwise, as ArduCopter's init() refuses). The height and the sticks are ALT_HOLD's. Once the
flow's quality (filtered) reaches FHLD_QUAL_MIN and 3 s have passed since arming, a flow-rate
controller adds its own lean to the pilot's:
- the flow less the body's rotation, each axis clamped to FHLD_FLOW_MAX and low-passed at
  FHLD_FILT_HZ, times a height estimate (held to 0.1-3 m), is the speed over the ground, roughly;
- a PI controller (FHLD_XY_P, FHLD_XY_I, input filtered at FHLD_XY_FILT_HZ) turns it, in the earth
  frame, into a lean in fractions of ANGLE_MAX, at most half of it. As ArduCopter's code has it,
  the P term counts twice while holding (P plus the PI's output) and the integrator may only
  shrink while the lean is at its limit;
- while a stick is moved, the P term opposes the motion and the integrator waits; released, the
  vehicle brakes at FHLD_BRAKE_RATE's angle for the speed until it is under 0.3 m/s or 3 s pass.
The height estimate starts at the height above home and learns from how the flow changes against
the change in velocity (the accelerometer's, in ArduCopter); ArduCopter reports it as
NAMED_VALUE_FLOAT "HEST" at each flow sample, as Firefly does (Mode.named_float).
"""
from __future__ import annotations

import math
from functools import cached_property

from ..optical_flow import FlowReading
from .base import Mode, Setpoint, stick_deadzone
from .context import ModeContext
from .manual import PilotTakeoff, pilot_lean_and_yaw, pilot_vertical
from .numbers import ModeNumber

HEIGHT_MIN_M, HEIGHT_MAX_M = 0.1, 3.0
QUALITY_FILTER = 0.95
FLOW_AFTER_ARMING_S = 3.0  # the flow is not used while just taking off
HEIGHT_AFTER_ARMING_S = 1.5  # before this the vehicle is taken to be on the ground
BRAKE_UNTIL_M_S, BRAKE_AT_MOST_S = 0.3, 3.0
MIN_VELOCITY_CHANGE, MIN_FLOW_CHANGE, HEIGHT_STEP_MAX_M = 0.04, 0.04, 0.25
STALE_FLOW_S = 0.5
HEST = b"HEST"


def _alpha(dt: float, hz: float) -> float:
    return 1.0 if hz <= 0.0 else dt / (dt + 1.0 / (2.0 * math.pi * hz))


def _rotate(v: tuple[float, float], yaw: float) -> tuple[float, float]:
    """ArduPilot's body_to_earth2D (yaw) and earth_to_body2D (-yaw) of a 2D vector."""
    c, s = math.cos(yaw), math.sin(yaw)
    return v[0] * c - v[1] * s, v[0] * s + v[1] * c


def _clamp(x: float, limit: float) -> float:
    return min(max(x, -limit), limit)


class FlowHold(Mode):
    number = ModeNumber.FLOWHOLD
    allows_arming = True
    requires_flow = True

    def __init__(self) -> None:
        self._reset()
        self._last_flow_s: float | None = None  # kept across entries, as ArduCopter's last_flow_ms

    def _reset(self) -> None:
        self._hold_d = 0.0
        self._quality = 0.0
        self._flow_filt = (0.0, 0.0)
        self._pi_input: tuple[float, float] | None = None
        self._integrator = (0.0, 0.0)
        self._xy_i = (0.0, 0.0)
        self._limited = False
        self._braking = False
        self._stick_at_s = -math.inf
        self._height_offset_m = 0.0
        self._last_flow_rate = (0.0, 0.0)
        self._vel_at_flow = (0.0, 0.0)
        self.named_float = None

    @cached_property
    def takeoff(self) -> PilotTakeoff:
        return PilotTakeoff()

    def enter(self, ctx: ModeContext) -> str | None:
        self._reset()
        self._hold_d = ctx.body.d_m
        return None

    def _ins_height(self, ctx: ModeContext) -> float:
        return ctx.height_ref_d - ctx.body.d_m

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        now = ctx.time_s
        flow = ctx.optical_flow
        healthy = ctx.optical_flow_healthy()
        self._update_height_estimate(ctx, flow, healthy)
        self._quality = QUALITY_FILTER * self._quality + (1 - QUALITY_FILTER) * flow.quality if healthy else 0.0
        pilot = ctx.pilot
        pilot_lean_and_yaw(ctx, sp, pilot)
        roll, pitch = sp.lean if sp.lean is not None else (0.0, 0.0)
        angle_max = math.radians(ctx.params["ANGLE_MAX"] / 100.0)
        if ctx.landed or not ctx.armed:
            self._integrator = self._xy_i = (0.0, 0.0)
        if self._quality >= ctx.params["FHLD_QUAL_MIN"] and ctx.armed and now - ctx.armed_at_s > FLOW_AFTER_ARMING_S:
            fr, fp = self._flow_to_angle(ctx, flow, dt, stick_deadzone(pilot.roll) != 0.0 or stick_deadzone(pilot.pitch) != 0.0, angle_max)
            roll += _clamp(fr, angle_max / 2)
            pitch += _clamp(fp, angle_max / 2)
        sp.lean = (_clamp(roll, angle_max), _clamp(pitch, angle_max))
        if not ctx.landed:
            sp.lean = ctx.avoid_lean(sp.lean)
        self._hold_d = pilot_vertical(ctx, sp, self._hold_d, dt, self.takeoff)

    def _flow_to_angle(self, ctx: ModeContext, flow: FlowReading, dt: float, stick: bool, angle_max: float) -> tuple[float, float]:
        """The flow controller's lean (roll, pitch) [rad]: ArduCopter's flowhold_flow_to_angle."""
        p, now = ctx.params, ctx.time_s
        flow_max = p["FHLD_FLOW_MAX"]
        raw = (_clamp(flow.flow_x - flow.body_x, flow_max), _clamp(flow.flow_y - flow.body_y, flow_max))
        if not (math.isfinite(raw[0]) and math.isfinite(raw[1])):  # no number: kept out of the filters,
            raw = self._flow_filt                                   # as AC_PI_2D keeps it out of its own
        a = _alpha(dt, p["FHLD_FILT_HZ"])
        self._flow_filt = (self._flow_filt[0] + (raw[0] - self._flow_filt[0]) * a,
                           self._flow_filt[1] + (raw[1] - self._flow_filt[1]) * a)
        height = min(max(self._ins_height(ctx) + self._height_offset_m, HEIGHT_MIN_M), HEIGHT_MAX_M)
        sensor = (self._flow_filt[0] * height, self._flow_filt[1] * height)  # about m/s
        yaw = ctx.attitude[2]
        input_ef = _rotate(sensor, yaw)
        last = input_ef if self._pi_input is None else self._pi_input  # the filter starts at its first input
        b = _alpha(dt, p["FHLD_XY_FILT_HZ"])
        pi_in = self._pi_input = (last[0] + (input_ef[0] - last[0]) * b, last[1] + (input_ef[1] - last[1]) * b)
        kp = p["FHLD_XY_P"]
        ef = (pi_in[0] * kp, pi_in[1] * kp)
        if stick:
            self._stick_at_s = now
            self._braking = True
        elif self._braking and (now - self._stick_at_s > BRAKE_AT_MOST_S or math.hypot(*sensor) < BRAKE_UNTIL_M_S):
            self._braking = False
        if not stick and not self._braking:
            i = self._integrate(p, dt, pi_in)
            self._xy_i = (ef[0] + i[0], ef[1] + i[1])  # get_pi(): P again, plus I
        bf = [0.0, 0.0]  # centidegrees
        if not stick and self._braking:
            gain = (15.0 * p["FHLD_BRAKE_RATE"] + 95.0) * 0.01
            for axis in (0, 1):
                speed_cm = abs(sensor[axis]) * 100.0
                lean = gain * speed_cm * (1.0 + 500.0 / (speed_cm + 60.0))
                bf[axis] = -lean if sensor[axis] < 0 else lean
            ef = (0.0, 0.0)
        angle_max_cd = p["ANGLE_MAX"]
        ef = ((ef[0] + self._xy_i[0]) * angle_max_cd, (ef[1] + self._xy_i[1]) * angle_max_cd)
        back = _rotate(ef, -yaw)
        bf = [bf[0] + back[0], bf[1] + back[1]]
        self._limited = abs(bf[0]) > angle_max_cd or abs(bf[1]) > angle_max_cd
        return math.radians(_clamp(bf[0], angle_max_cd) / 100.0), math.radians(_clamp(bf[1], angle_max_cd) / 100.0)

    def _integrate(self, p, dt: float, pi_in: tuple[float, float]) -> tuple[float, float]:
        """AC_PI_2D's integrator (get_i, or get_i_shrink while the lean is at its limit)."""
        ki, imax = p["FHLD_XY_I"], abs(p["FHLD_XY_IMAX"])
        if ki == 0.0:
            return (0.0, 0.0)
        before = min(math.hypot(*self._integrator), imax)
        ix = self._integrator[0] + pi_in[0] * ki * dt
        iy = self._integrator[1] + pi_in[1] * ki * dt
        length = math.hypot(ix, iy)
        limit = before if self._limited else imax
        if length > limit and length > 0.0:
            ix, iy = ix * limit / length, iy * limit / length
        self._integrator = (ix, iy)
        return self._integrator

    def _update_height_estimate(self, ctx: ModeContext, flow: FlowReading, healthy: bool) -> None:
        """ArduCopter's update_height_estimate: the height from the change in flow against the change
        in velocity between flow samples, folded slowly into an offset on the height above home."""
        ins = self._ins_height(ctx)
        b = ctx.body
        vel = (b.vn_m_s, b.ve_m_s)
        if not ctx.armed or ctx.landed or ctx.time_s - ctx.armed_at_s < HEIGHT_AFTER_ARMING_S:
            self._height_offset_m = -ins
            return
        if not healthy:
            self._last_flow_s = ctx.time_s
            self._vel_at_flow = vel
            return
        if self._last_flow_s is None:
            self._last_flow_s = flow.updated_s
            self._vel_at_flow = vel
            self._height_offset_m = 0.0
            return
        if flow.updated_s == self._last_flow_s:
            return
        yaw = ctx.attitude[2]
        dv_bf = _rotate((vel[0] - self._vel_at_flow[0], vel[1] - self._vel_at_flow[1]), -yaw)
        dv_rate = (-dv_bf[1], dv_bf[0])
        rate = (flow.flow_x - flow.body_x, flow.flow_y - flow.body_y)
        if not (math.isfinite(rate[0]) and math.isfinite(rate[1])):
            return  # a sample with no number teaches nothing
        gap = flow.updated_s - self._last_flow_s
        self._vel_at_flow = vel
        if gap > STALE_FLOW_S:
            self._last_flow_s = flow.updated_s
            self._last_flow_rate = rate
            self._height_offset_m = 0.0
            return
        d_flow = (rate[0] - self._last_flow_rate[0], rate[1] - self._last_flow_rate[1])
        self._last_flow_rate = rate
        self._last_flow_s = flow.updated_s
        estimate = ins + self._height_offset_m
        delta, weight = 0.0, 0
        for axis in (0, 1):
            magnitude = abs(d_flow[axis])
            if magnitude < MIN_FLOW_CHANGE or abs(dv_rate[axis]) < MIN_VELOCITY_CHANGE:
                continue
            height = dv_rate[axis] / d_flow[axis]
            if height <= 0.0:
                continue
            delta += (height - estimate) * magnitude
            weight = int(weight + magnitude) & 0xFF  # ArduCopter sums the weights in a uint8_t
        if weight > 0:
            delta /= weight
        if delta < 0.0:
            delta *= 2.0  # rather too low a gain than an oscillation
        new_offset = self._height_offset_m + _clamp(delta, HEIGHT_STEP_MAX_M)
        self._height_offset_m = 0.8 * self._height_offset_m + 0.2 * new_offset
        if ins + self._height_offset_m < HEIGHT_MIN_M:
            self._height_offset_m = HEIGHT_MIN_M - ins
        self.named_float = (HEST, ins + self._height_offset_m)
