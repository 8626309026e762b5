"""The gain sets AUTOTUNE flies on, as parameter values by ArduCopter's names: the original gains
(between dances and when the pilot takes over), the in-between set (original, with a tenth of the
I: while levelling), the test set (the tuned axis's candidate gains, almost no I), the tuned set
(what the pilot tests and a disarm saves)."""
from __future__ import annotations

from collections.abc import Mapping
from typing import Protocol

from .axes import Axis
from .rules import AxisGains

PI_RATIO_TESTING = 0.1    # I as a share of P while levelling between twitches
PI_RATIO_TEST = 0.01      # ... during a twitch
PI_RATIO_FINAL = 1.0      # ... tuned roll and pitch
YAW_PI_RATIO_FINAL = 0.1  # ... tuned yaw


class Params(Protocol):
    """What the gain sets read: the parameter store, or a GainOverlay on it."""

    def __getitem__(self, name: str, /) -> float: ...
    def get(self, name: str, default=None, /): ...


def original(params: Params, axis: Axis) -> AxisGains:
    """The gains the dance starts from, read from the parameters."""
    r = axis.rate
    return AxisGains(rp=params[f"ATC_RAT_{r}_P"], rd=params[f"ATC_RAT_{r}_D"], sp=params[f"ATC_ANG_{r}_P"],
                     accel=params[f"ATC_ACCEL_{axis.accel}_MAX"], flte=params[f"ATC_RAT_{r}_FLTE"])


def between_twitches(orig: dict[str, AxisGains], axes: tuple[Axis, ...]) -> dict[str, float]:
    out: dict[str, float] = {}
    for axis in axes:
        g, r = orig[axis.rate], axis.rate
        out.update({f"ATC_RAT_{r}_P": g.rp, f"ATC_RAT_{r}_I": g.rp * PI_RATIO_TESTING,
                    f"ATC_RAT_{r}_D": g.rd, f"ATC_ANG_{r}_P": g.sp})
        if axis.index == 2:
            out[f"ATC_RAT_{r}_FLTE"] = g.flte
    return out


def testing(between: dict[str, float], axis: Axis, g: AxisGains) -> dict[str, float]:
    """The in-between set with the twitching axis on its candidate gains (yaw's Yaw(E) with no D)."""
    r = axis.rate
    out = dict(between)
    out.update({f"ATC_RAT_{r}_P": g.rp, f"ATC_RAT_{r}_I": g.rp * PI_RATIO_TEST,
                f"ATC_RAT_{r}_D": g.rd if axis.d_gain == "rd" else 0.0, f"ATC_ANG_{r}_P": g.sp,
                f"ATC_RAT_{r}_FLTT": 0.0})  # the step unfiltered: the rate D kicks on it
    if axis.d_gain == "flte":
        out[f"ATC_RAT_{r}_FLTE"] = g.flte
    return out


def tuned(tune: dict[str, AxisGains], completed: tuple[Axis, ...], enabled: tuple[Axis, ...]) -> dict[str, float]:
    """The tuned gains of the completed axes (load_tuned_gains / save_tuning_gains)."""
    out: dict[str, float] = {}
    for axis in completed:
        g, r = tune[axis.rate], axis.rate
        ratio = YAW_PI_RATIO_FINAL if axis.index == 2 else PI_RATIO_FINAL
        out.update({f"ATC_RAT_{r}_P": g.rp, f"ATC_RAT_{r}_I": g.rp * ratio, f"ATC_ANG_{r}_P": g.sp,
                    f"ATC_ACCEL_{axis.accel}_MAX": g.accel})
        if axis.index != 2 or any(a.d_gain == "rd" and a.index == 2 for a in enabled):
            out[f"ATC_RAT_{r}_D"] = g.rd
        if axis.index == 2 and any(a.d_gain == "flte" for a in enabled):
            out[f"ATC_RAT_{r}_FLTE"] = g.flte
    return out


class GainOverlay:
    """The parameters with some gains in their place: what the controllers are configured from
    while AUTOTUNE flies a set that is not (yet) the parameters' own."""

    def __init__(self, params: Params, gains: Mapping[str, float]):
        self.params, self.gains = params, gains

    def __getitem__(self, name: str) -> float:
        value = self.gains.get(name)
        return self.params[name] if value is None else value

    def get(self, name: str, default=None):
        value = self.gains.get(name)
        return self.params.get(name, default) if value is None else value
