"""Flight-mode interface and the setpoint a mode hands to the controllers.

A mode declares what it needs and allows (data, not branches in the vehicle), is entered with
`enter()` (which may refuse), fills the setpoint in `update()`, and tidies up in `exit()`.
Modes see the vehicle only through the small context interface documented on `Mode`.
"""
from __future__ import annotations

import math
from typing import overload

from ..control.position import stopping_point_ne
from .context import ModeContext
from ..views import Vector3
from .numbers import ModeNumber


class Setpoint:
    """What the controllers should achieve this tick. None = that loop is not controlled.

    Horizontal: pos_ne (hold/track a point) with vel_ne as feed-forward, or vel_ne alone, or
    lean (roll, pitch) for manual modes; accel_ne, when set, is the acceleration of a trajectory
    already shaped within the limits (waypoint navigation): followed as it is, not slewed. Vertical: pos_d with vel_d feed-forward, or vel_d alone,
    or throttle (0..1) for manual modes. Yaw: yaw (heading) plus yaw_rate feed-forward.
    rates, when set, are body-rate targets (p, q, r) [rad/s] that replace the angle loop (ACRO,
    FLIP): lean and yaw are then ignored and the heading target follows the vehicle.
    """
    __slots__ = ("pos_ne", "vel_ne", "accel_ne", "lean", "pos_d", "vel_d", "throttle", "yaw", "yaw_rate",
                 "speed_xy", "speed_up", "speed_dn", "rates")
    pos_ne: tuple[float, float] | None
    vel_ne: tuple[float, float]
    accel_ne: tuple[float, float] | None
    lean: tuple[float, float] | None
    pos_d: float | None
    vel_d: float
    throttle: float | None
    yaw: float | None
    yaw_rate: float
    speed_xy: float
    speed_up: float | None
    speed_dn: float | None
    rates: tuple[float, float, float] | None

    def __init__(self) -> None:
        self.clear()

    def clear(self) -> None:
        self.pos_ne = None
        self.vel_ne = (0.0, 0.0)
        self.accel_ne = None
        self.lean = None
        self.pos_d = None
        self.vel_d = 0.0
        self.throttle = None
        self.yaw = None
        self.yaw_rate = 0.0
        self.speed_xy = math.inf
        self.speed_up = None
        self.speed_dn = None
        self.rates = None

    def wants_climb(self, d_m: float) -> bool:
        """Whether this setpoint asks a landed vehicle to leave the ground: a height above it, or
        a climb (alone, or fed forward to a height: a takeoff's profile leaving the ground)."""
        if self.throttle is not None:
            return self.throttle > 0.05
        if self.pos_d is not None and self.pos_d < d_m - 0.2:
            return True
        return self.vel_d < -0.05


@overload
def shifted(point: None, dn: float, de: float) -> None: ...
@overload
def shifted(point: tuple[float, float], dn: float, de: float) -> tuple[float, float]: ...


def shifted(point, dn, de):
    """A held point moved by a position reset (Mode.position_reset); None stays None."""
    return None if point is None else (point[0] + dn, point[1] + de)


class Mode:
    """Base flight mode. Every method gets `ctx`, a ModeContext (context.py): what a mode may see
    of the vehicle and do to it.

    Declared capabilities, read by the vehicle: requires_position (refused without a 3D fix),
    requires_home (measures from home: refused armed without it; entered disarmed, it waits, its
    enter() deferred until home is set, as ArduCopter lets a disarmed vehicle choose it), allows_arming, has_user_takeoff (NAV_TAKEOFF while armed on the ground: the mode implements
    user_takeoff), manual_throttle (the pilot's throttle stick is the thrust), requires_flow (refused
    without a healthy optical flow sensor). Ground-station
    targets (goto, velocity, heading) are refused unless the mode flies them (GUIDED).
    """
    number: ModeNumber  # set by each mode; its name is the table's
    name: str = "?"
    text_name: str = "?"  # what ArduCopter calls it in its texts (Mode::name(): "SMARTRTL", "AUTO RTL")
    requires_position = False
    requires_home = False
    allows_arming = False
    takes_speed_change = False  # DO_CHANGE_SPEED accepted (ArduCopter: GUIDED, AUTO, RTL)
    has_user_takeoff = False
    manual_throttle = False
    auto_disarms = True  # DISARM_DELAY disarms a vehicle landed in this mode (ArduCopter: all but THROW)
    # Flies up from the ground with no takeoff of its own (SMART_RTL): ArduCopter's land detector
    # reports that as an internal error, which then refuses arming until a reboot.
    climbs_without_takeoff = False
    in_guided_mode = False  # takes GUIDED's targets (ArduCopter's in_guided_mode: GUIDED, GUIDED_NOGPS)
    # Armed with the motors shut down (ArduCopter's SHUT_DOWN spool state: THROW waiting with
    # THROW_MOT_START 0): nothing spins and nothing is controlled. A mode sets it on itself.
    motors_stopped = False
    skips_arming_delay = False  # the motors may spin at once on arming (ArduCopter: THROW)
    # Its waypoint legs go round the fence by OA_TYPE's path planner (ctx.path_planner), as
    # ArduCopter's legs flown by its wp_nav (AC_WPNav_OA) do: AUTO, GUIDED, RTL, SMART_RTL (measured)
    plans_paths = False
    # ArduCopter's crash checks watch it (crash_check_enabled: all but ACRO and FLIP): a parachute
    # releases itself on a sink rate only in these
    checks_for_crashes = True
    # Needs the optical flow sensor enabled and healthy to be entered (FLOWHOLD): the vehicle refuses
    # it otherwise, as ArduCopter's init() does ("init failed")
    requires_flow = False
    # Terrain data missing for TERRAIN_TIMEOUT_S in it is a failsafe (requires_terrain_failsafe: AUTO,
    # GUIDED, RTL): the modes whose legs may be flown above terrain
    requires_terrain_failsafe = False
    # A value the mode reports by name (NAMED_VALUE_FLOAT), as ArduCopter's FLOWHOLD its height
    # estimate "HEST": (name, value), or None
    named_float: tuple[bytes, float] | None = None

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if "number" in cls.__dict__:
            cls.name = cls.number.name
            if "text_name" not in cls.__dict__:
                cls.text_name = cls.name

    def enter(self, ctx: ModeContext) -> str | None:
        """Prepare to take over; return None to accept, or the reason for refusing."""
        return None

    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        raise NotImplementedError

    def exit(self, ctx: ModeContext) -> None:
        pass

    def on_disarm(self, ctx: ModeContext, flying_it: bool) -> None:
        """The vehicle disarmed (flying_it: in this mode). AUTOTUNE saves or forgets its gains."""

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        """'TAKEOFF' or 'LANDING' while the mode is doing either, else None."""
        return None

    def restart_without_terrain(self, ctx: ModeContext) -> None:
        """The terrain failsafe in this mode (RTL's: its return starts again above home)."""

    def position_reset(self, dn: float, de: float) -> None:
        """The estimate's horizontal position jumped by (dn, de) on a change of its source: the
        point held moves with it, so that the vehicle stays where it is in the world (measured on
        ArduCopter, GUIDED holding after a takeoff: no move in the 10 s after the jump; the position
        controller's handle_ekf_xy_reset, which shifts whatever point it holds). GUIDED, LOITER,
        BRAKE (and POSHOLD's brake) and LAND move their held point; a mission's or a ground
        station's waypoints stay where they are in the local frame."""

    def controls_position(self, ctx: ModeContext) -> bool:
        """The horizontal position controller flies this mode (HEARTBEAT's GUIDED_ENABLED flag,
        as ArduCopter sets it from its position controller)."""
        return self.requires_position

    def destination(self) -> tuple[float, float, float | None] | None:
        """The point (local NED; d None = any height) the mode is flying to, if it flies to one:
        NAV_CONTROLLER_OUTPUT's bearing and distance to the waypoint."""
        return None

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """NAV_CONTROLLER_OUTPUT's (wp_dist [m], target_bearing) when the mode reports them
        otherwise than as the way to its destination (FOLLOW, as ArduCopter's does); None: that way."""
        return None

    # ----- commands from a ground station; refused unless the mode flies them ----------------
    def user_takeoff(self, ctx: ModeContext, alt_above_home_m: float) -> None:
        """Climb to alt_above_home_m; called only if has_user_takeoff, armed on the ground."""
        raise NotImplementedError(f"{self.name} declares no user takeoff")

    def goto(self, ctx: ModeContext, n: float, e: float, d: float | None, yaw: float | None,
             vel_ff: Vector3, terrain: bool = False) -> bool:
        """Fly to a local NED point (d None: keep the height); False if this mode does not."""
        return False

    def set_velocity(self, ctx: ModeContext, vn: float, ve: float, vd: float, yaw: float | None) -> bool:
        return False

    def set_heading(self, ctx: ModeContext, yaw_rad: float) -> bool:
        return False

    def set_target(self, ctx: ModeContext, pos: Vector3 | None, vel: Vector3 | None, accel: Vector3 | None,
                   yaw: float | None, yaw_rate: float | None, yaw_relative: bool = False,
                   terrain: bool = False) -> bool:
        """GUIDED's position / velocity / acceleration target (local NED, None = not given;
        terrain: the position's down is less its height above the terrain, not the origin's)."""
        return False

    def set_attitude(self, ctx: ModeContext, attitude: Vector3 | None, rates: Vector3, climb_or_thrust: float,
                     use_thrust: bool) -> bool:
        """GUIDED's attitude target (roll, pitch, yaw; None = turn at the body rates)."""
        return False

    def stop(self, ctx: ModeContext) -> bool:
        """An invalid GUIDED target: stop as the mode stops."""
        return False

    def turn(self, ctx: ModeContext, angle: float, rate: float, direction: int, relative: bool) -> bool:
        """CONDITION_YAW's turn, in the modes that steer the heading by it."""
        return False

    def set_roi(self, ctx: ModeContext, roi_ne: tuple[float, float] | None) -> bool:
        """DO_SET_ROI's point (north, east) to face, in the modes whose heading follows one (None:
        cleared); False where the heading is the pilot's or the mode's own."""
        return False

    def pause(self, ctx: ModeContext, paused: bool) -> bool:
        """DO_PAUSE_CONTINUE: stop (paused) or go on; False if the mode cannot."""
        return False

    def set_vertical_speed(self, ctx: ModeContext, up_m_s: float | None, dn_m_s: float | None) -> bool:
        """DO_CHANGE_SPEED's climb or descent speed; False if the mode flies none."""
        return False


def hold_here(ctx: ModeContext) -> tuple[tuple[float, float], float]:
    """Current horizontal position and height: the point a mode holds when it takes over."""
    b = ctx.body
    return (b.n_m, b.e_m), b.d_m


def stopping_point(ctx: ModeContext) -> tuple[tuple[float, float], float]:
    """Where the position controller brings the vehicle to rest from its present horizontal
    velocity, and its present height: the point GUIDED holds when it takes over at speed (as
    ArduCopter's, which stops ahead instead of flying back to where the mode changed)."""
    b = ctx.body
    kp, accel = ctx.params["PSC_POSXY_P"], ctx.params["WPNAV_ACCEL"] / 100.0
    if kp <= 0 or accel <= 0:
        return hold_here(ctx)
    return stopping_point_ne(b.n_m, b.e_m, b.vn_m_s, b.ve_m_s, kp, accel), b.d_m


def stick_deadzone(value: float, zone: float = 0.05) -> float:
    """Pilot stick (-1..1) with a centre dead-zone, rescaled to stay continuous."""
    if abs(value) <= zone:
        return 0.0
    return math.copysign((abs(value) - zone) / (1.0 - zone), value)
