"""AUTO: flies the stored mission item by item, as ArduCopter does.

Which item is current is mission/progress.py's business (AP_Mission's rules); AUTO is its runner:
it starts the items the progress hands it and says when each is done. Navigation items (takeoff,
waypoint, loiters, land, return to launch) fly until done; "do" items (change speed, set home)
act at once. On the ground nothing is flown until AUTO may take off (MISSION_START, or the
vehicle is already flying); an armed, landed vehicle enters AUTO only if a takeoff comes first.
"""
from __future__ import annotations

import math
from dataclasses import replace

from ..c_casts import as_int16, as_uint16
from ..control.wpnav import WPNAV_SPEED_MIN_M_S, WaypointNav
from ..mission.commands import (CMD_DO_CHANGE_SPEED, CMD_DO_REPEAT_RELAY, CMD_DO_REPEAT_SERVO, CMD_DO_SET_HOME,
                                CMD_DO_SET_RELAY, CMD_DO_SET_SERVO, CMD_LAND,
                                CMD_LOITER_TIME, CMD_LOITER_UNLIM, CMD_RTL, CMD_TAKEOFF, CMD_WAYPOINT, COPTER_DO,
                                FLOWN_AS, is_nav)
from ..mission.progress import DONE_UNREPORTED, MissionProgress
from ..mission.terrain import TERRAIN_FRAMES
from ..mission.store import MissionItem
from ..params import DEFAULTS as PARAM_DEFAULTS
from ..results import Severity
from ..views import Vector3
from .auto_items import ITEMS, AutoItem
from .auto_items.guided_limits import GuidedLimits
from .auto_items.spline_waypoint import CMD_NAV_SPLINE_WAYPOINT, entry_speed
from .base import Mode, Setpoint
from .context import ModeContext
from .guided import Guided
from .guided_stop import JERK_DEFAULT_M_S3, JerkLimitedStop
from .guided_yaw import DEFAULT, GuidedYaw
from .land import Rtl, descend_and_disarm, finish_precland, steer_to_target
from .numbers import ModeNumber
from .takeoff_climb import TakeoffClimb
from .waypoint_legs import NAV_BY_LEGS, WaypointLegs, flies_through, next_nav_index

# AP_Mission_ChangeDetector compares the current navigation item and the next two: a change
# further on (or an upload writing the same items again) restarts nothing.
CHANGE_WINDOW = 3
NAV_COMMANDS = {CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME, CMD_RTL, CMD_LAND, CMD_TAKEOFF}
# Places in the list, nothing to do (AUTO RTL jumps to them): passed over in silence.
# What the mission's servo and relay items do, as AP_Mission converts them (servo_relay.py):
# servos: param 1 the output, 2 the PWM, 3 the cycles, 4 the cycle time [s]; relays: param 1 the
# relay, 2 the state or the cycles, 3 the cycle time [s]
SERVO_RELAY_ITEMS = {
    CMD_DO_SET_SERVO: lambda ctx, item: ctx.set_servo(as_uint16(item.p1) & 0xFF, as_uint16(item.p2)),
    CMD_DO_REPEAT_SERVO: lambda ctx, item: ctx.repeat_servo(as_uint16(item.p1) & 0xFF, as_uint16(item.p2),
                                                            as_int16(item.p3), item.p4),
    CMD_DO_SET_RELAY: lambda ctx, item: ctx.set_relay(as_uint16(item.p1) & 0xFF, as_uint16(item.p2) & 0xFF),
    CMD_DO_REPEAT_RELAY: lambda ctx, item: ctx.repeat_relay(as_uint16(item.p1) & 0xFF, as_int16(item.p2), item.p3),
}
GLOBAL_AMSL_FRAMES = {0, 5}  # MAV_FRAME_GLOBAL, MAV_FRAME_GLOBAL_INT: altitude above sea level


def _flown(item: MissionItem) -> MissionItem:
    """The item as this multicopter flies it (a VTOL takeoff or landing is the plain one)."""
    command = FLOWN_AS.get(item.command)
    return item if command is None else replace(item, command=command)


class Auto(Mode):
    takes_speed_change = True
    number = ModeNumber.AUTO
    plans_paths = True
    requires_terrain_failsafe = True
    requires_position = True
    requires_home = True  # items at heights above home, RTL and land items
    _ctx: ModeContext
    _rtl: Rtl  # flies the RTL item
    _index: int | None  # the navigation item being flown (None: none, holding)
    _item: MissionItem  # ... and that item
    _nav_done: bool
    _legs: WaypointLegs
    _hold_ne: tuple[float, float]
    _hold_d: float
    _waiting_to_start: bool
    _target: Vector3
    _arrived_at: float | None
    _land_d: float
    _land_descending: bool  # a land item past its fly-over: descending where it is (or on a target)
    _seen: tuple[int, int | None, tuple[tuple[int, MissionItem], ...]]
    _paused_d: float | None = None  # DO_PAUSE_CONTINUE stopped a waypoint leg at this height
    _stopping: JerkLimitedStop | None = None  # ... slowing down as it does
    _takeoff: TakeoffClimb | None = None  # the takeoff item's climb, once it has started
    _runner: AutoItem | None = None  # the navigation item being flown, when it is one of ITEMS
    _do_runner: tuple[int, AutoItem] | None = None  # the "do" or condition item of ITEMS running
    # What the navigation item before the one starting left behind (its runner, or the waypoint
    # navigator of a waypoint leg): a spline leaves a waypoint along the leg that came in.
    previous_nav: AutoItem | WaypointNav | None = None
    # The circle navigator's radius, kept from one NAV_LOITER_TURNS to the next as ArduCopter's
    # AC_Circle keeps it (an item's radius 0 flies the last one; 0 at boot: a turn on the spot),
    # and its rate: CIRCLE_RATE's default, which ArduCopter's AC_Circle copies when it is built,
    # before the parameters are loaded; a CIRCLE_RATE set later does not reach AUTO (measured: a
    # turn of 10 m takes 18.6 s with CIRCLE_RATE set to 10 after boot, as at 20).
    circle_radius_m: float = 0.0
    circle_rate_deg_s: float = PARAM_DEFAULTS["CIRCLE_RATE"]
    # ArduCopter's auto_yaw as items other than the legs set it (CONDITION_YAW's FIXED turn): it
    # overrides the legs' heading until a navigation item sets it back to DEFAULT
    heading: GuidedYaw
    guided_limits: GuidedLimits

    def __init__(self) -> None:
        # Until enter() (which may wait for home): no item flown, no destination.
        self._index = None
        self._rtl = Rtl(disarm_on_land=False)
        self._legs = WaypointLegs(self.plans_paths)  # an ROI or speed change may come before the mode is entered
        self.heading = GuidedYaw()
        # DO_GUIDED_LIMITS' last limits: kept from one AUTO to the next, as ArduCopter's GUIDED keeps them
        self.guided_limits = GuidedLimits()

    def enter(self, ctx: ModeContext) -> str | None:
        mission = ctx.mission_progress
        # ArduCopter gives one reason for both refusals ("Mode change to AUTO failed: init failed").
        if not mission.items() and ctx.armed:  # disarmed: entered, and refused at arming instead
            return "init failed"
        if ctx.armed and ctx.landed and not mission.starts_with_takeoff(self._restart(ctx)):
            ctx.notify("Auto: Missing Takeoff Cmd", Severity.CRITICAL)
            return "init failed"
        self._ctx = ctx
        self._rtl = Rtl(disarm_on_land=False)  # the mission's end disarms (mission_complete)
        self._index = None
        self._nav_done = False
        self._legs = WaypointLegs(self.plans_paths)
        self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        self._waiting_to_start = True  # the mission starts (or resumes) at the first tick
        self._paused_d = None
        self._runner = self._do_runner = None
        self.heading = GuidedYaw()
        mission.bind(self)
        return None

    def exit(self, ctx: ModeContext) -> None:
        mission = ctx.mission_progress
        if mission.running:
            here = ctx.position_global()  # where a resume's rewind measures back from
            mission.exit_e7 = (here.lat_deg * 1e7, here.lon_deg * 1e7)
            mission.stop()
        ctx.mount.set_mode_to_default()  # as ArduCopter's ModeAuto::exit

    def destination(self) -> tuple[float, float, float | None] | None:
        """The item's point, or the corner of the path round the fence flown to it."""
        if self._index is None:
            return None
        return self._legs.destination if self._legs.avoiding else getattr(self, "_target", None)

    def nav_distance_bearing(self) -> tuple[float, float] | None:
        """While a path round the fence is flown: the way to the item's point, not the corner."""
        return self._legs.way_to_final() if self._index is not None and self._legs.avoiding else None

    def pause(self, ctx: ModeContext, paused: bool) -> bool:
        """As ArduCopter's: only a waypoint leg not yet at its point stops (where the vehicle can);
        going on flies the rest of the leg from there."""
        if not paused:
            if self._paused_d is not None:
                self._paused_d = None
                self._legs.resume_jerk = ctx.params.get("PSC_JERK_XY", JERK_DEFAULT_M_S3)
            return True
        if self._paused_d is not None:
            return True
        if (self._index is None or self._item.command != CMD_WAYPOINT or self._arrived_at is not None
                or self._legs.nav is None):
            return False
        self._paused_d = ctx.body.d_m
        self._stopping = JerkLimitedStop(ctx)
        self._legs.end()
        return True

    def heading_target(self, ctx: ModeContext) -> float:
        """The heading AUTO steers to now [rad] (where a FIXED turn starts from)."""
        if self.heading.kind != DEFAULT:
            return self.heading.angle
        yaw = self._legs.auto_yaw.yaw
        return ctx.attitude[2] if yaw is None else yaw

    def set_vertical_speed(self, ctx: ModeContext, up_m_s: float | None, dn_m_s: float | None) -> bool:
        """DO_CHANGE_SPEED's climb or descent speed, for the legs begun from now on."""
        up, dn = self._legs.vertical_speeds
        self._legs.vertical_speeds = (up if up_m_s is None else up_m_s, dn if dn_m_s is None else dn_m_s)
        return True

    def set_roi(self, ctx: ModeContext, roi_ne: tuple[float, float] | None) -> bool:
        """DO_SET_ROI (item or command): the legs face the point until it is cleared, or until a
        takeoff, landing or return starts (ArduCopter's AUTO holds the heading there)."""
        self._legs.auto_yaw.roi = roi_ne
        return True

    # ----- a companion's targets, while a guided item runs (auto_items/guided_inside.py) ---------
    def _guided(self) -> Guided | None:
        return self._runner.guided if self._runner is not None else None

    @property
    def in_guided_mode(self) -> bool:  # type: ignore[override]
        return self._guided() is not None

    def set_target(self, ctx: ModeContext, pos: Vector3 | None, vel: Vector3 | None, accel: Vector3 | None,
                   yaw: float | None, yaw_rate: float | None, yaw_relative: bool = False,
                   terrain: bool = False) -> bool:
        guided = self._guided()
        return guided is not None and guided.set_target(ctx, pos, vel, accel, yaw, yaw_rate, yaw_relative, terrain)

    def set_attitude(self, ctx: ModeContext, attitude: Vector3 | None, rates: Vector3, climb_or_thrust: float,
                     use_thrust: bool) -> bool:
        guided = self._guided()
        return guided is not None and guided.set_attitude(ctx, attitude, rates, climb_or_thrust, use_thrust)

    def stop(self, ctx: ModeContext) -> bool:
        guided = self._guided()
        return guided is not None and guided.stop(ctx)

    @staticmethod
    def _restart(ctx: ModeContext) -> bool:
        return ctx.params["MIS_RESTART"] == 1

    # ----- the runner mission/progress.py calls -------------------------------------------------
    def start_command(self, index: int, item: MissionItem) -> bool:
        """Start an item; False for a navigation item this vehicle cannot fly (it is passed over)."""
        ctx = self._ctx
        item = _flown(item)
        if item.command in NAV_COMMANDS:
            start = self._runner.hand_over() if self._runner is not None else None
            self._index, self._item, self._nav_done = index, item, False
            self._runner = None
            self._begin_nav(ctx, index, item, start)
            return True
        runner_class = ITEMS.get(item.command)
        if runner_class is not None:
            return self._start_runner(ctx, index, item, runner_class())
        if is_nav(item.command):  # a navigation item this emulator does not fly
            ctx.notify(f"Skipping invalid cmd #{item.command}", Severity.WARNING)
            return False
        if item.command == CMD_DO_CHANGE_SPEED:
            if math.isfinite(item.p2) and item.p2 > 0:
                ctx.set_speed(item.p2)
        elif item.command == CMD_DO_SET_HOME:
            ctx.set_home(None if item.p1 == 1 else self._target_ned(ctx, item))
        elif item.command in SERVO_RELAY_ITEMS:
            SERVO_RELAY_ITEMS[item.command](ctx, item)
        return True

    def _start_runner(self, ctx: ModeContext, index: int, item: MissionItem, runner: AutoItem) -> bool:
        if not is_nav(item.command):
            self._do_runner = (index, runner)
            return runner.start(self, ctx, index, item)
        self.previous_nav = self._runner if self._runner is not None else self._legs.nav
        self._index, self._item, self._nav_done = index, item, False
        self._runner = runner
        if runner.resets_heading:
            self.heading.kind = DEFAULT
        self._target = self._target_ned(ctx, item)
        self._legs.end()
        if runner.start(self, ctx, index, item):
            return True
        self._index = self._runner = None
        return False

    def verify_command(self, index: int, item: MissionItem) -> bool | str:
        item = _flown(item)
        if item.command in NAV_COMMANDS:
            return index == self._index and self._nav_done
        if item.command in ITEMS:
            if is_nav(item.command):
                runner = self._runner
                if index != self._index or runner is None or not runner.done(self._ctx):
                    return False
                return True if runner.reports_reached else DONE_UNREPORTED
            return self._do_runner is None or self._do_runner[0] != index or self._do_runner[1].done(self._ctx)
        if item.command not in COPTER_DO:
            self._ctx.notify(f"Skipping invalid cmd #{item.command}", Severity.WARNING)
        return True

    def mission_complete(self) -> None:
        """As ArduCopter's exit_mission: hold where we are, or disarm if on the ground."""
        ctx = self._ctx
        self._index = self._runner = None
        self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        if ctx.landed and ctx.armed:
            ctx.disarm("mission complete")

    def item_position(self, ctx: ModeContext, item: MissionItem) -> Vector3:
        """An item's point in local NED, as AUTO flies to it (for items looking ahead)."""
        return self._target_ned(ctx, item)

    def _target_ned(self, ctx: ModeContext, item: MissionItem) -> Vector3:
        """Item position in local NED; lat/lon 0 = here, altitude 0 for takeoff/land = keep."""
        b = ctx.body
        if item.x == 0 and item.y == 0:
            n, e = b.n_m, b.e_m
        else:
            n, e, _ = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, ctx.origin_alt_m)
        if item.frame in GLOBAL_AMSL_FRAMES:
            d = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, item.z)[2]
        else:
            d = ctx.require_home()[2] - item.z
        return n, e, d

    def _begin_nav(self, ctx: ModeContext, index: int, item: MissionItem,
                   start: tuple[Vector3, Vector3] | None = None) -> None:
        self.heading.kind = DEFAULT  # as ArduCopter's wp_start, takeoff and land set auto_yaw
        self._target = self._target_ned(ctx, item)
        self._arrived_at = None
        self._takeoff = None  # a takeoff's climb starts when the vehicle may take off
        if item.command == CMD_TAKEOFF:
            b = ctx.body
            self._target = (b.n_m, b.e_m, min(self._target[2], b.d_m))
        if item.command == CMD_RTL:
            self._rtl.enter(ctx)
        self._land_d = ctx.body.d_m
        self._land_descending = False
        self._begin_leg(ctx, index, item, start)

    def _begin_leg(self, ctx: ModeContext, index: int, item: MissionItem,
                   start: tuple[Vector3, Vector3] | None = None) -> None:
        """Waypoints and loiters are flown by the waypoint navigator; other items end its legs.
        `start`: where a spline flown through left its target moving (the leg starts there)."""
        if item.command not in NAV_BY_LEGS:
            self._legs.end()
            self._legs.auto_yaw.roi = None
            return
        mission = ctx.mission_progress
        items = mission.items()
        following = next_nav_index(items, index, mission.jumps_followed())
        next_item = None if following is None else items[following]
        through = flies_through(item, next_item)
        terrain = item.frame in TERRAIN_FRAMES
        target = (self._target[0], self._target[1], -item.z) if terrain else self._target
        next_target = None
        if through and next_item is not None and (next_item.frame in TERRAIN_FRAMES) == terrain:
            next_target = self._target_ned(ctx, next_item)  # (ArduCopter flies through only in one frame)
            if terrain:
                next_target = (next_target[0], next_target[1], -next_item.z)
        self._legs.begin(ctx, target, next_target, start=start, terrain=terrain)
        nav = self._legs.nav
        if (following is not None and nav is not None and item.command == CMD_WAYPOINT and not item.p1 > 0
                and items[following].command == CMD_NAV_SPLINE_WAYPOINT):  # passed at the spline's speed
            nav.set_destination_speed(entry_speed(self, ctx, following, nav.origin, nav.destination))

    # ----- loop ----------------------------------------------------------------------------------
    def update(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        self._fly(ctx, sp, dt)
        if self.heading.kind != DEFAULT:
            self.heading.fly(sp, dt, ctx.body)

    def _fly(self, ctx: ModeContext, sp: Setpoint, dt: float) -> None:
        sp.clear()
        sp.speed_xy = ctx.nav_speed_m_s
        mission = ctx.mission_progress
        if self._waiting_to_start:
            mission.start_or_resume(self._restart(ctx))
            self._waiting_to_start = False
            self._seen = (mission.store.version, mission.nav_index, self._upcoming(mission))
        else:
            self._check_for_new_list(ctx, mission)
            mission.update()
        if self._index is None or not ctx.armed or (ctx.landed and not ctx.auto_armed):
            self._hold(ctx, sp)
            return
        if self._runner is not None:
            self._runner.update(ctx, sp, dt)
            return
        item = self._item
        if item.command == CMD_RTL:
            self._rtl.update(ctx, sp, dt)
            self._nav_done = self._rtl.touched_down(ctx)
            return
        if item.command == CMD_LAND:
            self._land(ctx, sp, item)
            return
        if item.command == CMD_TAKEOFF:
            takeoff = self._takeoff
            if takeoff is None:
                takeoff = self._takeoff = TakeoffClimb(ctx, self._target[2])
            takeoff.fly(ctx, sp, dt)
            self._nav_done = takeoff.done
            return
        if self._paused_d is not None and self._stopping is not None:
            self._stopping.fly(ctx, sp, dt)
            sp.pos_d = self._paused_d
            return
        if self._legs.nav is None:  # the leg ended (a hold on the ground, a pause): fly it from here
            self._begin_leg(ctx, self._index, item)
        elif self._legs.planned_for != max(ctx.nav_speed_m_s, WPNAV_SPEED_MIN_M_S):
            self._legs.change_speed(ctx)
        sp.speed_xy = self._legs.speed_cap
        if self._legs.update(ctx, sp, dt) and self._arrived_at is None:  # waypoints and loiters
            self._arrived_at = ctx.time_s
        if self._arrived_at is None:
            return
        hold = item.p1 if item.command in (CMD_WAYPOINT, CMD_LOITER_TIME) and math.isfinite(item.p1) else 0.0
        if item.command != CMD_LOITER_UNLIM and ctx.time_s - self._arrived_at >= max(hold, 0.0):
            if not self._nav_done and item.command in (CMD_WAYPOINT, CMD_LOITER_TIME):
                ctx.notify(f"Reached command #{self._index + 1}")
            self._nav_done = True

    def _check_for_new_list(self, ctx: ModeContext, mission: MissionProgress) -> None:
        """The list changed while the mission runs (an upload writes item by item): if the
        current navigation item or the next ones differ while the current index stayed, a
        waypoint being flown starts again, as ArduCopter's mission change detector does."""
        version, index = mission.store.version, mission.nav_index
        if version == self._seen[0] and index == self._seen[1]:
            return
        upcoming = self._upcoming(mission)
        changed, moved_on = upcoming != self._seen[2], index != self._seen[1]
        self._seen = (version, index, upcoming)
        if changed and not moved_on and mission.running and self._index is not None \
                and self._item.command == CMD_WAYPOINT:
            if mission.restart_current_nav():
                ctx.notify("Auto mission changed, restarted command", Severity.CRITICAL)
            else:
                ctx.notify("Auto mission changed but failed to restart command", Severity.CRITICAL)

    @staticmethod
    def _upcoming(mission: MissionProgress) -> tuple[tuple[int, MissionItem], ...]:
        """(index, item) of the navigation items from the current one on, CHANGE_WINDOW at most,
        following DO_JUMPs as the mission will."""
        items, index = mission.items(), mission.nav_index
        if index is None or index >= len(items):
            return ()
        if not is_nav(items[index].command):
            index = next_nav_index(items, index, mission.jumps_followed())
        upcoming: list[tuple[int, MissionItem]] = []
        while index is not None and len(upcoming) < CHANGE_WINDOW:
            upcoming.append((index, items[index]))
            index = next_nav_index(items, index, mission.jumps_followed())
        return tuple(upcoming)

    def _land(self, ctx: ModeContext, sp: Setpoint, item: MissionItem) -> None:
        n, e, _ = self._target
        b = ctx.body
        if not self._land_descending:
            if math.hypot(b.n_m - n, b.e_m - e) > 1.0 and not ctx.landed:
                sp.pos_ne, sp.pos_d = (n, e), self._land_d  # fly over the landing point first
                return
            self._land_descending = True  # as ArduCopter's land states: no going back to the fly-over
        sp.pos_ne = (n, e) if not ctx.landed else None
        steer = steer_to_target(ctx, sp)
        # Landed: ArduCopter disarms here and leaves the land item current; the disarm resets
        # the mission (so the land item is never reported reached).
        descend_and_disarm(ctx, sp)
        finish_precland(sp, steer)

    def _hold(self, ctx: ModeContext, sp: Setpoint) -> None:
        self._legs.end()  # a leg after the hold starts from where the vehicle then is
        if ctx.landed:
            self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        sp.pos_ne, sp.pos_d = self._hold_ne, self._hold_d

    def landed_state_hint(self, ctx: ModeContext) -> str | None:
        if self._index is None:
            return None
        if self._runner is not None:
            return self._runner.landed_state_hint(ctx)
        command = self._item.command
        if command == CMD_TAKEOFF:  # ArduCopter's is_taking_off: until the climb is done
            return None if self._takeoff is not None and self._takeoff.done else "TAKEOFF"
        if command == CMD_LAND:
            return "LANDING"
        if command == CMD_RTL:
            return self._rtl.landed_state_hint(ctx)
        return None
