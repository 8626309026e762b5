"""Wind: a steady vector from the scenario (meteorological convention: the direction it blows from)."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SteadyWind:
    speed_m_s: float = 0.0
    from_direction_deg: float = 0.0

    def velocity_ned(self) -> tuple:
        to = math.radians(self.from_direction_deg + 180.0)
        return (self.speed_m_s * math.cos(to), self.speed_m_s * math.sin(to), 0.0)
