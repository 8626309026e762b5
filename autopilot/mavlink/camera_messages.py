"""The camera's messages, as ArduCopter sends them for a CAM1 servo or relay camera (AP_Camera):
CAMERA_FEEDBACK for each picture (to every link as it is taken, and the last one again on
request), and on request CAMERA_INFORMATION, CAMERA_SETTINGS, CAMERA_CAPTURE_STATUS,
CAMERA_FOV_STATUS and VIDEO_STREAM_INFORMATION. Without a camera (CAM1_TYPE 0) none is built, and
REQUEST_MESSAGE is ACCEPTED all the same (REQUESTABLE), as it is for CAMERA_THERMAL_RANGE, which
only a gimbal's camera would send; VIDEO_STREAM_STATUS is not among them: FAILED.

Measured on the reference: CAMERA_INFORMATION is all zeros but the time (a servo camera's driver
leaves its description unset: no focal length, no flags); CAMERA_SETTINGS is image mode with
zoom and focus unknown (NaN); CAMERA_CAPTURE_STATUS says 2 (interval set, idle) while an interval
capture has pictures left, with the interval it was last given; CAMERA_FOV_STATUS gives the
vehicle's position and heading (no mount to point it) and no field of view;
VIDEO_STREAM_INFORMATION is all zeros (ArduPilot sends a stream description only a script has
filled in; with none, an empty one: no name, no uri).
"""
from __future__ import annotations

import math

from ..payload.camera import MAVLINK_CAMV2
from ..views import TelemetryView
from .dialect import mavlink as mav
from .encoding import time_boot_ms

NAN = float("nan")
NOT_KNOWN = 2**31 - 1  # INT32_MAX: CAMERA_FOV_STATUS's "no point the camera looks at"
NO_NAME = [0] * 32
INTERVAL_SET_IDLE = 2  # CAMERA_CAPTURE_STATUS image_status


def camera_feedback(v: TelemetryView, codec):
    s = v.camera_status()
    f = s.feedback
    if not s.present:
        return None
    if f is None:  # asked before any picture: ArduPilot's zeroed record
        return codec.camera_feedback_encode(0, 0, 0, s.image_index, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                                            mav.CAMERA_FEEDBACK_PHOTO, 0)
    return codec.camera_feedback_encode(f.time_usec, 0, 0, s.image_index, f.lat_e7, f.lon_e7, f.alt_msl_m,
                                        f.alt_rel_m, f.roll_deg, f.pitch_deg, f.yaw_deg, 0.0,
                                        mav.CAMERA_FEEDBACK_PHOTO, 0)


def camera_information(v: TelemetryView, codec):
    s = v.camera_status()
    if not s.present:
        return None
    if s.kind == MAVLINK_CAMV2:  # the camera's own, as AP_Camera_MAVLinkCamV2 keeps it; none before it is found
        if s.mavlink_camera is None:
            return None
        return codec.camera_information_encode(time_boot_ms(v), *s.mavlink_camera.information_fields())
    return codec.camera_information_encode(time_boot_ms(v), NO_NAME, NO_NAME, 0, 0.0, 0.0, 0.0, 0, 0, 0, 0, 0, b"")


def camera_settings(v: TelemetryView, codec):
    if not v.camera_status().present:
        return None
    return codec.camera_settings_encode(time_boot_ms(v), mav.CAMERA_MODE_IMAGE, NAN, NAN)


def camera_capture_status(v: TelemetryView, codec):
    s = v.camera_status()
    if not s.present:
        return None
    return codec.camera_capture_status_encode(time_boot_ms(v), INTERVAL_SET_IDLE if s.capturing else 0, 0,
                                              s.interval_s, 0, NAN, s.image_index)


def video_stream_information(v: TelemetryView, codec):
    if not v.camera_status().present:
        return None
    return codec.video_stream_information_encode(0, 0, 0, 0, 0.0, 0, 0, 0, 0, 0, b"", b"")


def camera_fov_status(v: TelemetryView, codec):
    if not v.camera_status().present:
        return None
    pos = v.position_global()
    half_yaw = v.attitude[2] / 2.0
    return codec.camera_fov_status_encode(time_boot_ms(v), round(pos.lat_deg * 1e7), round(pos.lon_deg * 1e7),
                                          round(pos.alt_m * 1000), NOT_KNOWN, NOT_KNOWN, NOT_KNOWN,
                                          [math.cos(half_yaw), 0.0, 0.0, math.sin(half_yaw)], NAN, NAN)


BUILDERS = {
    mav.MAVLINK_MSG_ID_CAMERA_FEEDBACK: camera_feedback,
    mav.MAVLINK_MSG_ID_CAMERA_INFORMATION: camera_information,
    mav.MAVLINK_MSG_ID_CAMERA_SETTINGS: camera_settings,
    mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS: camera_capture_status,
    mav.MAVLINK_MSG_ID_CAMERA_FOV_STATUS: camera_fov_status,
    mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION: video_stream_information,
}
# Asked for by REQUEST_MESSAGE, ACCEPTED with a camera or none (ArduPilot queues any message it
# knows how to send, and then the camera has nothing to send)
REQUESTABLE = frozenset(BUILDERS) | {mav.MAVLINK_MSG_ID_CAMERA_THERMAL_RANGE}
