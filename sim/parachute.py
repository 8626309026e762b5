"""A recovery parachute's canopy: once deployed it opens over `inflation_s` and then drags the
vehicle through the air with a force of 1/2 rho Cd A |v|^2 against the air-relative velocity.

The defaults are those of a common 36-inch (0.91 m) round canopy sold for 1-2 kg multicopters:
area 0.65 m^2, drag coefficient about 1.5, so Cd A about 0.95 m^2, which lets this 1.5 kg
airframe down at about 5 m/s; such canopies open in roughly half a second. The air is the
standard atmosphere's at sea level.

The drag is integrated exactly over a step (a body slowed by quadratic drag alone keeps
v / (1 + k |v| dt)), so a canopy opening at speed cannot overshoot, whatever the step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

AIR_DENSITY_KG_M3 = 1.225


@dataclass(frozen=True)
class Canopy:
    drag_area_m2: float = 0.95  # Cd x A
    inflation_s: float = 0.5  # from deployment to fully open

    def validate(self) -> None:
        """Raise ValueError naming a field that makes no physical sense."""
        for name in ("drag_area_m2", "inflation_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be zero or positive, got {value!r}")

    def drag_area_at(self, since_deploy_s: float) -> float:
        """Cd x A this long after deployment: growing linearly while it inflates."""
        if since_deploy_s <= 0.0:
            return 0.0
        if since_deploy_s >= self.inflation_s:
            return self.drag_area_m2
        return self.drag_area_m2 * since_deploy_s / self.inflation_s

    def sink_rate_m_s(self, mass_kg: float, gravity_m_s2: float) -> float:
        """The steady descent under the open canopy, body drag aside (inf: no canopy)."""
        if self.drag_area_m2 <= 0.0:
            return math.inf
        return math.sqrt(2.0 * mass_kg * gravity_m_s2 / (AIR_DENSITY_KG_M3 * self.drag_area_m2))


def slowed(velocity_ned: tuple, wind_ned: tuple, drag_area_m2: float, mass_kg: float,
           dt: float) -> tuple[float, float, float]:
    """The velocity after `dt` of canopy drag alone (other forces are integrated by the body's step)."""
    vn, ve, vd = velocity_ned
    an, ae, ad = vn - wind_ned[0], ve - wind_ned[1], vd - wind_ned[2]  # the air past the canopy
    speed = math.sqrt(an * an + ae * ae + ad * ad)
    if speed == 0.0 or drag_area_m2 <= 0.0:
        return vn, ve, vd
    k = 0.5 * AIR_DENSITY_KG_M3 * drag_area_m2 / mass_kg
    keep = 1.0 / (1.0 + k * speed * dt)
    return wind_ned[0] + an * keep, wind_ned[1] + ae * keep, wind_ned[2] + ad * keep
