"""SYS_STATUS's pre-arm health bit (MAV_SYS_STATUS_PREARM_CHECK), which MAVSDK turns into
`health.is_armable` and QGroundControl into its "Ready to fly": when it follows a check that
starts or stops failing.

lag  a ready vehicle, SYS_STATUS at 10 Hz; BATT_LOW_VOLT set above the battery's voltage (a check
     that fails at once on both vehicles) and back to 0, TRIALS times each: the vehicle seconds
     from the parameter's echo to the first SYS_STATUS whose bit says so. The bit is the checks'
     last verdict, not a check made for each message, if it lags by varying amounts up to a second.
"""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Trace
from .booting import each_on_a_fresh_vehicle

AREA = "prearm_health"
TRIALS = 4
BIT = mav.MAV_SYS_STATUS_PREARM_CHECK
FAILING, PASSING = 20.0, 0.0  # BATT_LOW_VOLT: above any pack's voltage, off


def _healthy(c: Client) -> bool:
    return bool(c.last["SYS_STATUS"].onboard_control_sensors_health & BIT)


def _lag_s(c: Client, volts: float) -> float | None:
    """Set BATT_LOW_VOLT; seconds from its echo to the bit's change (None: none within 3 s)."""
    c.set_param("BATT_LOW_VOLT", volts)
    echoed_ms, want = c.now_ms, volts == PASSING
    c.last.pop("SYS_STATUS", None)
    if not c.try_wait(lambda: "SYS_STATUS" in c.last and _healthy(c) == want, 3.0):
        return None
    return (c.now_ms - echoed_ms) / 1000.0


def lag(c: Client, trace: Trace) -> None:
    c.wait(lambda: "SYS_STATUS" in c.last and _healthy(c), 120, what="the pre-arm checks passing")
    c.idle(2.0)
    lags = []
    for _ in range(TRIALS):
        lags.append(_lag_s(c, FAILING))
        c.idle(1.3)  # a phase of the once-a-second checks that differs from trial to trial
        lags.append(_lag_s(c, PASSING))
        c.idle(1.7)
    trace.fact("follows_within_1_2s", all(x is not None and x <= 1.2 for x in lags))
    trace.fact("lags_over_0_2s", any(x is not None and x > 0.2 for x in lags))


PROBES = {"lag": lag}


def run(target) -> dict[str, Trace]:
    return each_on_a_fresh_vehicle(target, PROBES, {"lag": None})
