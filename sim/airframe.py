"""Airframe constants of the default vehicle: a 1.5 kg quad in plus configuration.

Motor numbering follows the paper's mixer (eq. 2): motor 1 front (+x), 2 left (-y),
3 back (-x), 4 right (+y), body frame FRD. Motors 1 and 3 turn one way, 2 and 4 the other.

Constants are of the order published for 10-inch-prop quads of this mass: thrust coefficient
b = 3.13e-5 N s^2 and drag coefficient d = 7.5e-7 N m s^2 (Bouabdallah's OS4 rotor figures),
inertias of a 0.25 m arm frame with a central battery.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

GRAVITY_M_S2 = 9.80665


@dataclass(frozen=True)
class Airframe:
    mass_kg: float = 1.5
    arm_length_m: float = 0.25
    ixx_kg_m2: float = 0.0347
    iyy_kg_m2: float = 0.0347
    izz_kg_m2: float = 0.0658
    thrust_coeff_b: float = 3.13e-5  # F = b * omega^2  [N s^2]
    drag_coeff_d: float = 7.5e-7  # Q = d * omega^2  [N m s^2]
    motor_time_constant_s: float = 0.03
    omega_max_rad_s: float = 600.0
    omega_idle_rad_s: float = 60.0  # armed, throttle zero: props turn slowly as on a real copter
    linear_drag_n_per_m_s: float = 0.25
    angular_drag_nm_per_rad_s: float = 0.002
    prop_radius_m: float = 0.127
    figure_of_merit: float = 0.6
    motor_efficiency: float = 0.8
    # A 3S pack as ArduPilot SITL's quad flies (its full 12.6 V is SIM_BATT_VOLTAGE's default there),
    # so ArduCopter's voltage thresholds (BATT_LOW_VOLT 10.5 V: 3.5 V a cell) mean on this pack
    # what they mean on SITL's; its resistance is SITL's frame model's (refBatRes 0.01 ohm).
    battery_cells: int = 3
    battery_capacity_mah: float = 5000.0
    battery_internal_resistance_ohm: float = 0.01
    avionics_current_a: float = 0.6

    @property
    def torque_ratio_c(self) -> float:
        """c = d/b: yaw reaction torque per newton of rotor thrust [m]."""
        return self.drag_coeff_d / self.thrust_coeff_b

    @property
    def weight_n(self) -> float:
        return self.mass_kg * GRAVITY_M_S2

    @property
    def max_rotor_thrust_n(self) -> float:
        return self.thrust_coeff_b * self.omega_max_rad_s**2

    @property
    def hover_omega_rad_s(self) -> float:
        return math.sqrt(self.weight_n / (4.0 * self.thrust_coeff_b))

    def validate(self) -> None:
        """Raise ValueError naming the first field that makes no physical sense."""
        for name in ("mass_kg", "arm_length_m", "ixx_kg_m2", "iyy_kg_m2", "izz_kg_m2",
                     "thrust_coeff_b", "drag_coeff_d", "motor_time_constant_s",
                     "omega_max_rad_s", "prop_radius_m", "figure_of_merit",
                     "motor_efficiency", "battery_capacity_mah",
                     "battery_internal_resistance_ohm"):  # the sag model divides by it
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, got {value!r}")
        for name in ("linear_drag_n_per_m_s", "angular_drag_nm_per_rad_s", "avionics_current_a"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be zero or positive, got {value!r}")
        if not 0 <= self.omega_idle_rad_s < self.omega_max_rad_s:
            raise ValueError("omega_idle_rad_s must be at least 0 and below omega_max_rad_s")
        if self.battery_cells < 1:
            raise ValueError(f"battery_cells must be at least 1, got {self.battery_cells!r}")
        if 4 * self.max_rotor_thrust_n <= 1.2 * self.weight_n:
            raise ValueError("omega_max_rad_s too low: the airframe cannot lift its own weight")
