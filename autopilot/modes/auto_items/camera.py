"""The camera's mission items, as AP_Mission hands them to AP_Camera (payload/camera.py): done as
they start (RUN_BY_MISSION), whatever the camera makes of them.

DO_DIGICAM_CONFIGURE (param 2 the shutter speed, 3 the aperture, 4 the ISO), DO_DIGICAM_CONTROL
(x the shooting command: 1 a picture), DO_SET_CAM_TRIGG_DIST (param 1 the distance, param 3 = 1 a
picture now), IMAGE_START_CAPTURE (param 1 the camera, 0 all; 2 the interval [s]; 3 the number of
pictures, 0 until stopped), IMAGE_STOP_CAPTURE (param 1 the camera), SET_CAMERA_ZOOM and
SET_CAMERA_FOCUS (param 1 the type, 2 the rate or percentage: a servo camera's lens) and
SET_CAMERA_SOURCE (nothing: these cameras have one). Parameters are cut to AP_Mission's integer
fields (camera numbers, zoom and focus types and the aperture bytes; counts, the shutter speed
and the ISO uint16).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ...c_casts import as_uint8, as_uint16
from ...payload.camera import FOCUS_TYPES, ZOOM_TYPES
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext

DIGICAM_CONFIGURE, DIGICAM_CONTROL, SET_CAM_TRIGG_DIST = 202, 203, 206
IMAGE_START_CAPTURE, IMAGE_STOP_CAPTURE, SET_CAMERA_SOURCE = 2000, 2001, 534
SET_CAMERA_ZOOM, SET_CAMERA_FOCUS = 531, 532


def _camera_index(item: MissionItem) -> int | None:
    number = as_uint16(item.p1) & 0xFF
    return None if number == 0 else number - 1


class CameraItem(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        camera = ctx.camera
        command = item.command
        if command == DIGICAM_CONFIGURE:
            camera.configure(as_uint16(item.p2), as_uint8(item.p3), as_uint16(item.p4))
        elif command == DIGICAM_CONTROL:
            camera.control(item.x)
        elif command == SET_CAM_TRIGG_DIST:
            camera.trigger_distance(item.p1, as_uint16(item.p3) & 0xFF == 1)
        elif command == IMAGE_START_CAPTURE:
            camera.start_capture(_camera_index(item), item.p2, as_uint16(item.p3))
        elif command == IMAGE_STOP_CAPTURE:
            which = _camera_index(item)
            if camera.is_instance(which):
                camera.stop_capture()
        elif command == SET_CAMERA_ZOOM and as_uint8(item.p1) in ZOOM_TYPES:
            camera.set_zoom(ZOOM_TYPES[as_uint8(item.p1)], item.p2)
        elif command == SET_CAMERA_FOCUS and as_uint8(item.p1) in FOCUS_TYPES:
            camera.set_focus(FOCUS_TYPES[as_uint8(item.p1)], item.p2)
        return True
