"""A camera mount on servos, as ArduCopter's AP_Mount runs MNT1_TYPE 1 (a servo gimbal it steadies
against the vehicle's lean) and 7 (a brushless gimbal on PWM, which steadies itself); read at boot.

Outputs by SERVOn_FUNCTION: 6 pan, 7 tilt, 8 roll, 9 the retract servo. An axis is controlled
when its output is assigned and its MNT1_*_MIN is below its _MAX. Every 0.02 s (AP_Mount's 50 Hz)
the mode gives a target: an angle (roll and pitch earth-frame, yaw body-frame or earth-frame "yaw
lock") or a rate the angle follows at 50 Hz. The servos go straight to it: no slew, so the
attitude reported (the angles put out, which is all a servo gimbal can tell) is the target's at
the next update.

Modes (MAV_MOUNT_MODE): 0 retract and 1 neutral hold MNT1_RETRACT_* / MNT1_NEUTRAL_* as they are;
2 MAVLink targeting holds what a command or message set; 3 RC targeting follows the channels
whose RCn_OPTION is 212 (roll), 213 (pitch), 214 (yaw): the stick across each range, or with
MNT1_RC_RATE a rate of up to that many deg/s; an axis with no channel sits in the middle of its
range (the default mode: with none, a gimbal at boot tilts to -35 degrees, the middle of
-90..20). A channel moved by more than its dead zone (10 us at least) takes the gimbal back to
RC targeting from any mode but retract; 4 a point (the ROI);
5 another system, where its GLOBAL_POSITION_INT last put it (until one is heard the target stays);
6 home.

Output angles are put out as ArduPilot's SRV_Channels::move_servo does: decidegrees as an int16
over MNT1_*_MIN..MAX (x10) onto SERVOn_MIN..MAX (reversed with SERVOn_REVERSED), whole us.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

from ..c_casts import as_int16, as_uint8
from ..params import ParamStore
from ..rc.channels import Calibration, stick
from .outputs import Constrain, outputs_of

SERVO, BRUSHLESS_PWM = 1, 7  # MNT1_TYPE
PAN, TILT, ROLL, OPEN = 6, 7, 8, 9  # SERVOn_FUNCTION
RETRACT, NEUTRAL, MAVLINK_TARGETING, RC_TARGETING, GPS_POINT, SYSID_TARGET, HOME_LOCATION = range(7)
MODES = 7  # MAV_MOUNT_MODE_ENUM_END: modes are 0..6
UPDATE_S = 0.02
LOCK_FROM_PREVIOUS_MODE = 1  # MNT1_OPTIONS bit 0: RC targeting keeps the yaw lock the last target had
# GIMBAL_DEVICE_FLAGS and GIMBAL_MANAGER_FLAGS (their low bits are the same)
F_RETRACT, F_NEUTRAL, F_ROLL_LOCK, F_PITCH_LOCK, F_YAW_LOCK, F_YAW_IN_VEHICLE_FRAME = 1, 2, 4, 8, 16, 32


def _wrap_pi(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _clamp(v: float, low: float, high: float) -> float:
    return low if v < low else high if v > high else v


RC_OPTIONS = (212, 213, 214)  # RCn_OPTION: MOUNT1_ROLL, MOUNT1_PITCH, MOUNT1_YAW
CHANNELS = 16


class RcInput(NamedTuple):
    """The mount's channels (roll, pitch, yaw): PWM (0: no channel), stick (-1..1) and dead zone."""
    pwm: tuple[int, int, int] = (0, 0, 0)
    stick: tuple[float, float, float] = (0.0, 0.0, 0.0)
    dead_zone: tuple[int, int, int] = (10, 10, 10)


def read_rc(params: ParamStore, channel_us: Callable[[int], int]) -> RcInput:
    """The first channel with each mount option, as ArduPilot's find_channel_for_option finds it."""
    pwm, sticks, zones = [0, 0, 0], [0.0, 0.0, 0.0], [10, 10, 10]
    for axis, option in enumerate(RC_OPTIONS):
        channel = next((n for n in range(1, CHANNELS + 1) if int(params.get(f"RC{n}_OPTION", 0)) == option), None)
        if channel is None:
            continue
        pwm[axis] = channel_us(channel)
        cal = Calibration.of(params, channel)
        zones[axis] = max(cal.dead_zone_us, 10)
        sticks[axis] = stick(pwm[axis], cal) if pwm[axis] > 0 else 0.0
    return RcInput((pwm[0], pwm[1], pwm[2]), (sticks[0], sticks[1], sticks[2]), (zones[0], zones[1], zones[2]))


@dataclass
class Target:
    """Roll and pitch (earth-frame), yaw (earth-frame when yaw_ef, else body-frame) [rad]."""
    roll: float = 0.0
    pitch: float = 0.0
    yaw: float = 0.0
    yaw_ef: bool = False

    def bf_yaw(self, vehicle_yaw: float) -> float:
        return _wrap_pi(self.yaw - vehicle_yaw) if self.yaw_ef else self.yaw

    def ef_yaw(self, vehicle_yaw: float) -> float:
        return self.yaw if self.yaw_ef else _wrap_pi(self.yaw + vehicle_yaw)


class Mount:
    def __init__(self, params: ParamStore, servo_pwm: list[int], on_nan: Callable[[], None] = lambda: None):
        self.params = params
        self._constrain = Constrain(on_nan)
        self._servo_pwm = servo_pwm  # the outputs it drives (servo_relay.py's)
        kind = int(params.get("MNT1_TYPE", 0))
        self.fitted = kind in (SERVO, BRUSHLESS_PWM)  # made at boot, as ArduPilot's backends
        self.kind = kind
        self.mode = RC_TARGETING
        self.angle = Target()  # the angle target
        self.rate = Target()  # the rate target [rad/s] while is_rate
        self.is_rate = False
        self.yaw_lock = False  # RC targeting's yaw frame
        self.roi: tuple[float, float, float] | None = None  # (north, east, up above home) [m]
        self.target_sysid = 0
        self.sysid_point: tuple[float, float, float] | None = None  # where target_sysid said it is (as roi)
        self.control = (0, 0)  # the system and component in control (DO_GIMBAL_MANAGER_CONFIGURE)
        self.output = (0.0, 0.0, 0.0)  # roll, pitch, yaw put out (body-frame) [rad]
        self.next_update_s = 0.0
        self._warned_s = -math.inf
        self._last_rc: tuple[int, int, int] | None = None  # the channels when last in RC targeting (or retract)
        if self.fitted:
            self.target_sysid = int(params.get("MNT1_SYSID_DFLT", 0))
            self.set_mode(int(params.get("MNT1_DEFLT_MODE", RC_TARGETING)))

    # ----- the parameters -------------------------------------------------------------------
    def _limits(self, axis: str) -> tuple[float, float]:
        """MNT1_<axis>_MIN / _MAX [deg], as the int16 ArduPilot keeps."""
        p = self.params
        return float(as_int16(p.get(f"MNT1_{axis}_MIN", 0))), float(as_int16(p.get(f"MNT1_{axis}_MAX", 0)))

    def _vector(self, name: str) -> tuple[float, float, float]:
        """MNT1_RETRACT_* or MNT1_NEUTRAL_*: roll, pitch, yaw [rad]."""
        p = self.params
        roll, pitch, yaw = (math.radians(p.get(f"MNT1_{name}_{axis}", 0.0)) for axis in "XYZ")
        return roll, pitch, yaw

    def _axis(self, function: int, axis: str) -> bool:
        low, high = self._limits(axis)
        return bool(outputs_of(self.params, function)) and low < high

    def has_roll_control(self) -> bool:
        return self.fitted and self._axis(ROLL, "ROLL")

    def has_pitch_control(self) -> bool:
        return self.fitted and self._axis(TILT, "PITCH")

    def has_pan_control(self) -> bool:
        return self.fitted and self._axis(PAN, "YAW")

    def _option(self, bit: int) -> bool:
        return bool(int(self.params.get("MNT1_OPTIONS", 0)) & bit)

    # ----- targets --------------------------------------------------------------------------
    def set_mode(self, mode: int) -> bool:
        if not 0 <= mode < MODES:
            return False
        self.mode = mode
        return True

    def set_mode_to_default(self) -> None:
        if self.fitted:
            self.set_mode(int(self.params.get("MNT1_DEFLT_MODE", RC_TARGETING)))

    def set_angle_target(self, roll_deg: float, pitch_deg: float, yaw_deg: float, yaw_ef: bool) -> None:
        """Limited to MNT1_*_MIN..MAX (yaw only in body frame), and MAVLink targeting."""
        constrain = self._constrain
        roll_deg = constrain(roll_deg, *self._limits("ROLL"))
        pitch_deg = constrain(pitch_deg, *self._limits("PITCH"))
        if not yaw_ef:
            if yaw_deg > 180:
                yaw_deg -= 360
            yaw_deg = constrain(yaw_deg, *self._limits("YAW"))
        self.angle = Target(math.radians(roll_deg), math.radians(pitch_deg), math.radians(yaw_deg), yaw_ef)
        self.is_rate = False
        self.set_mode(MAVLINK_TARGETING)
        if self._option(LOCK_FROM_PREVIOUS_MODE):
            self.yaw_lock = yaw_ef

    def set_rate_target(self, roll_deg_s: float, pitch_deg_s: float, yaw_deg_s: float, yaw_ef: bool) -> None:
        self.rate = Target(math.radians(roll_deg_s), math.radians(pitch_deg_s), math.radians(yaw_deg_s), yaw_ef)
        self.is_rate = True
        self.set_mode(MAVLINK_TARGETING)
        if self._option(LOCK_FROM_PREVIOUS_MODE):
            self.yaw_lock = yaw_ef

    def set_roi_target(self, point: tuple[float, float, float] | None) -> None:
        """A point (north, east, up above home) [m] to look at (None: one that cannot be placed,
        which the mode goes to all the same and never looks at)."""
        self.roi = point
        self.set_mode(GPS_POINT)
        if self._option(LOCK_FROM_PREVIOUS_MODE):
            self.yaw_lock = True

    def clear_roi_target(self) -> None:
        self.roi = None
        if self.mode == GPS_POINT:
            self.set_mode_to_default()

    def set_target_sysid(self, sysid: int) -> None:
        self.target_sysid = sysid
        self.set_mode(SYSID_TARGET)
        if self._option(LOCK_FROM_PREVIOUS_MODE):
            self.yaw_lock = True

    def set_yaw_lock(self, lock: bool) -> None:
        self.yaw_lock = lock

    def warn(self, now_s: float, text: str, notify) -> None:
        """'Mount: ...', at most once in 30 s (AP_Mount_Backend::send_warning_to_GCS)."""
        if now_s - self._warned_s >= 30.0:
            notify(f"Mount: {text}")
            self._warned_s = now_s

    def configure_control(self, sysid: float, compid: float, sender: tuple[int, int]) -> bool | None:
        """DO_GIMBAL_MANAGER_CONFIGURE: who is in control; None for values out of range, else
        whether control changed. -1 keeps it, -2 the sender takes it, -3 the sender gives it up."""
        if sysid < -3 or sysid > 255 or compid < -3 or compid > 255:  # NaN passes, as in ArduPilot
            return None
        before = self.control
        code = int(sysid) if math.isfinite(sysid) else 0  # ArduPilot's int16_t of a NaN: 0 on x86
        if code == -2:
            self.control = sender
        elif code == -3:
            if self.control == sender:
                self.control = (0, 0)
        elif code != -1:
            self.control = (as_uint8(sysid), as_uint8(compid))
        return self.control != before

    # ----- the 50 Hz update -----------------------------------------------------------------
    def update(self, now_s: float, attitude, here: tuple[float, float, float] | None,
               home: tuple[float, float, float] | None, rc: RcInput = RcInput()) -> None:
        """`attitude` the vehicle's (roll, pitch, yaw) [rad]; `here` and `home` (north, east, up
        above home) [m], None when unknown; `rc` the mount's channels (read_rc)."""
        self.next_update_s = now_s + UPDATE_S
        self._rc_moved(rc)
        yaw = attitude[2]
        mode = self.mode
        if mode in (RETRACT, NEUTRAL):
            self.output = self._vector("RETRACT" if mode == RETRACT else "NEUTRAL")
            self.angle = Target(*self.output, yaw_ef=False)
            self.is_rate = False
        elif mode == RC_TARGETING:
            self._rc_target(rc)
        elif mode == GPS_POINT:
            if self.roi is not None:
                self._look_at(here, self.roi)
        elif mode == HOME_LOCATION:
            if home is not None:
                self._look_at(here, home)
        elif mode == SYSID_TARGET:
            if self.sysid_point is not None and self.target_sysid:
                self._look_at(here, self.sysid_point)
        if self.is_rate:
            self._follow_rate(yaw)
        if mode not in (RETRACT, NEUTRAL):
            self._outputs(self.angle, attitude)
        self._move(OPEN, 0 if mode == RETRACT else 1, 0, 1)
        roll, pitch, pan = self.output
        for function, value, axis in ((ROLL, roll, "ROLL"), (TILT, pitch, "PITCH"), (PAN, pan, "YAW")):
            low, high = self._limits(axis)
            self._move(function, as_int16(math.degrees(value) * 10), as_int16(low * 10), as_int16(high * 10))

    def _rc_moved(self, rc: RcInput) -> None:
        """AP_Mount_Backend::set_rctargeting_on_rcinput_change."""
        if self._last_rc is None:
            self._last_rc = rc.pwm
        if self.mode not in (RC_TARGETING, RETRACT) and any(
                abs(last - now) > zone for last, now, zone in zip(self._last_rc, rc.pwm, rc.dead_zone)):
            self.set_mode(RC_TARGETING)
        if self.mode in (RC_TARGETING, RETRACT):
            self._last_rc = rc.pwm

    def _rc_target(self, rc: RcInput) -> None:
        """The sticks across each range (yaw locked: -180..180 earth-frame), or with MNT1_RC_RATE
        rates of up to that [deg/s]."""
        roll_in, pitch_in, yaw_in = rc.stick
        rate_max = as_int16(self.params.get("MNT1_RC_RATE", 0))
        if rate_max > 0:
            r = math.radians(rate_max)
            self.rate = Target(roll_in * r, pitch_in * r, yaw_in * r, self.yaw_lock)
            self.is_rate = True
            return
        roll, pitch, yaw = (math.radians((v + 1.0) * 0.5 * (high - low) + low)
                            for v, (low, high) in zip(rc.stick, (self._limits(a) for a in ("ROLL", "PITCH", "YAW"))))
        self.angle = Target(roll, pitch, yaw_in * math.pi if self.yaw_lock else yaw, self.yaw_lock)
        self.is_rate = False

    def _look_at(self, here, point) -> None:
        if here is None:
            return
        dn, de, du = point[0] - here[0], point[1] - here[1], point[2] - here[2]
        self.angle = Target(0.0, math.atan2(du, math.hypot(dn, de)), math.atan2(de, dn), True)
        self.is_rate = False

    def _follow_rate(self, vehicle_yaw: float) -> None:
        a, r, constrain = self.angle, self.rate, self._constrain
        roll_low, roll_high = (math.radians(v) for v in self._limits("ROLL"))
        pitch_low, pitch_high = (math.radians(v) for v in self._limits("PITCH"))
        a.roll = constrain(a.roll + r.roll * UPDATE_S, roll_low, roll_high)
        a.pitch = constrain(a.pitch + r.pitch * UPDATE_S, pitch_low, pitch_high)
        if a.yaw_ef != r.yaw_ef:
            a.yaw = a.ef_yaw(vehicle_yaw) if r.yaw_ef else a.bf_yaw(vehicle_yaw)
            a.yaw_ef = r.yaw_ef
        a.yaw += r.yaw * UPDATE_S
        if a.yaw_ef:
            a.yaw = _wrap_pi(a.yaw)
        else:
            yaw_low, yaw_high = (math.radians(v) for v in self._limits("YAW"))
            a.yaw = constrain(a.yaw, yaw_low, yaw_high)

    def _outputs(self, target: Target, attitude) -> None:
        """The body-frame angles for an earth-frame target: a servo gimbal (type 1) takes the
        vehicle's lean off roll and pitch, turned to the pan angle when it pans."""
        yaw_low, yaw_high = (math.radians(v) for v in self._limits("YAW"))
        yaw_bf = self._constrain(target.bf_yaw(attitude[2]), yaw_low, yaw_high)
        roll, pitch = target.roll, target.pitch
        if self.kind == SERVO:
            lean_x, lean_y = attitude[0], attitude[1]
            if self.has_pan_control():
                c, s = math.cos(-yaw_bf), math.sin(-yaw_bf)
                lean_x, lean_y = lean_x * c - lean_y * s, lean_x * s + lean_y * c
            roll, pitch = roll - lean_x, pitch - lean_y
        self.output = (roll, pitch, yaw_bf)

    def _move(self, function: int, value: int, low: int, high: int) -> None:
        if high <= low:
            return
        share = _clamp((value - low) / (high - low), 0.0, 1.0)
        p = self.params
        for output in outputs_of(p, function):
            v = 1.0 - share if p.get(f"SERVO{output}_REVERSED", 0) else share
            servo_min, servo_max = int(p[f"SERVO{output}_MIN"]), int(p[f"SERVO{output}_MAX"])
            self._servo_pwm[output - 1] = int(servo_min + v * (servo_max - servo_min)) & 0xFFFF

    # ----- what it reports ------------------------------------------------------------------
    def attitude_quaternion(self) -> tuple[float, float, float, float]:
        """The angles put out, within the limits, on the axes it controls (w, x, y, z)."""
        roll, pitch, yaw = self.output
        constrain = self._constrain
        roll = constrain(roll, *(math.radians(v) for v in self._limits("ROLL"))) if self.has_roll_control() else 0.0
        pitch = constrain(pitch, *(math.radians(v) for v in self._limits("PITCH"))) if self.has_pitch_control() else 0.0
        yaw = constrain(yaw, *(math.radians(v) for v in self._limits("YAW"))) if self.has_pan_control() else 0.0
        cr, sr = math.cos(roll / 2), math.sin(roll / 2)
        cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
        cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
        return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)

    def device_flags(self) -> int:
        """GIMBAL_DEVICE_ATTITUDE_STATUS's flags: roll and pitch always earth-frame, yaw in the
        vehicle's frame, yaw lock as the mode has it."""
        mode = self.mode
        if mode == MAVLINK_TARGETING:
            lock = self.rate.yaw_ef if self.is_rate else self.angle.yaw_ef
        elif mode == RC_TARGETING:
            lock = self.yaw_lock
        else:
            lock = mode in (GPS_POINT, SYSID_TARGET, HOME_LOCATION)
        return ((F_RETRACT if mode == RETRACT else 0) | (F_NEUTRAL if mode == NEUTRAL else 0) | F_ROLL_LOCK
                | F_PITCH_LOCK | F_YAW_IN_VEHICLE_FRAME | (F_YAW_LOCK if lock else 0))

    def manager_flags(self) -> int:
        return F_ROLL_LOCK | F_PITCH_LOCK | (F_YAW_LOCK if self.yaw_lock else 0)

    def limits_rad(self) -> list[float]:
        """roll, pitch, yaw minimum and maximum [rad], as GIMBAL_MANAGER_INFORMATION gives them."""
        return [math.radians(v) for axis in ("ROLL", "PITCH", "YAW") for v in self._limits(axis)]


def take_roi(mount: Mount, face, point: tuple[float, float, float] | None) -> None:
    """ArduCopter's AutoYaw::set_roi: a point (north, east, up above home) to look at, None to
    clear. The vehicle turns to face it (face((north, east)): the mode's, where its heading
    follows one) unless a gimbal pans; a fitted gimbal looks at it whatever its axes."""
    if point is None:
        face(None)
        mount.clear_roi_target()
        return
    if not mount.has_pan_control():
        face(point[:2])
    if mount.fitted:
        mount.set_roi_target(point)
