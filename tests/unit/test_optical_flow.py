"""The optical flow sensor: SITL's camera (sim/optical_flow.py), ArduPilot's driver for it
(autopilot/optical_flow.py), what ArduCopter sends of it (OPTICAL_FLOW, SYS_STATUS's bit), and
FLOWHOLD (modes/flowhold.py) flown on it."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.mavlink import optical_flow_messages, telemetry
from firefly.autopilot.modes import ModeNumber
from firefly.autopilot.optical_flow import NONE, SITL, OpticalFlow
from firefly.autopilot.params import ParamStore
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle
from firefly.sim.optical_flow import FlowCamera, SensorSettings, true_flow
from firefly.sim.rigid_body import BodyState, quaternion_from_euler

from ._util import altitude, client_codec, fly_until, mav, ready_vehicle, throttle_at_mid
from .test_modes_manual import hold_sticks, said

CODEC = client_codec()
FLOW_BIT = mav.MAV_SYS_STATUS_SENSOR_OPTICAL_FLOW
WITH_FLOW = {"FLOW_TYPE": 10, "SIM_FLOW_ENABLE": 1}


def body(height_m=4.0, vn=0.0, ve=0.0, roll_deg=0.0, pitch_deg=0.0, yaw_deg=0.0, p=0.0, q=0.0) -> BodyState:
    qw, qx, qy, qz = quaternion_from_euler(*(math.radians(a) for a in (roll_deg, pitch_deg, yaw_deg)))
    return BodyState(d_m=-height_m, vn_m_s=vn, ve_m_s=ve, qw=qw, qx=qx, qy=qy, qz=qz, p_rad_s=p, q_rad_s=q)


# ----- the camera ------------------------------------------------------------------------------
def test_the_flow_is_the_velocity_across_the_beam_over_the_range_plus_the_rotation():
    assert true_flow(body(), 0.0)[:4] == pytest.approx((0.0, 0.0, 0.0, 0.0))
    north = true_flow(body(vn=2.0), 0.0)  # forward, facing north: about the pitch axis
    assert (north.flow_x, north.flow_y) == pytest.approx((0.0, 0.5))
    east = true_flow(body(ve=2.0), 0.0)  # to the right: about the roll axis, negative
    assert (east.flow_x, east.flow_y) == pytest.approx((-0.5, 0.0))
    facing_east = true_flow(body(ve=2.0, yaw_deg=90.0), 0.0)  # now forward
    assert (facing_east.flow_x, facing_east.flow_y) == pytest.approx((0.0, 0.5))
    turning = true_flow(body(p=0.3, q=-0.2), 0.0)  # the camera turns with the body
    assert turning[:4] == pytest.approx((0.3, -0.2, 0.3, -0.2))
    tilted = true_flow(body(vn=2.0, roll_deg=60.0), 0.0)  # a slant range twice the height
    assert tilted.flow_y == pytest.approx(0.25)
    assert true_flow(body(vn=2.0, roll_deg=90.0, p=0.1), 0.0).flow_x == pytest.approx(0.1)  # no ground seen
    assert true_flow(body(vn=2.0), 0.0).quality == 51


def test_a_camera_whose_offset_puts_it_on_the_ground_gives_no_number_and_does_not_raise():
    """SIM_FLOW_POS_Z (down to 5 m) can put the lens exactly at the ground: a range of 0. ArduPilot's
    float division gives an infinite (or NaN) flow there; a ZeroDivisionError here would abort the
    vehicle's whole mode tick (the mode, the failsafes) as an internal error each 10 ms."""
    moving = true_flow(body(height_m=0.5, vn=1.0, ve=-1.0), 0.0, (0.0, 0.0, 0.5))
    assert moving.flow_x == math.inf and moving.flow_y == math.inf
    still = true_flow(body(height_m=0.5), 0.0, (0.0, 0.0, 0.5))
    assert math.isnan(still.flow_x) and math.isnan(still.flow_y)
    assert still.body_x == 0.0 and still.quality == 51


def test_the_camera_samples_at_its_rate_with_bounded_noise_and_its_delay():
    cam = FlowCamera(seed=3)
    assert cam.read(0.0, body(vn=2.0)) is None  # SIM_FLOW_ENABLE 0
    cam.settings = SensorSettings(enabled=True, rate_hz=10.0, noise_rad_s=0.05)
    times = [i * 0.01 for i in range(200)]
    samples = [(t, cam.read(t, body(vn=2.0))) for t in times]
    made = [(t, s) for t, s in samples if s is not None]
    assert len(made) == 20  # 10 Hz over 2 s
    assert all(abs(s.flow_y - 0.5) <= 0.05 and abs(s.flow_x) <= 0.05 for _, s in made)
    assert len({round(s.flow_y, 6) for _, s in made}) > 10  # noisy
    delayed = FlowCamera(seed=3)
    delayed.settings = SensorSettings(enabled=True, rate_hz=10.0, delay_samples=2, noise_rad_s=0.0)
    got = [delayed.read(i * 0.1, body(vn=float(i))) for i in range(5)]
    assert [round(s.flow_y * 4) for s in got] == [0, 0, 0, 1, 2]  # two samples late


# ----- the driver ------------------------------------------------------------------------------
def test_the_driver_is_made_at_boot_and_scales_and_turns_the_flow():
    params = ParamStore()
    assert OpticalFlow(params).kind == NONE
    params.set("FLOW_TYPE", 10)
    flow = OpticalFlow(params)
    assert flow.kind == SITL and flow.enabled and not flow.healthy(0.0)
    cam = FlowCamera(seed=1)
    cam.settings = SensorSettings(enabled=True, noise_rad_s=0.0)
    params.set("FLOW_FXSCALER", 100)
    flow.update(1.0, cam.read(1.0, body(ve=-2.0)))
    assert flow.reading.flow_x == pytest.approx(0.5 * 1.1)
    assert flow.healthy(1.4) and not flow.healthy(1.5)
    params.set("FLOW_FXSCALER", 0)
    params.set("FLOW_ORIENT_YAW", 9000)
    flow.update(2.0, cam.read(2.0, body(ve=-2.0)))
    assert (flow.reading.flow_x, flow.reading.flow_y) == pytest.approx((0.0, 0.5))
    params.set("FLOW_TYPE", 0)
    assert not flow.enabled and not flow.healthy(2.0)


# ----- on the vehicle --------------------------------------------------------------------------
def _bits(v: Vehicle) -> list[bool]:
    s = telemetry.sys_status(v, CODEC)
    return [bool(s.onboard_control_sensors_present & FLOW_BIT), bool(s.onboard_control_sensors_enabled & FLOW_BIT),
            bool(s.onboard_control_sensors_health & FLOW_BIT)]


def test_flowhold_needs_a_healthy_sensor_and_optical_flow_goes_out_while_it_is():
    v = ready_vehicle({"FLOW_TYPE": 10})
    assert _bits(v) == [True, True, False]
    assert optical_flow_messages.optical_flow(v, CODEC) is None
    said(v)
    assert v.set_mode(ModeNumber.FLOWHOLD) == Result.FAILED
    assert said(v) == ["Mode change to FLOWHOLD failed: init failed"]
    v.params.set("SIM_FLOW_ENABLE", 1)
    v.run_until(v.time_s + 0.3)
    assert _bits(v) == [True, True, True]
    m = optical_flow_messages.optical_flow(v, CODEC)
    assert (m.sensor_id, m.quality, m.flow_x, m.flow_y, m.ground_distance) == (0, 51, 0, 0, 0.0)
    assert m.flow_rate_x == pytest.approx(m.flow_comp_m_x, abs=0.01) and abs(m.flow_rate_x) <= 0.06
    assert abs(m.time_usec - v.time_s * 1000) < 20  # milliseconds, as ArduPilot fills it
    assert v.set_mode(ModeNumber.FLOWHOLD) == Result.ACCEPTED
    v.params.set("SIM_FLOW_ENABLE", 0)  # the samples stop: unhealthy half a second later
    v.run_until(v.time_s + 0.6)
    assert _bits(v) == [True, True, False]


def test_the_pixel_fields_are_the_rates_truncated_into_an_int16():
    cast = optical_flow_messages._int16
    assert [cast(x) for x in (0.9, -0.9, 1.7, -1.7, 1e9, -math.inf, math.nan)] == [0, 0, 1, -1, 32767, -32768, 0]


def test_flow_type_set_while_running_makes_no_driver():
    v = ready_vehicle()
    assert _bits(v) == [False, False, False]
    v.params.set("FLOW_TYPE", 10)
    v.params.set("SIM_FLOW_ENABLE", 1)
    v.run_until(v.time_s + 0.5)
    assert _bits(v) == [True, True, False]
    assert v.set_mode(ModeNumber.FLOWHOLD) == Result.FAILED


def _hovering_in(mode: ModeNumber, wind_m_s: float) -> Vehicle:
    v = ready_vehicle(WITH_FLOW)
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED
    assert v.arm() == Result.ACCEPTED
    assert v.takeoff(4.0) == Result.ACCEPTED
    assert fly_until(v, lambda x: abs(altitude(x) - 4.0) < 0.1 and abs(x.body.vd_m_s) < 0.05, 30.0)
    v.run_until(v.time_s + 1.0)
    throttle_at_mid(v)
    v.params.set("SIM_WIND_SPD", wind_m_s)
    v.params.set("SIM_WIND_DIR", 180.0)  # from the south: pushes north
    assert v.set_mode(mode) == Result.ACCEPTED
    return v


def test_flowhold_holds_against_the_wind_where_alt_hold_drifts():
    drifts = {}
    for mode in (ModeNumber.ALT_HOLD, ModeNumber.FLOWHOLD):
        v = _hovering_in(mode, 12.0)  # about 3 m/s at its 4 m (SIM_WIND_T's profile)
        v.run_until(v.time_s + 3.0)
        n0, e0 = v.body.n_m, v.body.e_m
        v.run_until(v.time_s + 20.0)
        drifts[mode] = math.hypot(v.body.n_m - n0, v.body.e_m - e0)
        assert abs(altitude(v) - 4.0) < 0.5
    assert drifts[ModeNumber.ALT_HOLD] > 10.0
    assert drifts[ModeNumber.FLOWHOLD] < 3.0
    assert v.mode_named_float is not None and v.mode_named_float[0] == b"HEST"
    assert 3.0 < v.mode_named_float[1] < 5.0  # the height it learnt, about the real 4 m


def test_flowhold_flies_on_through_samples_that_are_no_number():
    v = _hovering_in(ModeNumber.FLOWHOLD, 0.0)
    v.run_until(v.time_s + 4.0)
    flow = v.optical_flow
    for bad in (math.nan, math.inf):
        flow.reading = flow.reading._replace(flow_x=bad, flow_y=-bad, updated_s=v.time_s)
        v.run_until(v.time_s + 0.05)
        assert all(math.isfinite(angle) for angle in v.setpoint.lean)  # the lean the mode asks for
    v.run_until(v.time_s + 3.0)
    assert v.mode_number == ModeNumber.FLOWHOLD and abs(altitude(v) - 4.0) < 0.5
    assert math.isfinite(v.body.n_m) and math.hypot(v.body.vn_m_s, v.body.ve_m_s) < 0.5
    assert math.isfinite(v.mode_named_float[1])


def test_a_flowhold_stick_moves_the_vehicle_and_it_brakes_on_release():
    v = _hovering_in(ModeNumber.FLOWHOLD, 0.0)
    v.run_until(v.time_s + 3.0)
    n0 = v.body.n_m
    hold_sticks(v, pitch=0.4, throttle=0.5, seconds=3.0)  # forward: north
    assert v.body.vn_m_s > 1.0 and v.body.n_m - n0 > 2.0
    n1 = v.body.n_m
    assert hold_sticks(v, throttle=0.5, until=lambda x: math.hypot(x.body.vn_m_s, x.body.ve_m_s) < 0.3)
    v.run_until(v.time_s + 5.0)
    assert math.hypot(v.body.vn_m_s, v.body.ve_m_s) < 0.3
    assert 0.0 < v.body.n_m - n1 < 4.0


def test_the_log_holds_the_flow_samples_while_the_sensor_is_healthy(tmp_path):
    from firefly.autopilot.dataflash.recorder import Recorder

    from .test_dataflash import MemorySink, read_log, run
    v = ready_vehicle({"FLOW_TYPE": 10})
    sink = MemorySink()
    rec = Recorder(v, sink)
    assert v.arm() == Result.ACCEPTED
    run(v, rec, 1.0)  # SIM_FLOW_ENABLE 0: never healthy, nothing logged
    v.params.set("SIM_FLOW_ENABLE", 1)
    run(v, rec, 2.0)
    records = read_log(tmp_path, sink.logs[0])["OF"]
    assert 18 <= len(records) <= 21  # 10 Hz, from the first sample
    assert all(r.Qual == 51 and abs(r.flowX) <= 0.06 and abs(r.bodyX) < 0.01 for r in records)
