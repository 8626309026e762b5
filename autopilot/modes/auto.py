"""AUTO: flies the stored mission item by item, as ArduCopter does.

Navigation items (takeoff, waypoint, loiters, land, return to launch) run until done; "do" items
(change speed, jump, set home) act at once. An item this emulator does not fly is announced and
skipped. On the ground the mission starts only once it is allowed to (MISSION_START, or the
vehicle is already flying), and only if it begins with a takeoff.
"""
from __future__ import annotations

import math

from ..mission.progress import MissionState
from ..results import Severity
from .base import Mode, Setpoint
from .land import Rtl, descend_and_disarm
from .numbers import ModeNumber
from .waypoint_legs import NAV_BY_LEGS, WaypointLegs, flies_through, next_nav_index

CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME, CMD_RTL, CMD_LAND, CMD_TAKEOFF = 16, 17, 19, 20, 21, 22
CMD_DO_JUMP, CMD_DO_CHANGE_SPEED, CMD_DO_SET_HOME = 177, 178, 179
NAV_COMMANDS = {CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME, CMD_RTL, CMD_LAND, CMD_TAKEOFF}
GLOBAL_AMSL_FRAMES = {0, 5}  # MAV_FRAME_GLOBAL, MAV_FRAME_GLOBAL_INT: altitude above sea level


def first_nav_is_takeoff(items) -> bool:
    for item in items:
        if item.command in NAV_COMMANDS:
            return item.command == CMD_TAKEOFF
    return False


class Auto(Mode):
    number = ModeNumber.AUTO
    requires_position = True

    def enter(self, ctx) -> str | None:
        mission = ctx.mission_progress
        items = mission.items()
        if not items:
            return "no mission"
        if ctx.armed and ctx.landed and not first_nav_is_takeoff(items[mission.index:]):
            ctx.notify("Auto: Missing Takeoff Cmd", Severity.CRITICAL)
            return "missing takeoff command"
        self._items = items
        self._version = mission.version
        self._jumps_done: dict[int, int] = {}
        self._rtl = None
        self._index = None
        self._legs = WaypointLegs()
        self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        mission.stop()  # flown once AUTO may start it (update)
        return None

    def exit(self, ctx) -> None:
        ctx.mission_progress.pause()

    # ----- item sequencing --------------------------------------------------------------------
    def _start_item(self, ctx, index: int) -> None:
        """Make `index` current; run "do" items at once until a navigation item is current."""
        for _ in range(len(self._items) + 1):  # a loop of only DO_JUMPs must not hang the vehicle
            if index >= len(self._items):
                self._finish(ctx)
                return
            item = self._items[index]
            ctx.mission_progress.set_index(index)
            if item.command in NAV_COMMANDS:
                self._index = index
                self._begin_nav(ctx, item)
                return
            index = self._do_item(ctx, index, item)
        self._finish(ctx)

    def _finish(self, ctx) -> None:
        """Mission over: hold where we are (a landed vehicle has already disarmed)."""
        self._index = None
        self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        if ctx.mission_progress.complete():
            ctx.notify("Mission complete")

    def _do_item(self, ctx, index: int, item) -> int:
        """Run a "do" item; returns the next index."""
        if item.command == CMD_DO_CHANGE_SPEED:
            if math.isfinite(item.p2) and item.p2 > 0:
                ctx.set_speed(item.p2)
        elif item.command == CMD_DO_JUMP:
            target, repeat = int(item.p1) - 1, int(item.p2)  # seq -> index (seq 0 is home)
            done = self._jumps_done.get(index, 0)
            if 0 <= target < len(self._items) and (repeat < 0 or done < repeat):
                self._jumps_done[index] = done + 1
                return target
        elif item.command == CMD_DO_SET_HOME:
            ctx.set_home(None if item.p1 == 1 else self._target_ned(ctx, item))
        else:
            ctx.notify(f"Skipping unsupported mission command {item.command}", Severity.WARNING)
        ctx.mission_progress.item_reached(index)
        return index + 1

    def _target_ned(self, ctx, item) -> tuple:
        """Item position in local NED; lat/lon 0 = here, altitude 0 for takeoff/land = keep."""
        b = ctx.body
        if item.x == 0 and item.y == 0:
            n, e = b.n_m, b.e_m
        else:
            n, e, _ = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, ctx.origin_alt_m)
        if item.frame in GLOBAL_AMSL_FRAMES:
            d = ctx.ned_of(item.x * 1e-7, item.y * 1e-7, item.z)[2]
        else:
            d = ctx.home_ned[2] - item.z
        return n, e, d

    def _begin_nav(self, ctx, item) -> None:
        self._target = self._target_ned(ctx, item)
        self._arrived_at = None
        if item.command == CMD_TAKEOFF:
            b = ctx.body
            self._target = (b.n_m, b.e_m, min(self._target[2], b.d_m))
        if item.command == CMD_RTL:
            self._rtl = Rtl()
            self._rtl.enter(ctx)
        self._land_d = ctx.body.d_m
        self._begin_leg(ctx, item)

    def _begin_leg(self, ctx, item) -> None:
        """Waypoints and loiters are flown by the waypoint navigator; other items end its legs."""
        if item.command not in NAV_BY_LEGS:
            self._legs.end()
            return
        following = next_nav_index(self._items, self._index, self._jumps_done)
        next_item = None if following is None else self._items[following]
        through = flies_through(item, next_item)
        self._legs.begin(ctx, self._target, self._target_ned(ctx, next_item) if through else None)

    def restart_at(self, ctx, index: int) -> None:
        self._start_item(ctx, index)

    def _complete(self, ctx) -> None:
        index = self._index
        ctx.mission_progress.item_reached(index)
        self._start_item(ctx, index + 1)

    # ----- loop ----------------------------------------------------------------------------------
    def update(self, ctx, sp: Setpoint, dt: float) -> None:
        sp.clear()
        sp.speed_xy = ctx.nav_speed_m_s
        mission = ctx.mission_progress
        if mission.version != self._version:  # a new mission was uploaded: hold until restarted
            self._items, self._version, self._index = mission.items(), mission.version, None
            mission.stop()
        if mission.state is MissionState.NOT_STARTED and (ctx.auto_armed or not ctx.landed):
            mission.resume()
            self._start_item(ctx, mission.index)
        if self._index is None:
            self._hold(ctx, sp)
            return
        item = self._items[self._index]
        if item.command == CMD_RTL:
            self._rtl.update(ctx, sp, dt)
            if not ctx.armed:
                self._complete(ctx)
            return
        if item.command == CMD_LAND:
            self._land(ctx, sp, item)
            return
        if item.command == CMD_TAKEOFF:
            n, e, d = self._target
            sp.pos_ne, sp.pos_d = (n, e), d
            if ctx.body.d_m <= d + 0.5:
                self._complete(ctx)
            return
        if self._legs.update(ctx, sp, dt) and self._arrived_at is None:  # waypoints and loiters
            self._arrived_at = ctx.time_s
        if self._arrived_at is None:
            return
        hold = item.p1 if item.command in (CMD_WAYPOINT, CMD_LOITER_TIME) and math.isfinite(item.p1) else 0.0
        if item.command != CMD_LOITER_UNLIM and ctx.time_s - self._arrived_at >= max(hold, 0.0):
            self._complete(ctx)

    def _land(self, ctx, sp: Setpoint, item) -> None:
        n, e, _ = self._target
        b = ctx.body
        if math.hypot(b.n_m - n, b.e_m - e) > 1.0 and not ctx.landed:
            sp.pos_ne, sp.pos_d = (n, e), self._land_d  # fly over the landing point first
            return
        sp.pos_ne = (n, e) if not ctx.landed else None
        if descend_and_disarm(ctx, sp):
            self._complete(ctx)

    def _hold(self, ctx, sp: Setpoint) -> None:
        self._legs.end()  # a leg after the hold starts from where the vehicle then is
        if ctx.landed:
            self._hold_ne, self._hold_d = (ctx.body.n_m, ctx.body.e_m), ctx.body.d_m
        sp.pos_ne, sp.pos_d = self._hold_ne, self._hold_d

    def landed_state_hint(self, ctx) -> str | None:
        if self._index is None:
            return None
        command = self._items[self._index].command
        if command == CMD_TAKEOFF:
            return "TAKEOFF"
        if command == CMD_LAND:
            return "LANDING"
        if command == CMD_RTL:
            return self._rtl.landed_state_hint(ctx)
        return None
