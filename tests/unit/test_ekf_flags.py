"""EKF_STATUS_REPORT's EKF_POS_VERT_AGL: ArduCopter's EKF3 has a terrain height only from a good
downward range within 5 s (measured on its SITL, area ekf_flags: 0x33f without a rangefinder,
0x37f hovering within its range, 0x33f again some seconds above it)."""
from __future__ import annotations

import pytest
from pymavlink.dialects.v20 import ardupilotmega as mav

from firefly.autopilot.mavlink import telemetry

from ._util import altitude, fly_until, hovering_vehicle, ready_vehicle

CODEC = mav.MAVLink(None)


def flags(v) -> int:
    return telemetry.ekf_status_report(v, CODEC).flags


def test_no_rangefinder_no_height_above_ground():
    v = hovering_vehicle(5.0)
    assert flags(v) == 0x33f


def test_a_rangefinder_in_range_gives_it_and_five_seconds_out_of_range_take_it_away():
    v = hovering_vehicle(4.0, boot_params={"RNGFND1_TYPE": 100, "RNGFND1_MAX": 7})
    v.run_until(v.time_s + 1.0)
    assert flags(v) == 0x37f
    b = v.body
    v.guided_goto(b.n_m, b.e_m, b.d_m - 6.0)
    assert fly_until(v, lambda x: altitude(x) > 9.8, 20.0)
    assert flags(v) == 0x37f  # a range within the last 5 s
    assert fly_until(v, lambda x: flags(x) == 0x33f, 6.0)


def variances(v) -> tuple[float, float, float, float]:
    r = telemetry.ekf_status_report(v, CODEC)
    return r.velocity_variance, r.pos_horiz_variance, r.pos_vert_variance, r.compass_variance


def test_the_variances_are_the_modelled_test_ratios_small_at_rest_and_past_the_gate_jammed():
    """ArduCopter SITL (area ekf_variances): a few hundredths settled; SIM_GPS1_JAM takes the
    velocity's past 0.8 in 3.6-4.2 s and on past the gate; the height's and compass's stay."""
    v = hovering_vehicle(10.0)
    quiet = []
    for _ in range(50):
        v.run_until(v.time_s + 0.1)
        quiet.append(variances(v))
    assert max(q[0] for q in quiet) < 0.2 and max(q[1] for q in quiet) < 0.4
    assert len({q[0] for q in quiet}) > 1  # modelled, not a constant
    v.params.set("SIM_GPS1_JAM", 1)
    assert fly_until(v, lambda x: variances(x)[0] > 1.0, 10.0, step_s=0.1)
    assert variances(v)[2:] == (0.0, pytest.approx(0.02))


def test_without_a_position_constant_position_mode_on_the_ground_attitude_and_height_flying():
    """ArduCopter SITL (area ekf_variances): booted without a GPS, 0xa7 on the ground; the GPS gone
    in a hover, 0x25 7 s later, the variances held where the last fix left them; 0xa7 again, the
    variances nothing, once the EKF stops aiding 15 s after the last fix."""
    grounded = ready_vehicle(boot_params={"SIM_GPS1_ENABLE": 0})
    assert flags(grounded) == 0xa7
    v = hovering_vehicle(10.0)
    v.params.set("SIM_GPS1_ENABLE", 0)
    assert fly_until(v, lambda x: flags(x) == 0x25, 15.0, step_s=0.1)
    held = variances(v)
    v.run_until(v.time_s + 2.0)
    assert variances(v) == held and held[0] < 0.2 and held[1] < 0.4
    assert fly_until(v, lambda x: flags(x) == 0xa7, 8.0, step_s=0.1)
    assert variances(v)[:2] == (0.0, 0.0)
