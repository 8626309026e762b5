"""What AUTOTUNE tunes, in ArduCopter's order: the axes (AUTOTUNE_AXES bits) and, per axis, the
sequence of tune types, each repeated until AUTOTUNE_SUCCESS_COUNT twitches agree."""
from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


@dataclass(frozen=True)
class Axis:
    name: str      # as ArduCopter's texts name it
    bit: int       # its AUTOTUNE_AXES bit
    index: int     # 0 roll, 1 pitch, 2 yaw: the body rate and Euler angle it turns
    rate: str      # its ATC_RAT_<rate>_* and ATC_ANG_<rate>_P names
    accel: str     # its ATC_ACCEL_<accel>_MAX name
    d_gain: str    # what the Rate D steps move: the rate D gain, or yaw's error filter (FLTE)


ROLL = Axis("Roll", 1, 0, "RLL", "R", "rd")
PITCH = Axis("Pitch", 2, 1, "PIT", "P", "rd")
YAW = Axis("Yaw(E)", 4, 2, "YAW", "Y", "flte")  # Yaw(E): tunes the error filter, no D
YAW_D = Axis("Yaw(D)", 8, 2, "YAW", "Y", "rd")
AXES = (ROLL, PITCH, YAW, YAW_D)


class TuneType(Enum):
    RATE_D_UP = "Rate D Up"
    RATE_D_DOWN = "Rate D Down"
    RATE_P_UP = "Rate P Up"
    ANGLE_P_DOWN = "Angle P Down"
    ANGLE_P_UP = "Angle P Up"

    @property
    def steps_angle(self) -> bool:
        """An angle step (the Angle P tunes), not a rate step."""
        return self in (TuneType.ANGLE_P_DOWN, TuneType.ANGLE_P_UP)


SEQUENCE = (TuneType.RATE_D_UP, TuneType.RATE_D_DOWN, TuneType.RATE_P_UP, TuneType.ANGLE_P_DOWN,
            TuneType.ANGLE_P_UP)
SUCCESS_COUNT = 4  # twitches in a row that agree before a tune type is done


def enabled_axes(bitmask: int) -> tuple[Axis, ...]:
    """The axes AUTOTUNE_AXES asks for, in the order they are tuned."""
    return tuple(axis for axis in AXES if int(bitmask) & axis.bit)


def completed_names(axes: tuple[Axis, ...]) -> str:
    """The axes in ArduCopter's "... gains for Roll Pitch Yaw(E)" texts: each but yaw's followed
    by a space, as its format string has them."""
    return "".join(a.name if a.index == 2 else a.name + " " for a in axes)
