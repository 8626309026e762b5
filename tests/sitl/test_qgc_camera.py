"""QGroundControl's camera page against the real process: pymavlink plays QGC's camera manager
(src/Camera of a recent snapshot of QGroundControl's master: QGCCameraManager,
CameraDiscoveryStateMachine and VehicleCameraControl) request by request, and each answer QGC reads
to go on is asserted.

What QGC does, in short (read from its source, paraphrased):
- Cameras are the components 100-105 (MAV_COMP_ID_CAMERA..CAMERA6) of the vehicle's system and the
  autopilot itself (component 1, which may stand in for a camera of its own). The first HEARTBEAT
  from one starts its discovery, whatever its MAV_TYPE.
- Discovery asks for CAMERA_INFORMATION, alternating REQUEST_MESSAGE(259) with the older
  REQUEST_CAMERA_INFORMATION(1), up to 10 tries with a back-off; any answer but ACCEPTED counts
  as a failed try, and so does an ACCEPTED REQUEST_MESSAGE whose message never comes (QGC's
  requestMessage reports it FAILED, "message not received"). The CAMERA_INFORMATION itself, in
  either order with its ACK, adds the camera to the list (labelled with model_name); QGC catches
  that message itself, so whether it comes before or after its ACK does not matter. A camera
  silent for 5 s (no HEARTBEAT) is dropped.
- With no cam_definition_uri the camera is "basic": no definition file, no PARAM_EXT.
- Then: CAMERA_SETTINGS after 0.5 s (its mode_id is the page's photo/video mode; NaN zoom and
  focus are ignored), and after each CAMERA_SETTINGS a REQUEST_MESSAGE for CAMERA_FOV_STATUS (hfov
  feeds its gimbal control on the video; a refusal is only logged); video streams after 1 s if
  the flags say HAS_VIDEO_STREAM (REQUEST_MESSAGE(269) for stream 0, then each missing id from 1
  to `count`); CAMERA_CAPTURE_STATUS after 1.5 s and STORAGE_INFORMATION after 2 s. Each request is
  retried every second (alternating the REQUEST_MESSAGE and the older command) up to 5 times.
- Take photo is only offered when the flags have CAPTURE_IMAGE (or HAS_VIDEO_STREAM): it sends
  IMAGE_START_CAPTURE (camera 0, interval 0, count 1; a time-lapse: its interval, count 0 for
  "until stopped"), marks the photo busy and, on ACCEPTED, asks CAMERA_CAPTURE_STATUS 1 s later,
  again each second while image_status is not idle (0). image_status 2 or 3 is a time-lapse
  running, which offers IMAGE_STOP_CAPTURE (camera 0). A refused capture asks for the status up
  to 5 times and then goes idle. CAMERA_IMAGE_CAPTURED with capture_result 1 puts the picture's
  position on the map.
- Video: a stream flagged THERMAL is kept apart as the overlay on the main video, and for an
  MPEG_TS stream QGC takes the uri as the port to listen on (or a whole mpegts:// URL); neither
  is asserted here (the thermal camera's uri is a udp:// URL that PyAV opens as it is).
- SET_CAMERA_MODE only when the flags have HAS_MODES; zoom and focus commands only with
  HAS_BASIC_ZOOM / HAS_BASIC_FOCUS. Reset settings is RESET_CAMERA_SETTINGS(1), followed on
  ACCEPTED by a new CAMERA_SETTINGS request; format is STORAGE_FORMAT(storage 1, format 1).
"""
from __future__ import annotations

import time

import pytest
from pymavlink.dialects.v20 import ardupilotmega as mav

from .conftest import free_udp_port
from .pymav import Gcs

pytestmark = pytest.mark.sitl
AUTOPILOT, THERMAL = mav.MAV_COMP_ID_AUTOPILOT1, mav.MAV_COMP_ID_CAMERA
QGC_CAMERA_IDS = range(mav.MAV_COMP_ID_CAMERA, mav.MAV_COMP_ID_CAMERA6 + 1)
QGC_SILENT_S = 5.0  # a camera whose HEARTBEAT stops for this long leaves QGC's list
QGC_DISCOVERY_TRIES = 10
REPLY_WAIT_S = 1.0  # after an ACCEPTED request, how long (wall) a missing message is waited for


class QgcCameraManager:
    """QGC's side of the camera protocol over one pymavlink link, as a ground station (255)."""

    def __init__(self, gcs: Gcs):
        self.gcs = gcs
        self.system = gcs.conn.target_system

    def components_heard(self, within_s: float) -> dict:
        """Component -> its last HEARTBEAT, for the components QGC treats as cameras."""
        heard: dict = {}
        deadline = time.monotonic() + within_s
        while time.monotonic() < deadline:
            hb = self.gcs.recv("HEARTBEAT", deadline - time.monotonic(),
                               lambda m: m.get_srcSystem() == self.system)
            if hb is not None and (hb.get_srcComponent() == AUTOPILOT or hb.get_srcComponent() in QGC_CAMERA_IDS):
                heard[hb.get_srcComponent()] = hb
        return heard

    def ask(self, component: int, command: int, *params, reply: str | None = None, timeout: float = 5.0,
            reply_optional: bool = False):
        """One command to `component`: (its ACK's result, the `reply` message or None). Both are
        waited for, in either order (the autopilot sends the message first, the camera the ACK);
        with reply_optional, a message not come REPLY_WAIT_S after an ACCEPTED ACK is None."""
        p = [float(x) for x in params] + [0.0] * (7 - len(params))
        self.gcs.mav.command_long_send(self.system, component, command, 0, *p)
        types = ["COMMAND_ACK"] + ([reply] if reply else [])

        def ours(m) -> bool:
            return m.get_srcComponent() == component and (m.get_type() == reply or m.command == command)

        ack = answer = None
        while ack is None or (reply and answer is None and ack.result == mav.MAV_RESULT_ACCEPTED):
            msg = self.gcs.recv(types, REPLY_WAIT_S if reply_optional and ack is not None else timeout, ours)
            if msg is None and reply_optional and ack is not None:
                break  # QGC: "message not received", a failed request
            assert msg is not None, f"component {component}: no answer to command {command} (ACK {ack})"
            if msg.get_type() == "COMMAND_ACK":
                ack = msg
            else:
                answer = msg
        return ack.result, answer

    def discover(self, component: int):
        """QGC's discovery: CAMERA_INFORMATION by REQUEST_MESSAGE, then by the older command,
        alternately, until one answers or the tries run out. (CAMERA_INFORMATION, the results)."""
        results = []
        for attempt in range(QGC_DISCOVERY_TRIES):
            if attempt % 2 == 0:
                result, info = self.ask(component, mav.MAV_CMD_REQUEST_MESSAGE,
                                        mav.MAVLINK_MSG_ID_CAMERA_INFORMATION, reply="CAMERA_INFORMATION",
                                        reply_optional=True)
            else:
                result, info = self.ask(component, mav.MAV_CMD_REQUEST_CAMERA_INFORMATION, 1,
                                        reply="CAMERA_INFORMATION")
            results.append(result)
            if info is not None:
                return info, results
        return None, results

    def capture_status(self, component: int, legacy: bool = False):
        if legacy:
            return self.ask(component, mav.MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS, 1, reply="CAMERA_CAPTURE_STATUS")
        return self.ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS,
                        reply="CAMERA_CAPTURE_STATUS")


def model(info) -> str:
    return bytes(info.model_name).rstrip(b"\0").decode()


def photo_offered(info) -> bool:
    """QGC's take-photo button: enabled with CAPTURE_IMAGE or HAS_VIDEO_STREAM in the flags."""
    return bool(info.flags & (mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE | mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM))


@pytest.fixture
def qgc(autopilot_factory):
    """The thermal camera with its video on a free port, and the autopilot's own servo camera
    (CAM1_TYPE 1): QGC lists both."""
    ap = autopilot_factory(extra=("--thermal-camera", "--video-port", str(free_udp_port()),
                                  "--param", "CAM1_TYPE=1"))
    gcs = Gcs(ap.pymavlink_url, timeout=15)
    yield QgcCameraManager(gcs)
    gcs.close()


def test_qgc_lists_the_thermal_camera_and_reads_its_state(qgc):
    heard = qgc.components_heard(3.0)
    assert set(heard) == {AUTOPILOT, THERMAL}, sorted(heard)
    assert heard[THERMAL].type == mav.MAV_TYPE_CAMERA

    # discovery: the first try answers (no back-off), and so would the older command
    info, results = qgc.discover(THERMAL)
    assert info is not None and results == [mav.MAV_RESULT_ACCEPTED]
    assert model(info) == "Thermal 160 (Lepton 3.5 class)"  # the label in QGC's camera list
    assert info.cam_definition_uri == ""  # basic: no definition file to fetch, no PARAM_EXT
    assert photo_offered(info)
    assert info.flags & mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE  # a real still, not a grab of the video
    assert not info.flags & mav.CAMERA_CAP_FLAGS_HAS_MODES  # no SET_CAMERA_MODE: stills only
    assert not info.flags & (mav.CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM | mav.CAMERA_CAP_FLAGS_HAS_BASIC_FOCUS)
    assert (info.resolution_h, info.resolution_v) == (160, 120)  # QGC's aspect for the FOV: 0.75
    result, legacy = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_CAMERA_INFORMATION, 1, reply="CAMERA_INFORMATION")
    assert result == mav.MAV_RESULT_ACCEPTED and model(legacy) == model(info)

    # settings (both forms), then the FOV QGC asks for after each
    for command, params in ((mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_CAMERA_SETTINGS,)),
                            (mav.MAV_CMD_REQUEST_CAMERA_SETTINGS, (1,))):
        result, settings = qgc.ask(THERMAL, command, *params, reply="CAMERA_SETTINGS")
        assert result == mav.MAV_RESULT_ACCEPTED and settings.mode_id == mav.CAMERA_MODE_IMAGE
    result, fov = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_FOV_STATUS,
                          reply="CAMERA_FOV_STATUS")
    assert result == mav.MAV_RESULT_ACCEPTED and 0 < fov.hfov < 180
    assert fov.hfov == pytest.approx(57.0)

    # video: stream 0 asks for all; the one stream is id 1 of a count of 1, so QGC asks no more
    assert info.flags & mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM
    result, stream = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_VIDEO_STREAM_INFORMATION, 0,
                             reply="VIDEO_STREAM_INFORMATION")
    assert result == mav.MAV_RESULT_ACCEPTED and (stream.stream_id, stream.count) == (1, 1)
    assert stream.type == mav.VIDEO_STREAM_TYPE_MPEG_TS
    result, again = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION, 1,
                            reply="VIDEO_STREAM_INFORMATION")
    assert result == mav.MAV_RESULT_ACCEPTED and again.stream_id == 1
    result, status = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_VIDEO_STREAM_STATUS, 1,
                             reply="VIDEO_STREAM_STATUS")
    assert result == mav.MAV_RESULT_ACCEPTED and status.stream_id == 1

    # capture status (both forms): idle, with free space to show
    for legacy_form in (False, True):
        result, capture = qgc.capture_status(THERMAL, legacy_form)
        assert result == mav.MAV_RESULT_ACCEPTED and capture.image_status == 0
        assert capture.available_capacity > 0
    # storage (both forms): READY, or QGC shows no card and keeps no figures
    for command, params in ((mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_STORAGE_INFORMATION, 0)),
                            (mav.MAV_CMD_REQUEST_STORAGE_INFORMATION, (0, 1))):
        result, storage = qgc.ask(THERMAL, command, *params, reply="STORAGE_INFORMATION")
        assert result == mav.MAV_RESULT_ACCEPTED and storage.status == mav.STORAGE_STATUS_READY
        assert storage.total_capacity >= storage.available_capacity > 0  # MiB, as QGC shows them


def test_qgc_takes_a_photo_and_a_time_lapse_with_the_thermal_camera(qgc):
    assert qgc.discover(THERMAL)[0] is not None

    # one photo: ACCEPTED, the picture on the map, and the status idle again so the button frees
    result, captured = qgc.ask(THERMAL, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1, reply="CAMERA_IMAGE_CAPTURED")
    assert result == mav.MAV_RESULT_ACCEPTED
    assert captured.capture_result == 1 and captured.lat != 0 and captured.lon != 0
    result, status = qgc.capture_status(THERMAL)
    assert result == mav.MAV_RESULT_ACCEPTED and status.image_status == 0 and status.image_count == 1
    first = captured.image_index

    # a time-lapse, QGC's default: every 1 s until stopped; the first still at once, numbered on
    # from the photo's (CAMERA_IMAGE_CAPTURED's image_index runs on without a gap)
    result, lapse_first = qgc.ask(THERMAL, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 1.0, 0,
                                  reply="CAMERA_IMAGE_CAPTURED")
    assert result == mav.MAV_RESULT_ACCEPTED and lapse_first.image_index == first + 1
    result, status = qgc.capture_status(THERMAL)
    assert result == mav.MAV_RESULT_ACCEPTED and status.image_status in (2, 3)  # QGC: "capturing" + Stop
    assert status.image_interval == pytest.approx(1.0)
    indexes = []
    while len(indexes) < 2:  # and they go on coming (some came while the status was asked)
        msg = qgc.gcs.recv("CAMERA_IMAGE_CAPTURED", 10, lambda m: m.get_srcComponent() == THERMAL)
        assert msg is not None, f"the time-lapse stopped after {indexes}"
        indexes.append(msg.image_index)
    assert indexes[0] > lapse_first.image_index and indexes[1] == indexes[0] + 1
    assert qgc.ask(THERMAL, mav.MAV_CMD_IMAGE_STOP_CAPTURE, 0)[0] == mav.MAV_RESULT_ACCEPTED
    result, status = qgc.capture_status(THERMAL)
    assert result == mav.MAV_RESULT_ACCEPTED and status.image_status == 0

    # reset settings: ACCEPTED ends QGC's "resetting" and it reads the settings again
    assert qgc.ask(THERMAL, mav.MAV_CMD_RESET_CAMERA_SETTINGS, 1)[0] == mav.MAV_RESULT_ACCEPTED
    result, settings = qgc.ask(THERMAL, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_SETTINGS,
                               reply="CAMERA_SETTINGS")
    assert result == mav.MAV_RESULT_ACCEPTED and settings.mode_id == mav.CAMERA_MODE_IMAGE

    # format the card: storage 1, and the card is empty after it
    result, storage = qgc.ask(THERMAL, mav.MAV_CMD_STORAGE_FORMAT, 1, 1, reply="STORAGE_INFORMATION")
    assert result == mav.MAV_RESULT_ACCEPTED and storage.used_capacity == 0
    result, status = qgc.capture_status(THERMAL)
    assert result == mav.MAV_RESULT_ACCEPTED and status.image_count == 0

    # still listed: its HEARTBEATs come well inside QGC's 5 s of silence
    beats = []
    while len(beats) < 3:
        hb = qgc.gcs.recv("HEARTBEAT", QGC_SILENT_S, lambda m: m.get_srcComponent() == THERMAL)
        assert hb is not None, "the camera fell silent: QGC would drop it"
        beats.append(time.monotonic())


def test_qgc_lists_the_autopilots_camera_as_arducopter_answers(qgc):
    """CAM1_TYPE 1: QGC asks the autopilot too, and ArduCopter 4.7 answers (the reference, asked
    the same): CAMERA_INFORMATION all blank with no flags, so QGC lists a camera with an empty
    label whose photo button is off (QGC sends it no IMAGE_START_CAPTURE); CAMERA_SETTINGS and
    CAMERA_CAPTURE_STATUS answer, STORAGE_INFORMATION is FAILED (QGC gives up after its retries)
    and the older REQUEST_CAMERA_* commands are UNSUPPORTED."""
    info, results = qgc.discover(AUTOPILOT)
    assert info is not None and results == [mav.MAV_RESULT_ACCEPTED]
    assert model(info) == "" and info.flags == 0 and info.cam_definition_uri == ""
    assert not photo_offered(info)
    result, settings = qgc.ask(AUTOPILOT, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_SETTINGS,
                               reply="CAMERA_SETTINGS")
    assert result == mav.MAV_RESULT_ACCEPTED and settings.mode_id == mav.CAMERA_MODE_IMAGE
    result, capture = qgc.capture_status(AUTOPILOT)
    assert result == mav.MAV_RESULT_ACCEPTED and capture.image_status == 0
    assert qgc.ask(AUTOPILOT, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_STORAGE_INFORMATION, 0)[0] == \
        mav.MAV_RESULT_FAILED
    for command in (mav.MAV_CMD_REQUEST_CAMERA_INFORMATION, mav.MAV_CMD_REQUEST_CAMERA_SETTINGS,
                    mav.MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS):
        assert qgc.ask(AUTOPILOT, command, 1)[0] == mav.MAV_RESULT_UNSUPPORTED


def test_without_cam1_qgc_gives_the_autopilot_up_and_keeps_the_thermal_camera(autopilot_factory):
    """CAM1_TYPE 0 (the default): no discovery try at the autopilot brings CAMERA_INFORMATION, as
    on ArduCopter (measured, tests/parity/probes/camera.py no_camera_v2: REQUEST_MESSAGE ACCEPTED
    and nothing sent; REQUEST_CAMERA_INFORMATION UNSUPPORTED), so QGC gives up on it after its
    tries and lists the thermal camera alone."""
    ap = autopilot_factory(extra=("--thermal-camera", "--video-port", "0"))
    gcs = Gcs(ap.pymavlink_url, timeout=15)
    try:
        qgc = QgcCameraManager(gcs)
        info, results = qgc.discover(AUTOPILOT)
        assert info is None and len(results) == QGC_DISCOVERY_TRIES
        assert results == [mav.MAV_RESULT_ACCEPTED, mav.MAV_RESULT_UNSUPPORTED] * (QGC_DISCOVERY_TRIES // 2)
        info, _ = qgc.discover(THERMAL)
        assert info is not None and photo_offered(info)
        # no video (--video-port 0): no HAS_VIDEO_STREAM, so QGC asks for no stream
        assert not info.flags & mav.CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM
    finally:
        gcs.close()
