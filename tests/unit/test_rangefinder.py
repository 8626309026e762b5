"""The rangefinder RNGFND1: SITL's downward beam (sim/rangefinder.py), ArduPilot's driver and its
statuses (autopilot/rangefinder.py), a companion's DISTANCE_SENSOR, and what ArduCopter sends of it
(mavlink/rangefinder_messages.py, SYS_STATUS's laser-position bit, the pre-arm check)."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.c_casts import float32
from firefly.autopilot.mavlink import rangefinder_messages, telemetry
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.modes import Guided
from firefly.autopilot.params import ParamStore
from firefly.autopilot.rangefinder import MAVLINK, RangeStatus, Rangefinder
from firefly.autopilot.results import Result
from firefly.autopilot.safety.arming import prearm_failure
from firefly.autopilot.vehicle import Vehicle
from firefly.sim.rangefinder import SonarBeam
from firefly.sim.rigid_body import BodyState, quaternion_from_euler

from ._session_link import Link
from ._util import GCS_COMPONENT, GCS_SYSTEM, client_codec, fly_until, mav, ready_vehicle

CODEC = client_codec()
LASER = mav.MAV_SYS_STATUS_SENSOR_LASER_POSITION


def body_at(height_m: float, roll_deg: float = 0.0, pitch_deg: float = 0.0) -> BodyState:
    qw, qx, qy, qz = quaternion_from_euler(math.radians(roll_deg), math.radians(pitch_deg), 0.3)
    return BodyState(d_m=-height_m, qw=qw, qx=qx, qy=qy, qz=qz)


def test_the_beam_reads_the_slant_range_and_misses_the_ground_past_the_horizon():
    beam = SonarBeam(seed=1)
    assert beam.range_m(body_at(5.0)) == pytest.approx(5.0)
    assert beam.range_m(body_at(5.0, roll_deg=60.0)) == pytest.approx(10.0)
    assert beam.range_m(body_at(5.0, roll_deg=30.0, pitch_deg=30.0)) == pytest.approx(5.0 / 0.75)
    assert beam.range_m(body_at(5.0, pitch_deg=90.0)) == math.inf
    assert beam.range_m(body_at(5.0, roll_deg=120.0)) == math.inf
    assert beam.range_m(body_at(-1.0)) == 0.0  # never negative


def test_beam_noise_is_uniform_within_sim_sonar_rnd_and_seeded():
    ranges = []
    for seed in (1, 1, 2):
        beam = SonarBeam(seed)
        beam.noise_m = 0.5
        ranges.append([beam.range_m(body_at(5.0)) for _ in range(400)])
    assert ranges[0] == ranges[1] and ranges[0] != ranges[2]
    assert 4.5 <= min(ranges[0]) < 4.55 and 5.45 < max(ranges[0]) <= 5.5


def store(**values) -> ParamStore:
    params = ParamStore()
    for name, value in values.items():
        params.set(name, value)
    return params


@pytest.mark.parametrize("distance, status", [
    (0.0, RangeStatus.OUT_OF_RANGE_LOW), (0.19, RangeStatus.OUT_OF_RANGE_LOW), (0.2, RangeStatus.GOOD),
    (7.0, RangeStatus.GOOD), (7.01, RangeStatus.OUT_OF_RANGE_HIGH), (math.inf, RangeStatus.NO_DATA)])
def test_a_range_is_judged_against_min_and_max_inclusive(distance, status):
    rf = Rangefinder(store(RNGFND1_TYPE=100))
    assert rf.reading().status == RangeStatus.NOT_CONNECTED and not rf.reading().has_data
    rf.update(0.0, distance)
    assert rf.reading().status == status
    assert rf.reading().has_data == (status != RangeStatus.NO_DATA)


def test_good_readings_count_to_ten_and_any_other_resets_the_count():
    rf = Rangefinder(store(RNGFND1_TYPE=100))
    for _ in range(12):
        rf.update(0.0, 3.0)
    assert rf.reading().valid_count == 10
    rf.update(0.0, 9.0)
    assert rf.reading().valid_count == 0
    rf.update(0.0, 3.0)
    rf.update(0.0, math.inf)  # SITL's no data: the range and the count are left as they were
    r = rf.reading()
    assert (r.status, r.distance_m, r.valid_count) == (RangeStatus.NO_DATA, 3.0, 1)


def test_the_type_is_read_at_boot_and_set_to_zero_stops_the_driver():
    params = store()
    rf = Rangefinder(params)
    params.set("RNGFND1_TYPE", 100)
    rf.update(0.0, 3.0)
    assert not rf.exists and rf.prearm_failure() == "Rangefinder 1: Not Detected"
    rf = Rangefinder(params)
    rf.update(0.0, 3.0)
    assert rf.exists and rf.prearm_failure() is None
    params.set("RNGFND1_TYPE", 0)
    rf.update(0.05, 3.0)
    assert not rf.exists and not rf.down and rf.prearm_failure() is None
    assert Rangefinder(store(RNGFND1_TYPE=2)).prearm_failure() == "Rangefinder 1: Not Detected"


def test_a_companion_rangefinder_takes_its_orientation_times_out_and_narrows_the_limits():
    rf = Rangefinder(store(RNGFND1_TYPE=MAVLINK, RNGFND1_MAX=327.67))
    rf.update(0.0, math.inf)
    assert rf.reading().status == RangeStatus.NO_DATA and rf.prearm_failure() == "Rangefinder 1: No Data"
    rf.heard(0.1, 0, 300, 10, 50, 1, 0)  # facing forward: not this rangefinder's
    rf.update(0.1, math.inf)
    assert rf.reading().status == RangeStatus.NO_DATA
    # min max(0.2, 0.1), max min(327.67, 0.5); 20 cm is 0.19999999 m in float32, below 0.2: out
    # of range (but data), and sent back as 19 cm, as the reference sends it
    rf.heard(0.2, 25, 20, 10, 50, 1, 0)
    rf.update(0.25, math.inf)
    r = rf.reading()
    assert (r.status, r.min_m, r.max_m, r.sensor_type) == (RangeStatus.OUT_OF_RANGE_LOW, float32(0.2), 0.5, 1)
    assert rangefinder_messages._cm(r.distance_m) == 19 and rangefinder_messages._cm(r.min_m) == 20
    rf.heard(0.2, 25, 21, 10, 50, 1, 0)
    rf.update(0.25, math.inf)
    assert rf.reading().status == RangeStatus.GOOD
    rf.update(0.7, math.inf)  # 500 ms after the message: still data
    assert rf.reading().status == RangeStatus.GOOD
    rf.update(0.75, math.inf)
    r = rf.reading()
    assert (r.status, r.distance_m) == (RangeStatus.NO_DATA, 0.0)
    rf.heard(1.0, 25, 900, 0, 0, 0, 0)  # no limits of its own: the parameters'
    rf.update(1.0, math.inf)
    assert (rf.reading().status, rf.reading().max_m) == (RangeStatus.GOOD, float32(327.67))


@pytest.mark.parametrize("sent, kept, resent", [(0, -1, 0), (1, 0, 1), (2, 2, 2), (100, 100, 100), (101, 101, 1),
                                                (200, -56, 1), (255, -1, 0)])
def test_a_companion_signal_quality_is_kept_as_an_int8_and_sent_back_as_mavlink_has_it(sent, kept, resent):
    rf = Rangefinder(store(RNGFND1_TYPE=MAVLINK))
    rf.heard(0.0, 25, 300, 0, 0, 1, sent)
    rf.update(0.0, math.inf)
    assert rf.reading().signal_quality == kept
    assert rangefinder_messages._mavlink_quality(kept) == resent


def vehicle_with(**values) -> Vehicle:
    return ready_vehicle(boot_params=values)


def test_without_a_rangefinder_nothing_is_sent_and_the_laser_bit_is_clear():
    v = vehicle_with()
    assert rangefinder_messages.distance_sensor(v, CODEC) is None
    assert rangefinder_messages.rangefinder(v, CODEC) is None
    status = telemetry.sys_status(v, CODEC)
    assert not (status.onboard_control_sensors_present | status.onboard_control_sensors_health) & LASER


def test_sitl_rangefinder_reads_out_of_range_low_on_the_ground_and_the_height_in_flight():
    v = vehicle_with(RNGFND1_TYPE=100)
    ground = rangefinder_messages.distance_sensor(v, CODEC)
    assert (ground.current_distance, ground.min_distance, ground.max_distance) == (0, 20, 700)
    assert (ground.type, ground.id, ground.orientation, ground.covariance, ground.signal_quality) == (4, 0, 25, 0, 0)
    status = telemetry.sys_status(v, CODEC)
    assert status.onboard_control_sensors_present & status.onboard_control_sensors_enabled & LASER
    assert status.onboard_control_sensors_health & LASER  # out of range is data
    assert prearm_failure(v) is None  # nor does it stop arming
    assert v.set_mode(Guided.number) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    assert v.takeoff(5.0) == Result.ACCEPTED
    assert fly_until(v, lambda v: abs(v.home_ned[2] - v.body.d_m - 5.0) < 0.1 and abs(v.body.vd_m_s) < 0.05, 30.0)
    flying = rangefinder_messages.distance_sensor(v, CODEC)
    height = v.home_ned[2] - v.sim.state.body.d_m
    assert flying.current_distance == pytest.approx(100 * height, abs=3)
    assert rangefinder_messages.rangefinder(v, CODEC).distance == pytest.approx(height, abs=0.03)
    assert v.rangefinder_reading().status == RangeStatus.GOOD and v.rangefinder_reading().valid_count == 10


@pytest.mark.parametrize("fields", [
    (0, 0, 0, 0, 0, 0, 25, 0), (0xFFFFFFFF, 65535, 65535, 65535, 255, 255, 25, 255),
    (0, 65535, 0, 65535, 4, 0, 25, 0), (0, 10, 50, 20, 0, 7, 255, 255)])
def test_hostile_distance_sensor_messages_change_only_the_reading(fields):
    """Any field values, from anyone: the session stays up, the messages it builds pack, and a
    range past either limit is out of range, never a fault."""
    link = Link(ready_vehicle(boot_params={"RNGFND1_TYPE": MAVLINK}))
    sender = new_codec(GCS_SYSTEM, GCS_COMPONENT)
    for _ in range(3):
        msg = sender.distance_sensor_encode(*fields, signal_quality=fields[-1])
        link.send(msg)
        link.vehicle.run_until(link.vehicle.time_s + 0.1)
    assert link.session.counters["handler_errors"] == 0 and not link.vehicle.internal_error_bits
    for build in (rangefinder_messages.distance_sensor, rangefinder_messages.rangefinder, telemetry.sys_status):
        msg = build(link.vehicle, CODEC)
        if msg is not None:
            msg.pack(CODEC)


def test_the_rangefinder_aux_function_enables_it_high_and_disables_it_otherwise():
    """As measured: low clears the laser bit's enabled and healthy (present stays, the messages go
    on), high sets them again; without a downward rangefinder high enables nothing."""
    v = vehicle_with(RNGFND1_TYPE=100)
    bits = lambda: [bool(getattr(telemetry.sys_status(v, CODEC), f"onboard_control_sensors_{k}") & LASER)
                    for k in ("present", "enabled", "health")]
    assert v.aux_function(10, 0) == Result.ACCEPTED and bits() == [True, False, False]
    assert rangefinder_messages.distance_sensor(v, CODEC) is not None
    assert v.aux_function(10, 2) == Result.ACCEPTED and bits() == [True, True, True]
    v = vehicle_with(RNGFND1_TYPE=100, RNGFND1_ORIENT=0)
    assert v.aux_function(10, 2) == Result.ACCEPTED and bits() == [False, False, False]
