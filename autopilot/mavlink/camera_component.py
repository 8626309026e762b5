"""The thermal camera as its own MAVLink component (system = the vehicle's, component 100,
MAV_COMP_ID_CAMERA), speaking MAVLink's camera protocol v2, sans-IO. The session hands it what is
addressed to component 100 and sends what it returns; payload/thermal_camera.py takes the stills.

What it says unasked, to every link: a HEARTBEAT (MAV_TYPE_CAMERA) each second of sim time, and a
CAMERA_IMAGE_CAPTURED for each still as it is taken. Asked (COMMAND_LONG or COMMAND_INT), it answers
each command with exactly one COMMAND_ACK, then any message the command asked for, to the asking link:
- REQUEST_MESSAGE for CAMERA_INFORMATION, CAMERA_SETTINGS, CAMERA_CAPTURE_STATUS,
  STORAGE_INFORMATION, CAMERA_FOV_STATUS, VIDEO_STREAM_INFORMATION and VIDEO_STREAM_STATUS (param 2 the stream id, 0
  or 1; when the video is on), CAMERA_IMAGE_CAPTURED (param 2 the image index, -1 all; param 3 0 that one,
  -1 it and all after it, else the last index of a range) and HEARTBEAT; and the deprecated
  REQUEST_CAMERA_INFORMATION / _SETTINGS / _CAPTURE_STATUS (param 1 = 0 asks for nothing) and
  REQUEST_STORAGE_INFORMATION (param 1 the storage, 0 or 1; param 2 = 0 asks for nothing), and
  REQUEST_CAMERA_IMAGE_CAPTURE (param 1 the index);
- IMAGE_START_CAPTURE (param 2 interval [s], param 3 count, 0 until stopped), IMAGE_STOP_CAPTURE,
  SET_CAMERA_MODE (image only), STORAGE_FORMAT, RESET_CAMERA_SETTINGS, and with the video on
  VIDEO_START_STREAMING / VIDEO_STOP_STREAMING (param 1 the stream id) and the deprecated
  REQUEST_VIDEO_STREAM_INFORMATION / _STATUS (param 1 the stream id).
Results, as the camera protocol and ArduPilot give them: a message it does not send, or an image it
does not hold, is FAILED (ArduPilot's answer to a message id it cannot send); a parameter out of
its range (a camera/sensor id other than 0 or 1, NaN, a negative interval or count, an interval
shorter than a frame with more than one still, video mode, a storage other than 0 or 1) is DENIED,
as the protocol asks of a MAVLink camera; a full card is FAILED; any other command UNSUPPORTED.
FILE_TRANSFER_PROTOCOL addressed to it reads the card (camera_ftp.py).
"""
from __future__ import annotations

import math
from collections.abc import Callable

from ..payload.thermal_video import NAME as VIDEO_NAME
from ..payload.thermal_video import STREAM_ID
from ..results import Result
from .camera_ftp import CameraFtp, file_url
from .camera_messages import NOT_KNOWN
from .commands import Command
from .component_frames import FromComponent
from .dialect import mavlink as mav

HEARTBEAT_S = 1.0
VENDOR = b"Firefly"
MODEL = b"Thermal 160 (Lepton 3.5 class)"
PIXEL_PITCH_MM = 0.012  # the Lepton's 12 um pixel
SENSORS = (0, 1)  # camera ids a command may name: 0 all, 1 its one sensor
STORAGES = (0, 1)  # storage ids: 0 all, 1 its card
STREAMS = (0, STREAM_ID)  # video stream ids: 0 all, 1 its one stream
MIB = 1024 * 1024
ALL_FOLLOWING = -1  # CAMERA_IMAGE_CAPTURED request: param 3 (and param 2 = -1: every image)
CAPTURED_PER_REQUEST = 50  # at most this many resent for one request (a client asks again for more)


def _whole(value: float, low: float, high: float) -> int | None:
    if not math.isfinite(value) or value != int(value) or not low <= value <= high:
        return None
    return int(value)


class CameraComponent:
    COMPONENT = mav.MAV_COMP_ID_CAMERA

    def __init__(self, camera, codec, gimbal_device_id: int = 0, video=None):
        self.camera = camera
        self.video = video  # its live stream (payload/thermal_video.py), None: no video
        self.codec = codec
        self.gimbal_device_id = gimbal_device_id  # the autopilot's mount (1) when one is fitted
        self.ftp = CameraFtp(camera)
        self._seq = 0
        self.next_heartbeat_s = 0.0
        self.counters = {"commands": 0, "refused": 0}
        # Told of a bug in a command's handler (the session's handler_failed: an internal error);
        # the command is answered FAILED all the same
        self.on_failure: Callable[[str, BaseException], None] | None = None

    # ----- output -------------------------------------------------------------------------------
    def _framed(self, msg) -> FromComponent:
        frame = FromComponent(msg, self._seq, self.COMPONENT)
        self._seq = (self._seq + 1) & 0xFF
        return frame

    def _ms(self) -> int:
        return int(self.camera.now() * 1000) & 0xFFFFFFFF

    def heartbeat(self):
        return self.codec.heartbeat_encode(mav.MAV_TYPE_CAMERA, mav.MAV_AUTOPILOT_INVALID, 0, 0,
                                           mav.MAV_STATE_ACTIVE)

    def information_fields(self) -> tuple:
        """CAMERA_INFORMATION's fields after time_boot_ms (the autopilot's CAM1_TYPE 6 copies them)."""
        spec = self.camera.spec
        return (list(VENDOR.ljust(32, b"\0")), list(MODEL.ljust(32, b"\0")), 0,
                spec.focal_px * PIXEL_PITCH_MM, spec.width_px * PIXEL_PITCH_MM, spec.height_px * PIXEL_PITCH_MM,
                spec.width_px, spec.height_px, 0, self.flags, 0, b"",
                self.gimbal_device_id, 0)

    @property
    def flags(self) -> int:
        video = mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM if self.video is not None else 0
        return mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE | video

    def information(self):
        return self.codec.camera_information_encode(self._ms(), *self.information_fields())

    @property
    def announcement(self) -> str:
        """What ArduPilot's CAM1_TYPE 6 says when it gets the camera's CAMERA_INFORMATION."""
        return f"Camera: {VENDOR.decode()} {MODEL.decode()} fw:0.0.0.0"

    def trigger(self, sequence: int) -> bool:
        """The autopilot's CAM1_TYPE 6 takes a picture: the IMAGE_START_CAPTURE it sends (one still,
        param 4 its next image number) handled as from the autopilot's component; the ACK goes back
        to the autopilot, which does not read it. True: sent (as ArduPilot's trigger_pic)."""
        system = self.codec.srcSystem
        self._command(Command(mav.MAV_CMD_IMAGE_START_CAPTURE, 0.0, 0.0, 1.0, float(sequence), 0.0, 0.0, 0.0,
                              mav.MAV_FRAME_GLOBAL, False, 0, (system, mav.MAV_COMP_ID_AUTOPILOT1)))
        return True

    def settings(self):
        return self.codec.camera_settings_encode(self._ms(), mav.CAMERA_MODE_IMAGE, math.nan, math.nan)

    def fov_status(self):
        """Where the camera is and how wide it sees: QGroundControl asks after each CAMERA_SETTINGS
        and takes hfov (with the aspect of CAMERA_INFORMATION's resolution) for its gimbal
        control on the video. The point it looks at is not worked out: INT32_MAX, "not known"."""
        look = self.camera.look()
        spec = self.camera.spec
        return self.codec.camera_fov_status_encode(self._ms(), look.lat_e7, look.lon_e7, look.alt_mm,
                                                   NOT_KNOWN, NOT_KNOWN, NOT_KNOWN, list(look.q),
                                                   spec.hfov_deg, spec.vfov_deg)

    def capture_status(self):
        camera = self.camera
        status = 2 if camera.interval_running else 0  # interval set (and idle between stills), or idle
        free = (camera.card_bytes - camera.used_bytes) / MIB
        return self.codec.camera_capture_status_encode(self._ms(), status, 0, camera.interval_s, 0, free,
                                                       len(camera.stills))

    def storage_information(self):
        camera = self.camera
        return self.codec.storage_information_encode(
            self._ms(), 1, 1, mav.STORAGE_STATUS_READY, camera.card_bytes / MIB, camera.used_bytes / MIB,
            (camera.card_bytes - camera.used_bytes) / MIB, math.nan, math.nan, mav.STORAGE_TYPE_OTHER,
            b"thermal card", mav.STORAGE_USAGE_FLAG_SET | mav.STORAGE_USAGE_FLAG_PHOTO)

    def _stream_fields(self) -> tuple:
        """VIDEO_STREAM_INFORMATION's and VIDEO_STREAM_STATUS's shared fields after flags."""
        spec = self.camera.spec
        return (spec.frame_rate_hz, spec.width_px, spec.height_px, self.video.bit_rate, 0, round(spec.hfov_deg))

    def _stream_flags(self) -> int:
        running = mav.VIDEO_STREAM_STATUS_FLAGS_RUNNING if self.video.running else 0
        return running | mav.VIDEO_STREAM_STATUS_FLAGS_THERMAL

    def video_stream_information(self):
        return self.codec.video_stream_information_encode(
            STREAM_ID, 1, mav.VIDEO_STREAM_TYPE_MPEG_TS, self._stream_flags(), *self._stream_fields(),
            VIDEO_NAME.encode(), self.video.uri.encode(), mav.VIDEO_STREAM_ENCODING_H264, 0)

    def video_stream_status(self):
        return self.codec.video_stream_status_encode(STREAM_ID, self._stream_flags(), *self._stream_fields(), 0)

    def image_captured(self, still):
        look = still.look
        return self.codec.camera_image_captured_encode(
            look.time_boot_ms, look.time_utc_us, 0, look.lat_e7, look.lon_e7, look.alt_mm,
            look.relative_alt_mm, list(look.q), still.index, int(still.ok),
            file_url(still.name).encode() if still.ok else b"")

    # ----- input --------------------------------------------------------------------------------
    def due(self, now_s: float) -> bool:
        """Whether poll has something to do now (the session is not idle)."""
        camera = self.camera
        return (now_s >= self.next_heartbeat_s or bool(camera.fresh) or camera.next_s <= now_s + 1e-9
                or (self.video is not None and self.video.due(now_s)))

    def poll(self, now_s: float) -> list:
        """What goes to every link now: the heartbeat when due, a CAMERA_IMAGE_CAPTURED per still."""
        out = []
        if now_s >= self.next_heartbeat_s:
            self.next_heartbeat_s = now_s + HEARTBEAT_S
            out.append(self._framed(self.heartbeat()))
        camera = self.camera
        camera.tick()
        if self.video is not None:
            self.video.tick()
        if camera.fresh:
            out.extend(self._framed(self.image_captured(s)) for s in camera.take_fresh())
        return out

    def receive(self, msg, link_s: float) -> list:
        """The answer to one message addressed to this component, for the asking link."""
        kind = msg.get_type()
        if kind == "COMMAND_LONG":
            return self._command(Command.from_long(msg))
        if kind == "COMMAND_INT":
            return self._command(Command.from_int(msg))
        if kind == "FILE_TRANSFER_PROTOCOL":
            sender = (msg.get_srcSystem(), msg.get_srcComponent())
            return [self._framed(self.codec.file_transfer_protocol_encode(0, *sender, r.encode()))
                    for r in self.ftp.handle(msg.payload, sender, link_s)]
        return []

    def _command(self, c: Command) -> list:
        self.counters["commands"] += 1
        handler = COMMANDS.get(c.command)
        replies: list = []
        try:
            result = Result.UNSUPPORTED if handler is None else handler(self, c, replies)
        except Exception as exc:  # noqa: BLE001 - a bug: reported, and the command still answered once
            if self.on_failure is not None:
                self.on_failure(f"camera command {c.command}", exc)
            result, replies = Result.FAILED, []
        if result != Result.ACCEPTED:
            self.counters["refused"] += 1
        ack = self.codec.command_ack_encode(c.command, int(result), 0, 0, *c.src)
        # the ACK first, then what it asked for (as MAVSDK's camera server orders them)
        return [self._framed(ack), *(self._framed(m) for m in replies)]

    # ----- commands: (component, command, replies to fill) -> result ----------------------------
    def request_message(self, c: Command, replies: list) -> Result:
        msg_id = _whole(c.p1, 0, 2**24)
        if msg_id == mav.MAVLINK_MSG_ID_CAMERA_IMAGE_CAPTURED:
            return self._resend(c.p2, c.p3, replies)
        if msg_id in VIDEO_MESSAGES:  # param 2 the stream id, 0 every stream
            return self._video_message(msg_id, c.p2, replies)
        build: Callable | None = MESSAGES.get(msg_id) if msg_id is not None else None
        if build is None:
            return Result.FAILED
        replies.append(build(self))
        return Result.ACCEPTED

    def _resend(self, first: float, last: float, replies: list) -> Result:
        held = len(self.camera.stills)
        start = _whole(first, -1, 2**31)
        end = _whole(last, -1, 2**31)
        if start is None or end is None:
            return Result.DENIED
        if start == -1:
            start, end = 0, held - 1
        elif end == 0:
            end = start
        elif end == ALL_FOLLOWING:
            end = held - 1
        end = min(end, held - 1, start + CAPTURED_PER_REQUEST - 1)
        if start >= held or end < start:
            return Result.FAILED
        replies.extend(self.image_captured(self.camera.stills[i]) for i in range(start, end + 1))
        return Result.ACCEPTED

    def request_deprecated(self, c: Command, replies: list) -> Result:
        """REQUEST_CAMERA_INFORMATION and its kin: param 1 = 0 asks for nothing. Except
        REQUEST_STORAGE_INFORMATION, whose param 1 is the storage (0 all) and param 2 the request
        (QGroundControl's retry sends 0, 1)."""
        flag = c.p1
        if c.command == mav.MAV_CMD_REQUEST_STORAGE_INFORMATION:
            if _whole(c.p1, 0, 255) not in STORAGES:
                return Result.DENIED
            flag = c.p2
        ask = _whole(flag, 0, 1)  # a MAV_BOOL: "values not equal to 0 or 1 are invalid"
        if ask is None:
            return Result.DENIED
        if ask:
            replies.append(MESSAGES[DEPRECATED_REQUESTS[c.command]](self))
        return Result.ACCEPTED

    def _video_message(self, msg_id: int, stream: float, replies: list) -> Result:
        if self.video is None:
            return Result.FAILED  # as any message it does not send
        if _whole(stream, 0, 255) not in STREAMS:
            return Result.DENIED
        replies.append(VIDEO_MESSAGES[msg_id](self))
        return Result.ACCEPTED

    def request_video_deprecated(self, c: Command, replies: list) -> Result:
        """REQUEST_VIDEO_STREAM_INFORMATION / _STATUS: param 1 the stream id, 0 every stream."""
        return self._video_message(DEPRECATED_VIDEO_REQUESTS[c.command], c.p1, replies)

    def video_streaming(self, c: Command, replies: list) -> Result:
        """VIDEO_START_STREAMING / VIDEO_STOP_STREAMING, param 1 the stream id (0 every stream)."""
        if self.video is None:
            return Result.UNSUPPORTED
        if _whole(c.p1, 0, 255) not in STREAMS:
            return Result.DENIED
        if c.command == mav.MAV_CMD_VIDEO_START_STREAMING:
            self.video.start()
        else:
            self.video.stop()
        return Result.ACCEPTED

    def request_image_captured(self, c: Command, replies: list) -> Result:
        return self._resend(c.p1, 0.0, replies)

    def start_capture(self, c: Command, replies: list) -> Result:
        camera = self.camera
        count = _whole(c.p3, 0, 2**31)
        if (_whole(c.p1, 0, 255) not in SENSORS or count is None or not math.isfinite(c.p2) or c.p2 < 0
                or (count != 1 and c.p2 < 1.0 / camera.spec.frame_rate_hz)):
            return Result.DENIED
        if camera.full:
            return Result.FAILED
        camera.start(c.p2, count)
        return Result.ACCEPTED

    def stop_capture(self, c: Command, replies: list) -> Result:
        if _whole(c.p1, 0, 255) not in SENSORS:
            return Result.DENIED
        self.camera.stop()
        return Result.ACCEPTED

    def set_mode(self, c: Command, replies: list) -> Result:
        if _whole(c.p1, 0, 255) not in SENSORS or c.p2 != mav.CAMERA_MODE_IMAGE:
            return Result.DENIED  # video mode included: this camera takes stills only
        return Result.ACCEPTED

    def format_storage(self, c: Command, replies: list) -> Result:
        if _whole(c.p1, 0, 255) not in STORAGES:
            return Result.DENIED
        self.camera.format()
        replies.append(self.storage_information())
        return Result.ACCEPTED

    def reset_settings(self, c: Command, replies: list) -> Result:
        self.camera.stop()  # the only setting it has is the capture running
        return Result.ACCEPTED


MESSAGES: dict[int, Callable] = {
    mav.MAVLINK_MSG_ID_HEARTBEAT: CameraComponent.heartbeat,
    mav.MAVLINK_MSG_ID_CAMERA_INFORMATION: CameraComponent.information,
    mav.MAVLINK_MSG_ID_CAMERA_SETTINGS: CameraComponent.settings,
    mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS: CameraComponent.capture_status,
    mav.MAVLINK_MSG_ID_STORAGE_INFORMATION: CameraComponent.storage_information,
    mav.MAVLINK_MSG_ID_CAMERA_FOV_STATUS: CameraComponent.fov_status,
}
VIDEO_MESSAGES: dict[int, Callable] = {
    mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION: CameraComponent.video_stream_information,
    mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS: CameraComponent.video_stream_status,
}
DEPRECATED_VIDEO_REQUESTS = {
    mav.MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION: mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION,
    mav.MAV_CMD_REQUEST_VIDEO_STREAM_STATUS: mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS,
}
DEPRECATED_REQUESTS = {
    mav.MAV_CMD_REQUEST_CAMERA_INFORMATION: mav.MAVLINK_MSG_ID_CAMERA_INFORMATION,
    mav.MAV_CMD_REQUEST_CAMERA_SETTINGS: mav.MAVLINK_MSG_ID_CAMERA_SETTINGS,
    mav.MAV_CMD_REQUEST_STORAGE_INFORMATION: mav.MAVLINK_MSG_ID_STORAGE_INFORMATION,
    mav.MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS: mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS,
}
COMMANDS: dict[int, Callable] = {
    mav.MAV_CMD_REQUEST_MESSAGE: CameraComponent.request_message,
    **{command: CameraComponent.request_deprecated for command in DEPRECATED_REQUESTS},
    mav.MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE: CameraComponent.request_image_captured,
    **{command: CameraComponent.request_video_deprecated for command in DEPRECATED_VIDEO_REQUESTS},
    mav.MAV_CMD_VIDEO_START_STREAMING: CameraComponent.video_streaming,
    mav.MAV_CMD_VIDEO_STOP_STREAMING: CameraComponent.video_streaming,
    mav.MAV_CMD_IMAGE_START_CAPTURE: CameraComponent.start_capture,
    mav.MAV_CMD_IMAGE_STOP_CAPTURE: CameraComponent.stop_capture,
    mav.MAV_CMD_SET_CAMERA_MODE: CameraComponent.set_mode,
    mav.MAV_CMD_STORAGE_FORMAT: CameraComponent.format_storage,
    mav.MAV_CMD_RESET_CAMERA_SETTINGS: CameraComponent.reset_settings,
}
