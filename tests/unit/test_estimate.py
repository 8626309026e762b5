"""The state estimate (estimate.py): samples at fixed sim rates, the barometric height."""
from __future__ import annotations

import pytest

from firefly.autopilot.estimate import DEAD_RECKONING_S, GPS_RATE_HZ, TEMPERATURE_RATE_HZ
from firefly.autopilot.mavlink.dialect import mavlink as mav

from ._session_link import Link
from ._util import command_long, hovering_vehicle, ready_vehicle


def sample_times(v, attribute: str, seconds: float) -> list[float]:
    """Sim times at which the estimate's `attribute` took a new value."""
    seen, times = getattr(v.estimate, attribute), []
    end = v.time_s + seconds
    while v.time_s < end - 1e-9:
        v.step()
        if getattr(v.estimate, attribute) is not seen:
            seen = getattr(v.estimate, attribute)
            times.append(v.time_s)
    return times


@pytest.mark.parametrize("attribute, rate_hz", [("gps", GPS_RATE_HZ), ("temperature", TEMPERATURE_RATE_HZ)])
def test_sensors_are_sampled_at_their_own_fixed_rate(attribute, rate_hz):
    times = sample_times(ready_vehicle(), attribute, 2.0)
    assert len(times) == round(2.0 * rate_hz)
    gaps = {round(b - a, 9) for a, b in zip(times, times[1:])}
    assert gaps == {round(1.0 / rate_hz, 9)}


def test_what_telemetry_asks_for_does_not_change_the_noise():
    quiet, chatty = ready_vehicle(), ready_vehicle()
    link = Link(chatty)
    for _ in range(50):
        link.send(command_long(mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_GPS_RAW_INT))
        quiet.run_until(quiet.time_s + 0.03)
        chatty.run_until(chatty.time_s + 0.03)
    assert quiet.estimate.gps == chatty.estimate.gps and quiet.estimate.baro_alt_m == chatty.estimate.baro_alt_m


def test_a_drifting_barometer_moves_the_height_estimate_not_the_truth():
    v = hovering_vehicle(10.0)
    true_d = v.sim.state.body.d_m
    assert v.body.d_m == true_d  # ideal while the barometer is good
    v.params.set("SIM_BARO_DRIFT", 1.0)
    v.run_until(v.time_s + 3.0)
    assert v.estimate.alt_error_m == pytest.approx(3.0, abs=0.05)
    assert v.body.d_m == pytest.approx(v.sim.state.body.d_m - v.estimate.alt_error_m)
    # it holds the height it believes in: the truth sinks after the error (the loop lags a ramp)
    assert 1.5 < v.sim.state.body.d_m - true_d <= v.estimate.alt_error_m + 0.05


def test_the_position_is_known_with_a_3d_fix_and_dead_reckoned_for_7_s_after():
    """As ArduCopter's EKF3 (posRetryTimeNoVel_ms): the position times out 7 s after the last fix."""
    v = ready_vehicle()
    assert v.estimate.has_position()
    v.params.set("SIM_GPS1_ENABLE", 0)
    v.run_until(v.time_s + 0.2)
    assert v.estimate.gps.fix_type == 1
    t_lost = v.estimate.last_fix_s
    v.run_until(t_lost + DEAD_RECKONING_S - 0.05)
    assert v.estimate.has_position()
    v.run_until(t_lost + DEAD_RECKONING_S + 0.15)
    assert not v.estimate.has_position()
