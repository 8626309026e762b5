"""CAM1 on the real process, as a user sets it up with pymavlink: CAM1_TYPE 1 and a trigger output
(SERVO9_FUNCTION 10) set and the vehicle rebooted (the camera is built at boot, as ArduPilot's),
then a survey-like leg flown in AUTO with DO_SET_CAM_TRIGG_DIST: one CAMERA_FEEDBACK per picture,
every 10 m along the leg, as the parity area `camera` measured on ArduCopter (six on a 60 m leg,
the first at its start)."""
from __future__ import annotations

import math
import time

import pytest
from pymavlink import mavutil

from .pymav import Gcs, set_param, upload_mission
from .test_mission_progress import gcs, home, north_east  # noqa: F401 - gcs: the fixture
from .test_reboot import arm_in_guided_once_booted, reboot_and_wait

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink


def test_a_survey_leg_reports_a_picture_every_trigger_distance(gcs):
    set_param(gcs, "CAM1_TYPE", 1)
    set_param(gcs, "SERVO9_FUNCTION", 10)
    reboot_and_wait(gcs)
    origin = home(gcs)
    upload_mission(gcs, [(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 10.0),
                         (mav.MAV_CMD_NAV_WAYPOINT, *north_east(origin, 0.5, 0), 10.0),
                         (mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, 0, 0, 0.0, (10, 0, 1, 0)),  # 10 m, a picture now
                         (mav.MAV_CMD_NAV_WAYPOINT, *north_east(origin, 60, 0), 10.0),
                         (mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST, 0, 0, 0.0),
                         (mav.MAV_CMD_NAV_LAND, *north_east(origin, 60, 0), 0.0)])
    arm_in_guided_once_booted(gcs)
    assert gcs.command(mav.MAV_CMD_MISSION_START) == mav.MAV_RESULT_ACCEPTED
    feedback = []
    deadline = time.monotonic() + 120  # the mission is some 40 s of flight: 4 s at speedup 10
    while True:
        msg = gcs.recv(["CAMERA_FEEDBACK", "HEARTBEAT"], 120)
        assert msg is not None, f"the mission stalled after {len(feedback)} pictures"
        assert time.monotonic() < deadline, f"the mission never ended: {len(feedback)} pictures"
        if msg.get_type() == "CAMERA_FEEDBACK":
            feedback.append(msg)
        elif not msg.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED:
            break
    assert [m.img_idx for m in feedback] == [1, 2, 3, 4, 5, 6]
    lat0 = origin[0] * 1e-7
    norths = [(m.lat - origin[0]) * 1e-7 * 111_319.5 for m in feedback]
    easts = [(m.lng - origin[1]) * 1e-7 * 111_319.5 * math.cos(math.radians(lat0)) for m in feedback]
    assert abs(norths[0] - 0.5) < 1.0 and all(abs(e) < 1.0 for e in easts)
    # (positions come to 1e-7 degrees, about a centimetre)
    assert all(9.99 <= b - a < 10.8 for a, b in zip(norths, norths[1:])), norths
    assert all(abs(m.alt_rel - 10.0) < 0.5 for m in feedback[1:])
    result, status = gcs.command_with_reply(mav.MAV_CMD_REQUEST_MESSAGE, "CAMERA_CAPTURE_STATUS", 262)
    assert result == mav.MAV_RESULT_ACCEPTED and status.image_count == 6
