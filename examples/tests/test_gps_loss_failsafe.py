"""Example: a failsafe test. The GPS is lost while the vehicle flies a GUIDED leg; as ArduCopter,
the EKF failsafe switches it to LAND, it says so, and it comes down where it was.

`airborne=15` starts the test with the vehicle already hovering at 15 m in GUIDED, and
`set_param("SIM_GPS1_ENABLE", 0)` is the fault ArduPilot's own SITL uses for a GPS loss.
"""
import pytest

from pymavlink import mavutil

MAV = mavutil.mavlink
POSITION_ONLY = 0b110111111000  # SET_POSITION_TARGET_LOCAL_NED type_mask: use x, y, z


@pytest.mark.firefly(airborne=15)
def test_gps_loss_mid_flight_lands_the_vehicle(firefly):
    conn = firefly.mavlink()
    conn.mav.set_position_target_local_ned_send(0, firefly.system_id, 1, MAV.MAV_FRAME_LOCAL_NED, POSITION_ONLY,
                                                50, 0, -15, 0, 0, 0, 0, 0, 0, 0, 0)
    firefly.wait_until(lambda s: s.north_m > 20, timeout=30, what="the leg north under way")

    firefly.set_param("SIM_GPS1_ENABLE", 0)
    # As ArduCopter's EKF, the estimate dead-reckons for a few seconds first: LAND about 8 s later.
    firefly.wait_until(lambda s: s.mode == "LAND", timeout=12, what="the EKF failsafe")
    text = conn.recv_match(type="STATUSTEXT", blocking=True, timeout=5,
                           condition="STATUSTEXT.text.startswith('EKF Failsafe')")
    assert text is not None and "LAND" in text.text

    landed = firefly.wait_until(lambda s: s.landed, timeout=120, what="landed and disarmed")
    assert landed.mode == "LAND"
    assert landed.north_m > 15, "it came down out where the GPS was lost, not back home"
