"""A load hanging below the vehicle on a string (a gripper's cargo): while the vehicle is at least
the string's length above the ground the load hangs from it, and everything that accelerates the
vehicle but gravity moves both, so it acts on the vehicle's mass and the load's together; lower,
the load rests on the ground and the vehicle flies alone.

The airframe's physics step moves the airframe's own mass; `carried` takes the velocity change of
an interval it stepped and gives it as the heavier whole would have made it.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SlungLoad:
    mass_kg: float
    string_m: float = 2.0

    def hangs(self, height_above_ground_m: float) -> bool:
        return height_above_ground_m >= self.string_m


def carried(v_before: tuple, v_after: tuple, gravity_dv: float, vehicle_kg: float,
            load_kg: float) -> tuple[float, float, float]:
    """The velocity after an interval that took v_before to v_after with the vehicle's mass alone
    (gravity_dv: what gravity added downwards in it), had it carried the load as well."""
    keep = vehicle_kg / (vehicle_kg + load_kg)
    n0, e0, d0 = v_before
    n1, e1, d1 = v_after
    return n0 + (n1 - n0) * keep, e0 + (e1 - e0) * keep, d0 + gravity_dv + (d1 - d0 - gravity_dv) * keep
