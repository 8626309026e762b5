"""The land detector and ArduCopter's auto-disarm (DISARM_DELAY).

Landed: armed, with the thrust demand below most of the weight and (almost) no motion for
MOTOR_WIND_DOWN_S + LAND_DETECT_S. Taken off: risen 0.2 m above home or climbing. Disarmed means landed.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from firefly.sim.rigid_body import BodyState

LAND_DETECT_S = 1.0
# ArduCopter starts its one-second count only once the motors reach their lower limit, which
# takes its vertical-acceleration integrator about a second to unwind from hover throttle after
# touchdown (ArduCopter SITL: 2.4 s and 3.4 s from 0.2 m above home to the disarm). Firefly's
# thrust demand drops at touchdown, so the unwinding is counted as time.
MOTOR_WIND_DOWN_S = 1.0
LOW_THRUST_SHARE = 0.85  # of the weight: the motors no longer carry the vehicle
STILL_VD_M_S = 0.3
STILL_VNE_M_S = 0.5
RISEN_M = 0.2  # above home: off the ground
CLIMBING_VD_M_S = -0.3


class LandDetector:
    def __init__(self, weight_n: float):
        self.weight_n = weight_n
        self.landed = True
        self._landed_since: float | None = None
        self.landed_at_s = 0.0  # sim time the vehicle was last found landed

    def set_landed(self) -> None:
        """On arming: the vehicle stands on the ground until it rises."""
        self.landed = True

    def update(self, body: BodyState, armed: bool, home_d_m: float, thrust_n: float, now_s: float) -> bool:
        """Called at the flight-mode rate; True at the tick the vehicle is found landed."""
        if self.landed:
            if armed and (body.d_m < home_d_m - RISEN_M or body.vd_m_s < CLIMBING_VD_M_S):
                self.landed = False
                self._landed_since = None
            return False
        if not armed:
            self.landed = True
            return False
        low_thrust = thrust_n < LOW_THRUST_SHARE * self.weight_n
        still = abs(body.vd_m_s) < STILL_VD_M_S and math.hypot(body.vn_m_s, body.ve_m_s) < STILL_VNE_M_S
        if not (low_thrust and still):
            self._landed_since = None
            return False
        if self._landed_since is None:
            self._landed_since = now_s
            return False
        if now_s - self._landed_since >= MOTOR_WIND_DOWN_S + LAND_DETECT_S:
            self.landed = True
            self.landed_at_s = now_s
            return True
        return False


class AutoDisarm:
    """Disarm after DISARM_DELAY seconds landed with nothing asking to climb."""

    def __init__(self) -> None:
        self._since: float | None = None

    def restart(self, now_s: float) -> None:
        """Count from now (on arming and on landing)."""
        self._since = now_s

    def cancel(self) -> None:
        """Stop counting (a takeoff was commanded)."""
        self._since = None

    def due(self, armed: bool, landed: bool, wants_climb: bool, delay_s: float, now_s: float) -> bool:
        """Called at the flight-mode rate; True when the vehicle should disarm now."""
        if not armed or delay_s <= 0:
            return False
        if not landed or wants_climb:
            self._since = None
            return False
        if self._since is None:
            self._since = now_s
            return False
        return now_s - self._since >= delay_s
