"""The thermal camera's MAVLink component (autopilot/mavlink/camera_component.py, camera_ftp.py)
over a real ThermalCamera (payload/thermal_camera.py) and frames packed and parsed as on the wire:
what it says unasked, what each command answers (exactly one COMMAND_ACK, then what was asked),
bad input, interval captures in sim time, the card read by FTP."""
from __future__ import annotations

import io
import math
import struct

import numpy as np
import pytest

from firefly.autopilot.mavlink.camera_component import CameraComponent
from firefly.autopilot.mavlink.dialect import mavlink as mav, new_codec
from firefly.autopilot.payload.thermal_camera import Look, ThermalCamera, quaternion_of
from firefly.sim.fire import Fire, FireWorld
from firefly.sim.thermal_camera import ThermalCameraSpec, pose_from_attitude
from firefly.sim.thermal_still import Geotag, load_radiometric

SYSTEM = 1
FTP_HEADER = struct.Struct("<HBBBBBxI")


class Clock:
    t = 0.0


def look_at(clock: Clock) -> Look:
    pose = pose_from_attitude(0.0, 0.0, 20.0)
    return Look(pose, Geotag(-35.0, 149.0, 604.0, 0.0, 0.0, 0.0, -90.0, 0.0, 1.8e9 + clock.t), -350000000,
                1490000000, 604000, 20000, quaternion_of(pose.rotation), int(clock.t * 1000),
                int((1.8e9 + clock.t) * 1e6))


@pytest.fixture
def rig():
    clock = Clock()
    camera = ThermalCamera(ThermalCameraSpec(), FireWorld(fires=(Fire(0.0, 0.0),)), lambda: look_at(clock),
                           lambda: clock.t)
    component = CameraComponent(camera, new_codec(SYSTEM))
    return clock, camera, component


GCS = new_codec(255, 190)
WIRE = new_codec(255, 190)  # parses what the component packs


def wire(messages) -> list:
    """The component's messages as a client receives them: packed by the vehicle's codec, parsed."""
    codec = new_codec(SYSTEM)
    out = []
    for m in messages:
        out.extend(WIRE.parse_buffer(m.pack(codec)) or [])
    return out


def long(command: int, *params, component: int = CameraComponent.COMPONENT):
    p = [float(x) for x in params] + [0.0] * (7 - len(params))
    frame = GCS.command_long_encode(SYSTEM, component, command, 0, *p).pack(GCS)
    return new_codec(SYSTEM).parse_buffer(frame)[0]


def ask(component, command: int, *params) -> list:
    return wire(component.receive(long(command, *params), 0.0))


def acks(messages) -> list:
    return [m for m in messages if m.get_type() == "COMMAND_ACK"]


def test_heartbeat_each_second_of_sim_time_as_a_camera(rig):
    clock, _, component = rig
    beats = []
    for step in range(25):
        clock.t = step * 0.1
        beats += [m for m in wire(component.poll(clock.t)) if m.get_type() == "HEARTBEAT"]
    assert len(beats) == 3  # at 0, 1 and 2 s
    hb = beats[0]
    assert (hb.get_srcSystem(), hb.get_srcComponent()) == (SYSTEM, mav.MAV_COMP_ID_CAMERA)
    assert (hb.type, hb.autopilot) == (mav.MAV_TYPE_CAMERA, mav.MAV_AUTOPILOT_INVALID)


def test_information_after_its_one_ack(rig):
    _, _, component = rig
    got = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_INFORMATION)
    assert [m.get_type() for m in got] == ["COMMAND_ACK", "CAMERA_INFORMATION"]
    ack, info = got
    assert ack.result == mav.MAV_RESULT_ACCEPTED and (ack.target_system, ack.target_component) == (255, 190)
    assert (info.resolution_h, info.resolution_v) == (160, 120)
    assert info.flags == mav.CAMERA_CAP_FLAGS_CAPTURE_IMAGE and info.cam_definition_uri == ""
    assert bytes(info.vendor_name).rstrip(b"\0") == b"Firefly"
    assert info.focal_length == pytest.approx(147.34 * 0.012, rel=1e-3)


@pytest.mark.parametrize("msg_id, name", [(mav.MAVLINK_MSG_ID_CAMERA_SETTINGS, "CAMERA_SETTINGS"),
                                          (mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS, "CAMERA_CAPTURE_STATUS"),
                                          (mav.MAVLINK_MSG_ID_STORAGE_INFORMATION, "STORAGE_INFORMATION")])
def test_the_other_messages_on_request(rig, msg_id, name):
    got = ask(rig[2], mav.MAV_CMD_REQUEST_MESSAGE, msg_id)
    assert [m.get_type() for m in got] == ["COMMAND_ACK", name] and got[0].result == mav.MAV_RESULT_ACCEPTED


def test_the_older_requests_and_their_flag(rig):
    """REQUEST_CAMERA_INFORMATION and its kin take the request in param 1; REQUEST_STORAGE_INFORMATION
    takes the storage there and the request in param 2 (QGroundControl's retry: 0 all, 1 yes)."""
    component = rig[2]
    storage = ask(component, mav.MAV_CMD_REQUEST_STORAGE_INFORMATION, 0, 1)
    assert [m.get_type() for m in storage] == ["COMMAND_ACK", "STORAGE_INFORMATION"]
    assert storage[0].result == mav.MAV_RESULT_ACCEPTED
    assert [m.get_type() for m in ask(component, mav.MAV_CMD_REQUEST_STORAGE_INFORMATION, 1, 0)] == ["COMMAND_ACK"]
    assert acks(ask(component, mav.MAV_CMD_REQUEST_STORAGE_INFORMATION, 2, 1))[0].result == mav.MAV_RESULT_DENIED
    assert acks(ask(component, mav.MAV_CMD_REQUEST_STORAGE_INFORMATION, 0, 2))[0].result == mav.MAV_RESULT_DENIED
    info = ask(component, mav.MAV_CMD_REQUEST_CAMERA_INFORMATION, 1)
    assert [m.get_type() for m in info] == ["COMMAND_ACK", "CAMERA_INFORMATION"]
    assert [m.get_type() for m in ask(component, mav.MAV_CMD_REQUEST_CAMERA_SETTINGS, 0)] == ["COMMAND_ACK"]


def test_fov_status_gives_the_lens_and_where_the_camera_is(rig):
    """QGroundControl asks for it after each CAMERA_SETTINGS and reads hfov (its gimbal control on
    the video): the lens's 57 x 44.3 deg, the camera's position and attitude; the ground point
    it looks at is left "not known" (INT32_MAX)."""
    got = ask(rig[2], mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_FOV_STATUS)
    assert [m.get_type() for m in got] == ["COMMAND_ACK", "CAMERA_FOV_STATUS"]
    fov = got[1]
    assert (fov.hfov, fov.vfov) == (pytest.approx(57.0), pytest.approx(44.3, abs=0.05))
    assert (fov.lat_camera, fov.lon_camera, fov.alt_camera) == (-350000000, 1490000000, 604000)
    assert fov.lat_image == fov.lon_image == fov.alt_image == 2**31 - 1
    assert fov.q == pytest.approx([math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0], abs=1e-6)  # straight down


def test_a_photo_is_announced_with_its_geotag_and_file(rig):
    clock, camera, component = rig
    got = ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    assert [(m.get_type(), m.result) for m in got] == [("COMMAND_ACK", mav.MAV_RESULT_ACCEPTED)]
    captured = [m for m in wire(component.poll(0.0)) if m.get_type() == "CAMERA_IMAGE_CAPTURED"]
    assert len(captured) == 1
    c = captured[0]
    assert (c.image_index, c.capture_result, c.file_url) == (0, 1, "mftp://DCIM/IR_0000.tif")
    assert (c.lat, c.lon, c.alt, c.relative_alt) == (-350000000, 1490000000, 604000, 20000)
    # looking straight down: the optical axis (x) pitched -90 deg about the east axis
    assert c.q == pytest.approx([math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0], abs=1e-6)
    image, geotag = load_radiometric(io.BytesIO(camera.stills[0].data))
    assert geotag.lat_deg == -35.0 and image.max() > 60.0 > 30.0 > np.percentile(image, 5)
    # resent on request, by either command; nothing for an index not taken
    again = ask(component, mav.MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE, 0)
    assert [m.get_type() for m in again] == ["COMMAND_ACK", "CAMERA_IMAGE_CAPTURED"]
    again = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_IMAGE_CAPTURED, -1)
    assert [m.image_index for m in again[1:]] == [0]
    missing = ask(component, mav.MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE, 3)
    assert [(m.get_type(), m.result) for m in missing] == [("COMMAND_ACK", mav.MAV_RESULT_FAILED)]


def test_an_interval_capture_runs_in_sim_time_and_stops_after_its_count(rig):
    clock, camera, component = rig
    assert acks(ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 1.0, 3))[0].result == mav.MAV_RESULT_ACCEPTED
    status = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS)[1]
    assert (status.image_status, status.image_interval) == (2, 1.0)
    taken = []
    for step in range(50):
        clock.t = step * 0.1
        taken += [(m.image_index, round(clock.t, 1)) for m in wire(component.poll(clock.t))
                  if m.get_type() == "CAMERA_IMAGE_CAPTURED"]
    assert taken == [(0, 0.0), (1, 1.0), (2, 2.0)]
    status = ask(component, mav.MAV_CMD_REQUEST_MESSAGE, mav.MAVLINK_MSG_ID_CAMERA_CAPTURE_STATUS)[1]
    assert (status.image_status, status.image_count) == (0, 3)


def test_a_capture_that_raises_ends_its_series(rig):
    """A bug in a capture (say a geotag it cannot make) is the session's to count; the series
    stops, so that the next poll does not meet it again."""
    clock, camera, component = rig
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0.5, 0)

    def broken():
        raise ValueError("geotag")
    camera.capture = broken
    clock.t = 1.0
    with pytest.raises(ValueError):
        camera.tick()
    assert camera.left == 0
    camera.tick()  # nothing due any more: no second raise


def test_an_interval_until_stopped(rig):
    clock, camera, component = rig
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0.5, 0)
    for step in range(1, 11):
        clock.t = step * 0.1
        component.poll(clock.t)
    assert len(camera.stills) == 3  # at 0, 0.5 and 1.0 s
    assert acks(ask(component, mav.MAV_CMD_IMAGE_STOP_CAPTURE))[0].result == mav.MAV_RESULT_ACCEPTED
    clock.t = 5.0
    component.poll(clock.t)
    assert len(camera.stills) == 3


@pytest.mark.parametrize("command, params, result", [
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (2, 0, 1), mav.MAV_RESULT_DENIED),  # no such sensor
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (math.nan, 0, 1), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, math.nan, 1), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0, 5), mav.MAV_RESULT_DENIED),  # interval 0, count not 1
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 0.05, 0), mav.MAV_RESULT_DENIED),  # faster than a frame
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, -1, 1), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 1, -2), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_IMAGE_START_CAPTURE, (0, 1, 1.5), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_IMAGE_STOP_CAPTURE, (7,), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_SET_CAMERA_MODE, (0, mav.CAMERA_MODE_VIDEO), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_SET_CAMERA_MODE, (0, math.nan), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_SET_CAMERA_MODE, (0, mav.CAMERA_MODE_IMAGE), mav.MAV_RESULT_ACCEPTED),
    (mav.MAV_CMD_STORAGE_FORMAT, (3, 1, 1), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_REQUEST_MESSAGE, (5000,), mav.MAV_RESULT_FAILED),  # a message it does not send
    (mav.MAV_CMD_REQUEST_MESSAGE, (math.nan,), mav.MAV_RESULT_FAILED),
    (mav.MAV_CMD_REQUEST_MESSAGE, (mav.MAVLINK_MSG_ID_CAMERA_IMAGE_CAPTURED, math.nan), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE, (-5,), mav.MAV_RESULT_DENIED),
    (mav.MAV_CMD_VIDEO_START_CAPTURE, (0, 1), mav.MAV_RESULT_UNSUPPORTED),
    (mav.MAV_CMD_COMPONENT_ARM_DISARM, (1,), mav.MAV_RESULT_UNSUPPORTED),  # the autopilot's, not the camera's
])
def test_each_command_one_ack_and_bad_input_refused(rig, command, params, result):
    _, camera, component = rig
    got = ask(component, command, *params)
    assert [(m.command, m.result) for m in acks(got)] == [(command, result)]
    if result != mav.MAV_RESULT_ACCEPTED:
        assert len(got) == 1 and not camera.stills


def test_a_command_int_is_answered_too(rig):
    _, _, component = rig
    frame = GCS.command_int_encode(SYSTEM, CameraComponent.COMPONENT, 0, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0,
                                   0, 0, 1, 0, 0, 0, 0).pack(GCS)
    got = wire(component.receive(new_codec(SYSTEM).parse_buffer(frame)[0], 0.0))
    assert [(m.get_type(), m.result) for m in got] == [("COMMAND_ACK", mav.MAV_RESULT_ACCEPTED)]


def test_format_empties_the_card_and_counts_from_zero(rig):
    _, camera, component = rig
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    got = ask(component, mav.MAV_CMD_STORAGE_FORMAT, 1, 1, 1)
    assert [m.get_type() for m in got] == ["COMMAND_ACK", "STORAGE_INFORMATION"]
    assert got[1].used_capacity == 0.0 and got[1].status == mav.STORAGE_STATUS_READY
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    assert [s.name for s in camera.stills] == ["IR_0000.tif"]


def test_a_full_card_fails_a_capture(rig):
    _, camera, component = rig
    camera.card_bytes = camera.still_bytes * 2
    for _ in range(2):
        ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    assert acks(ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1))[0].result == mav.MAV_RESULT_FAILED
    assert len(camera.stills) == 2


def ftp(component, seq: int, opcode: int, session: int = 0, offset: int = 0, data: bytes = b"", size=None):
    payload = FTP_HEADER.pack(seq, session, opcode, len(data) if size is None else size, 0, 0, offset) + data
    frame = GCS.file_transfer_protocol_encode(0, SYSTEM, CameraComponent.COMPONENT,
                                              list(payload.ljust(251, b"\0"))).pack(GCS)
    replies = wire(component.receive(new_codec(SYSTEM).parse_buffer(frame)[0], float(seq)))
    assert len(replies) == 1 and replies[0].get_srcComponent() == CameraComponent.COMPONENT
    raw = bytes(replies[0].payload)
    _, _, op, size, _, _, _ = FTP_HEADER.unpack_from(raw)
    return op, raw[12:12 + size]


def test_the_card_is_read_by_ftp_and_cannot_be_written(rig):
    _, camera, component = rig
    ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    still = camera.stills[0].data
    op, listing = ftp(component, 1, 3, data=b"DCIM")  # ListDirectory
    assert op == 128 and f"FIR_0000.tif\t{len(still)}".encode() in listing
    op, data = ftp(component, 3, 4, data=b"DCIM/IR_0000.tif")  # OpenFileRO
    assert op == 128 and struct.unpack("<I", data)[0] == len(still)
    got, seq = b"", 5
    while len(got) < len(still):
        op, data = ftp(component, seq, 5, offset=len(got), size=239)
        assert op == 128
        got, seq = got + data, seq + 2
    assert got == still
    assert ftp(component, seq, 1)[0] == 128  # TerminateSession
    assert ftp(component, seq + 2, 6, data=b"DCIM/x.tif")[0] == 129  # CreateFile: NAK
    assert ftp(component, seq + 4, 4, data=b"DCIM/IR_0009.tif")[0] == 129  # no such still


# ----- ArduCopter's CAM1_TYPE 6 (AP_Camera_MAVLinkCamV2) driving the camera --------------------------
def camv2_vehicle(tmp_path, fitted: bool = True):
    from firefly.autopilot.cli.main import attach_thermal_camera
    from firefly.autopilot.mavlink.session import Session
    from firefly.autopilot.params import ParamStore
    from firefly.autopilot.vehicle import Vehicle, VehicleConfig
    store = ParamStore()
    store.set("CAM1_TYPE", 6)
    v = Vehicle(VehicleConfig(), store)
    session = Session(v, new_codec(SYSTEM))
    if fitted:
        attach_thermal_camera(v, session, ThermalCameraSpec(), tmp_path / "thermal", {})
    v.run_until(0.5)
    return v, session


def autopilot_command(v, number: int, *params) -> int:
    from firefly.autopilot.mavlink.camera_commands import HANDLERS
    from firefly.autopilot.mavlink.commands import Command
    p = (list(params) + [0.0] * 7)[:7]
    session = type("Session", (), {"vehicle": v})()
    return HANDLERS[number](session, Command(number, *p, mav.MAV_FRAME_GLOBAL, False, 0, (255, 190)))


def test_cam1_type_6_takes_each_picture_with_the_thermal_camera(tmp_path):
    v, session = camv2_vehicle(tmp_path)
    texts = [text for _, text in v.drain_events()]
    assert "Camera: Firefly Thermal 160 (Lepton 3.5 class) fw:0.0.0.0" in texts
    outputs = list(v.servo_pwm)
    assert autopilot_command(v, mav.MAV_CMD_DO_DIGICAM_CONTROL, 0, 0, 0, 0, 1) == mav.MAV_RESULT_ACCEPTED
    assert list(v.servo_pwm) == outputs  # no shutter output: the camera takes it
    camera = session.camera_component.camera
    assert [s.name for s in camera.stills] == ["IR_0000.tif"] and v.camera.feedback.image_index == 1
    assert (tmp_path / "thermal" / "IR_0000.tif").read_bytes() == camera.stills[0].data  # its copy on disk
    sent = wire(session.poll(v.time_s))
    kinds = {(m.get_type(), m.get_srcComponent()) for m in sent}
    assert {("CAMERA_FEEDBACK", 1), ("CAMERA_IMAGE_CAPTURED", mav.MAV_COMP_ID_CAMERA)} <= kinds
    info = wire([session.build(mav.MAVLINK_MSG_ID_CAMERA_INFORMATION)])[0]  # the autopilot's copy
    assert info.get_srcComponent() == 1 and (info.resolution_h, info.resolution_v) == (160, 120)


def test_cam1_type_6_without_the_camera_takes_no_picture(tmp_path):
    v, session = camv2_vehicle(tmp_path, fitted=False)
    assert autopilot_command(v, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1) == mav.MAV_RESULT_FAILED
    assert v.camera.feedback is None
    assert session.build(mav.MAVLINK_MSG_ID_CAMERA_INFORMATION) is None  # as ArduPilot: none until found


def test_any_command_gets_exactly_one_ack_and_never_raises(rig):
    """Every command the camera knows, with parameters from the awkward corners (NaN, inf, huge,
    negative, fractional): one COMMAND_ACK each, for that command, whatever else follows."""
    from firefly.autopilot.mavlink.camera_component import COMMANDS
    rng = np.random.default_rng(5)
    corners = [0.0, 1.0, -1.0, 0.5, 2.0, 259.0, 263.0, 1e9, -1e9, math.nan, math.inf, -math.inf, 3.4e38]
    clock, _, component = rig
    for trial in range(400):
        command = int(rng.choice(list(COMMANDS) + [0, 65535]))
        params = [float(rng.choice(corners)) for _ in range(7)]
        got = ask(component, command, *params)
        assert [m.command for m in acks(got)] == [command], (command, params)
        clock.t += 0.05
        wire(component.poll(clock.t))


def test_a_command_whose_handler_fails_is_still_answered_once(rig, monkeypatch):
    """As the autopilot's command table (commands.py) does: a bug in a handler is counted as an
    internal error and the command still gets its one COMMAND_ACK (FAILED), not silence; what the
    handler had queued before it failed is not sent."""
    from firefly.autopilot.mavlink import camera_component

    def broken(component, c, replies):
        replies.append(component.heartbeat())
        raise ZeroDivisionError("a bug")

    failures = []
    _, _, component = rig
    component.on_failure = lambda where, exc: failures.append(where)
    monkeypatch.setitem(camera_component.COMMANDS, mav.MAV_CMD_IMAGE_START_CAPTURE, broken)
    got = ask(component, mav.MAV_CMD_IMAGE_START_CAPTURE, 0, 0, 1)
    assert [(m.get_type(), m.command, m.result) for m in got] == [
        ("COMMAND_ACK", mav.MAV_CMD_IMAGE_START_CAPTURE, mav.MAV_RESULT_FAILED)]
    assert failures == [f"camera command {mav.MAV_CMD_IMAGE_START_CAPTURE}"]
    assert component.counters["refused"] == 1


@pytest.mark.internal_errors  # the bug planted is one
def test_the_session_counts_a_camera_handler_bug_as_its_own(tmp_path, monkeypatch):
    from firefly.autopilot.mavlink import camera_component

    def broken(component, c, replies):
        raise ZeroDivisionError("a bug")

    v, session = camv2_vehicle(tmp_path)
    monkeypatch.setitem(camera_component.COMMANDS, mav.MAV_CMD_SET_CAMERA_MODE, broken)
    got = wire(session.receive(long(mav.MAV_CMD_SET_CAMERA_MODE, 0, 0), v.time_s))
    assert [(m.get_type(), m.result) for m in got] == [("COMMAND_ACK", mav.MAV_RESULT_FAILED)]
    assert session.counters["handler_errors"] == 1 and "ZeroDivisionError" in session.last_handler_error
