"""What ArduCopter does about an ADS-B threat (its AP_Avoidance_Copter), and how it recovers.

While the threat is HIGH and AVD_F_ACTION asks for more than a report, every 100 ms:
- the ADS-B failsafe is on (the heartbeat says CRITICAL, arming is refused: "ADSB threat
  detected"), and the mode it flew in is remembered, the first time;
- in LAND, THROW and FLIP it does nothing more; landed (or in the arming delay, or in STABILIZE or
  ACRO with the throttle down) it disarms;
- 5 RTL and 6 hover (LOITER) change mode once; 2 climbs at WPNAV_SPEED_UP when above the intruder,
  else descends at WPNAV_SPEED_DN (holding below RTL_ALT); 3 flies away horizontally at
  WPNAV_SPEED; 4 away in three dimensions. Those three fly AVOID_ADSB (entered the first time),
  whose velocity GUIDED holds for GUID_TIMEOUT;
- a mode change that fails, or a pilot who left AVOID_ADSB, makes the action none.
When the threat falls from HIGH, the failsafe clears, and if the mode is still the one avoidance
chose: AVD_F_RCVRY 0 stays, 1 goes back to the remembered mode, 2 RTL, 3 back to AUTO if that is
where it was; a mode that cannot be entered falls back to RTL, then LAND.

The direction away from an intruder is ArduPilot's: straight away from a slow one (under 1 m/s),
its vertical in centimetres against metres horizontally (so it is nearly vertical); else
perpendicular to its velocity.
"""
from __future__ import annotations

import math

from ..modes.numbers import ModeNumber
from ..results import Result
from ..views import EscapeView
from ..location import Loc
from .threats import ACTION_NONE, ACTION_REPORT, Obstacle

RTL, HOVER, VERTICAL, HORIZONTAL, PERPENDICULAR = 5, 6, 2, 3, 4  # MAV_COLLISION_ACTION
REMAIN, RESUME, RECOVER_RTL, RESUME_IF_AUTO = 0, 1, 2, 3  # AVD_F_RCVRY
NO_ACTION_MODES = (ModeNumber.LAND, ModeNumber.THROW, ModeNumber.FLIP)
SLOW_M_S = 1.0  # _low_velocity_threshold


def _away(threat: Obstacle, me: Loc) -> tuple[float, float, float] | None:
    """AP_Avoidance::get_vector_perpendicular: a unit vector (north, east, up) away from the threat."""
    n, e = threat.loc.ne_to(me)
    vel = threat.vel_ned
    if math.sqrt(vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2) < SLOW_M_S:
        vec = (n, e, float(me.alt_cm - threat.loc.alt_cm))  # centimetres, as ArduPilot's
    else:
        p = (n, e, (me.alt_cm - threat.loc.alt_cm) * 0.01)
        v = (vel[0], vel[1], -vel[2])
        d = p[0] * v[0] + p[1] * v[1] + p[2] * v[2]
        if abs(d) < 1.1920929e-07:
            vec = p
        else:
            k = d / (v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
            vec = (p[0] - v[0] * k, p[1] - v[1] * k, p[2] - v[2] * k)
    length = math.sqrt(vec[0] ** 2 + vec[1] ** 2 + vec[2] ** 2)
    if length == 0:
        return None
    return vec[0] / length, vec[1] / length, vec[2] / length


class CopterEscape:
    def __init__(self, vehicle: EscapeView, failsafes):
        self._v = vehicle
        self._failsafes = failsafes  # its `adsb` flag is ArduCopter's failsafe.adsb
        self._prev_mode: int = ModeNumber.STABILIZE
        self._chosen: tuple[int, int] | None = None  # (mode, the vehicle's mode changes) avoidance set

    def _set_mode(self, number: int) -> bool:
        v = self._v
        if v.set_mode(number) != Result.ACCEPTED:
            return False
        self._chosen = (number, v.mode_changes)
        return True

    def _should_disarm(self) -> bool:
        v = self._v
        if v.armed and v.time_s < v.interlock_at_s:
            return True
        mode = v.mode_number
        if mode in (ModeNumber.STABILIZE, ModeNumber.ACRO):
            return v.pilot.throttle <= 0.0 or v.landed
        if mode in (ModeNumber.AUTO, ModeNumber.AUTO_RTL):
            return not v.auto_armed and v.landed
        return v.landed

    def act(self, threat: Obstacle, action: int) -> int:
        v = self._v
        first = not self._failsafes.adsb
        if first:
            self._failsafes.adsb = True
            self._prev_mode = v.mode_number
        if v.mode_number in NO_ACTION_MODES:
            return ACTION_NONE
        if action > ACTION_REPORT and self._should_disarm():
            v.disarm("ADS-B avoidance", force=True)
            return ACTION_NONE
        if action in (RTL, HOVER):
            if first and not self._set_mode(ModeNumber.RTL if action == RTL else ModeNumber.LOITER):
                return ACTION_NONE
            return action
        if action in (VERTICAL, HORIZONTAL, PERPENDICULAR):
            return action if self._fly_away(threat, action, first) else ACTION_NONE
        return action

    def _fly_away(self, threat: Obstacle, action: int, first: bool) -> bool:
        v = self._v
        if first and v.mode_number != ModeNumber.AVOID_ADSB and not self._set_mode(ModeNumber.AVOID_ADSB):
            return False
        if v.mode_number != ModeNumber.AVOID_ADSB:
            return False
        p = v.params
        me = v.adsb_location()
        below_rtl_alt = v.height_above_home_m() * 100.0 < p["RTL_ALT"]
        if action == VERTICAL:
            if me is not None and me.alt_cm > threat.loc.alt_cm:
                up = p["WPNAV_SPEED_UP"]
            else:
                up = 0.0 if below_rtl_alt else -p["WPNAV_SPEED_DN"]
            north = east = 0.0
        else:
            away = _away(threat, me) if me is not None else None
            if away is None:
                return False
            north, east, up = away
            if action == HORIZONTAL:
                flat = math.hypot(north, east)
                if flat == 0:
                    return False
                north, east, up = north / flat, east / flat, 0.0
            elif up > 0:
                up *= p["WPNAV_SPEED_UP"]
            else:
                up = 0.0 if below_rtl_alt else up * p["WPNAV_SPEED_DN"]
            north, east = north * p["WPNAV_SPEED"], east * p["WPNAV_SPEED"]
        v.guided_velocity(north / 100.0, east / 100.0, -up / 100.0)
        return True

    def recover(self, recovery: int) -> None:
        if not self._failsafes.adsb:
            return
        self._failsafes.adsb = False
        v = self._v
        if self._chosen != (v.mode_number, v.mode_changes):
            return  # the pilot or a ground station has changed mode since: theirs stands
        if recovery == RESUME:
            self._set_mode_or_rtl_or_land(self._prev_mode)
        elif recovery == RECOVER_RTL:
            self._set_mode_or_rtl_or_land(ModeNumber.RTL)
        elif recovery == RESUME_IF_AUTO and self._prev_mode == ModeNumber.AUTO:
            self._set_mode_or_rtl_or_land(ModeNumber.AUTO)

    def _set_mode_or_rtl_or_land(self, number: int) -> None:
        v = self._v
        if v.set_mode(number) != Result.ACCEPTED and v.set_mode(ModeNumber.RTL) != Result.ACCEPTED:
            v.set_mode(ModeNumber.LAND)
