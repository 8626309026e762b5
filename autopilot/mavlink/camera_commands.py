"""The camera's commands, answered as ArduCopter's AP_Camera answers them (payload/camera.py acts).

Measured on the reference with CAM1_TYPE 1 and with none: DO_DIGICAM_CONFIGURE, DO_DIGICAM_CONTROL
and DO_SET_CAM_TRIGG_DIST are ACCEPTED whatever they ask, a camera or not; IMAGE_START_CAPTURE is
UNSUPPORTED for a negative camera number, FAILED when no picture or interval results (no such
camera, too soon after the last picture, an interval of 0 with more than one picture asked);
IMAGE_STOP_CAPTURE is ACCEPTED for camera 0 (all), UNSUPPORTED for a negative number or one that
is not there; SET_CAMERA_SOURCE is DENIED (neither a servo nor a relay camera has sources).
Camera numbers are 1-based, 0 meaning every camera. A DO_DIGICAM_CONTROL's shooting command is
param 5 as an integer (a COMMAND_INT's x).
"""
from __future__ import annotations

import math

from ..c_casts import as_uint16, param5_int
from ..results import Result
from .dialect import mavlink as mav

CAMERAS_MAX = 2  # AP_CAMERA_MAX_INSTANCES: the camera numbers SET_CAMERA_SOURCE takes


def _camera_index(number: float) -> int | None:
    """A command's camera number (0: all -> None) as the 0-based index AP_Camera casts it to."""
    return None if number == 0 else as_uint16(number - 1) & 0xFF


def _x(c) -> int:
    """Param 5 as the int32 AP_Camera reads."""
    return param5_int(c.p5, c.is_int)


def digicam_configure(s, c) -> Result:
    s.vehicle.camera.configure(c.p4)
    return Result.ACCEPTED


def digicam_control(s, c) -> Result:
    s.vehicle.camera.control(_x(c))
    return Result.ACCEPTED


def set_cam_trigg_dist(s, c) -> Result:
    """Param 1 the distance [m] (0: off), param 3 = 1 a picture now."""
    s.vehicle.camera.trigger_distance(c.p1, c.p3 == 1)
    return Result.ACCEPTED


def image_start_capture(s, c) -> Result:
    """Param 1 the camera, 2 the interval [s], 3 the number of pictures (an int16; 0: until stopped)."""
    if c.p1 < 0:
        return Result.UNSUPPORTED
    count = int(c.p3) if math.isfinite(c.p3) and abs(c.p3) < 2**15 else 0
    started = s.vehicle.camera.start_capture(_camera_index(c.p1), c.p2, count)
    return Result.ACCEPTED if started else Result.FAILED


def image_stop_capture(s, c) -> Result:
    if c.p1 < 0:
        return Result.UNSUPPORTED
    camera = s.vehicle.camera
    index = _camera_index(c.p1)
    if index is not None and not camera.is_instance(index):
        return Result.UNSUPPORTED
    camera.stop_capture()
    return Result.ACCEPTED


def set_camera_source(s, c) -> Result:
    return Result.DENIED  # no camera of these types switches sources; nor does a missing one


HANDLERS = {
    mav.MAV_CMD_DO_DIGICAM_CONFIGURE: digicam_configure,
    mav.MAV_CMD_DO_DIGICAM_CONTROL: digicam_control,
    mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST: set_cam_trigg_dist,
    mav.MAV_CMD_IMAGE_START_CAPTURE: image_start_capture,
    mav.MAV_CMD_IMAGE_STOP_CAPTURE: image_stop_capture,
    mav.MAV_CMD_SET_CAMERA_SOURCE: set_camera_source,
}
