"""The camera's commands, answered as ArduCopter's AP_Camera answers them (payload/camera.py acts).

Measured on the reference with CAM1_TYPE 1 and with none: DO_DIGICAM_CONFIGURE, DO_DIGICAM_CONTROL
and DO_SET_CAM_TRIGG_DIST are ACCEPTED whatever they ask, a camera or not; IMAGE_START_CAPTURE is
UNSUPPORTED for a negative camera number, FAILED when no picture or interval results (no such
camera, too soon after the last picture, an interval of 0 with more than one picture asked);
IMAGE_STOP_CAPTURE is ACCEPTED for camera 0 (all), UNSUPPORTED for a negative number or one that
is not there; SET_CAMERA_SOURCE is DENIED (neither a servo nor a relay camera has sources).
Camera numbers are 1-based, 0 meaning every camera. A DO_DIGICAM_CONTROL's shooting command is
param 5 as an integer (a COMMAND_INT's x).

The camera protocol v2's commands (measured with a servo camera, a relay camera and none:
tests/parity/probes/camera.py camera_v2): SET_CAMERA_ZOOM continuous or to a percentage is
ACCEPTED by a servo camera, every other zoom UNSUPPORTED; SET_CAMERA_FOCUS of a step or in metres
(or no known type) is DENIED, else what the camera says (payload/camera.py set_focus: ACCEPTED,
UNSUPPORTED, or FAILED with no camera); CAMERA_TRACK_POINT / _RECTANGLE / _STOP_TRACKING are
UNSUPPORTED (no camera of these types tracks); VIDEO_START_CAPTURE / _STOP_CAPTURE FAILED (none
records video). SET_CAMERA_MODE, RESET_CAMERA_SETTINGS, VIDEO_START/STOP_STREAMING and the
deprecated REQUEST_CAMERA_* / REQUEST_VIDEO_STREAM_* are not ArduCopter's: UNSUPPORTED, as any
command not in the table.
"""
from __future__ import annotations

import math

from ..c_casts import as_int32, as_uint16, param5_int
from ..payload.camera import FOCUS_TYPES, ZOOM_TYPES
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
    """Param 2 the shutter speed, 3 the aperture, 4 the ISO (param 1's shooting mode: not modelled)."""
    s.vehicle.camera.configure(c.p2, c.p3, c.p4)
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


def set_camera_zoom(s, c) -> Result:
    """Param 1 the zoom type (exactly 1 or 2), param 2 the rate (-1 out, 0 hold, 1 in) or percentage."""
    how = ZOOM_TYPES.get(c.p1)
    return Result.ACCEPTED if how is not None and s.vehicle.camera.set_zoom(how, c.p2) else Result.UNSUPPORTED


def set_camera_focus(s, c) -> Result:
    """Param 1 the focus type (cut to an integer, as C casts it to the enum), param 2 the rate or
    percentage."""
    how = FOCUS_TYPES.get(as_int32(c.p1))
    return Result.DENIED if how is None else s.vehicle.camera.set_focus(how, c.p2)


def camera_tracking(s, c) -> Result:
    return Result.UNSUPPORTED  # no camera of these types tracks; nor does a missing one


def video_capture(s, c) -> Result:
    return Result.FAILED  # no camera of these types records video (stream 0: the first; N: camera N)


HANDLERS = {
    mav.MAV_CMD_DO_DIGICAM_CONFIGURE: digicam_configure,
    mav.MAV_CMD_DO_DIGICAM_CONTROL: digicam_control,
    mav.MAV_CMD_DO_SET_CAM_TRIGG_DIST: set_cam_trigg_dist,
    mav.MAV_CMD_IMAGE_START_CAPTURE: image_start_capture,
    mav.MAV_CMD_IMAGE_STOP_CAPTURE: image_stop_capture,
    mav.MAV_CMD_SET_CAMERA_SOURCE: set_camera_source,
    mav.MAV_CMD_SET_CAMERA_ZOOM: set_camera_zoom,
    mav.MAV_CMD_SET_CAMERA_FOCUS: set_camera_focus,
    mav.MAV_CMD_CAMERA_TRACK_POINT: camera_tracking,
    mav.MAV_CMD_CAMERA_TRACK_RECTANGLE: camera_tracking,
    mav.MAV_CMD_CAMERA_STOP_TRACKING: camera_tracking,
    mav.MAV_CMD_VIDEO_START_CAPTURE: video_capture,
    mav.MAV_CMD_VIDEO_STOP_CAPTURE: video_capture,
}
