"""MAV_CMD_BATTERY_RESET as ArduCopter answers it (measured on its SITL): the monitor counts from
the percentage given, the pack itself unchanged; NaN is ArduPilot's constrain of a NaN."""
from __future__ import annotations

import math

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session

from ._util import client_codec, hovering_vehicle, ready_vehicle, wire


def reset(v, s, mask: float, percentage: float) -> int:
    msg = client_codec().command_long_encode(1, 1, mav.MAV_CMD_BATTERY_RESET, 0, mask, percentage, 0, 0, 0, 0, 0)
    acks = [m for m in s.receive(wire(msg), v.time_s) if m.get_type() == "COMMAND_ACK"]
    assert len(acks) == 1
    return acks[0].result


def test_reset_sets_what_the_monitor_counts_and_it_counts_on_from_there():
    v = hovering_vehicle()
    s = Session(v, new_codec(1))
    pack_before = v.sim.battery.consumed_mah
    assert reset(v, s, 1, 10) == mav.MAV_RESULT_ACCEPTED
    assert round(v.battery_remaining * 100) == 10
    assert v.sim.battery.consumed_mah == pack_before  # the pack is as it was; only the count moved
    used = v.battery.consumed_mah
    v.run_until(v.time_s + 10.0)
    drawn = v.sim.battery.consumed_mah - pack_before
    assert drawn > 0 and math.isclose(v.battery.consumed_mah - used, drawn, rel_tol=1e-9)


def test_masks_and_limits_as_ap_battmonitor():
    v = ready_vehicle()
    s = Session(v, new_codec(1))
    assert reset(v, s, 2, 30) == mav.MAV_RESULT_ACCEPTED  # no second battery: passed over
    assert v.battery_remaining == v.sim.battery_remaining
    for percentage, left in ((150, 1.0), (-5, 0.0), (60, 0.6), (math.inf, 1.0)):
        assert reset(v, s, 3, percentage) == mav.MAV_RESULT_ACCEPTED
        assert math.isclose(v.battery_remaining, left, abs_tol=1e-6)
    assert not v.internal_errors.bits


def test_a_nan_percentage_is_fifty_and_arducopters_internal_error():
    v = ready_vehicle()
    s = Session(v, new_codec(1))
    assert reset(v, s, 1, math.nan) == mav.MAV_RESULT_ACCEPTED
    assert math.isclose(v.battery_remaining, 0.5, abs_tol=1e-6)
    assert "Internal Errors 0x400" in [t for _, t in v.events]
    assert v.prearm_failure().startswith("Internal errors 0x400")
