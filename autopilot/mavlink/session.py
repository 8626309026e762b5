"""One vehicle's MAVLink session, sans-IO.

`receive(msg, now_s, link_s, link)` consumes one decoded message from link `link` (an opaque key
the I/O edge gives) and returns the messages that answer it, which go to that link only, as
ArduCopter answers the channel that asked; `poll(now_s)` returns what is due for every link
(heartbeat, telemetry streams, status texts). What a transfer sends later (the parameter list's
stream, a mission upload's retries) goes to the link that started it: `take_directed()`; a
parameter's new value goes to every other link that has spoken too: `take_announced()`. The link layer
(link.py) packs them and the I/O edge sends them; this class never touches a socket or a wall clock.
"""
from __future__ import annotations

from functools import partial

from .. import version
from . import terrain
from ..results import Result
from .adsb_messages import collision, forwarded, report_of
from .adsb_out import AdsbOut
from .commands import Command, CommandService
from .dialect import mavlink as mav
from .fast_pack import FastCodec
from .external_nav_messages import EXTERNAL_NAV_HANDLERS
from .mount_commands import MESSAGE_HANDLERS as MOUNT_MESSAGE_HANDLERS
from .ftp import FtpServer
from .follow_messages import on_follow_target, on_global_position_int
from .guided_setpoints import handle_attitude_target, handle_global_int, handle_local_ned
from .guided_waypoint import guided_request
from . import device_ops, rc_input
from .legacy_points import LegacyPoints
from .log_service import LogService
from .mission_service import MissionService
from .params_service import ParamService
from .signing import LinkSigning
from .statustext import StatusTexts
from .streams import StreamScheduler
from .telemetry import BUILDERS

FOLLOW_FEEDS = {"GLOBAL_POSITION_INT": on_global_position_int, "FOLLOW_TARGET": on_follow_target}
GCS_SYSID_ENFORCE = 1 << 0  # MAV_OPTIONS: hear only the ground station (and the vehicle's own system)


class Session:
    def __init__(self, vehicle, codec):
        self.vehicle = vehicle
        self.codec = codec
        self.texts = StatusTexts(codec)  # STATUSTEXT, long texts in chunks
        self.telemetry_codec = FastCodec(codec)  # what the telemetry builders encode with
        self.signing = LinkSigning(codec)  # off until a key is set; the link layer admits frames
        self.system_id = codec.srcSystem
        self.streams = StreamScheduler(vehicle.params)
        vehicle.params.on_change(self.streams.param_changed)
        self.params = ParamService(vehicle.params, codec)
        self.commands = CommandService()
        self.missions = MissionService(vehicle.mission, vehicle, codec)
        self.adsb_out = AdsbOut()  # a uAvionix transponder's configuration and channel
        self._transceiver_seq = 0  # the next frame number of SITL's ADS-B transceiver (component 156)
        self._mode_changes_told = vehicle.mode_changes  # mode changes a HEARTBEAT has told
        self._channels: dict = {}  # link -> its channel number, in the order transceivers reported on them
        self.legacy_points = LegacyPoints(vehicle.mission, vehicle.params, codec)  # older GCSs' fence and rally
        self.ftp = FtpServer(vehicle.params, vehicle.notify)
        self.logs = LogService(vehicle, codec)  # the I/O edge gives it the log files (logs.store)
        self.link_s = 0.0  # link clock (wall time from the I/O layer) for transfer retries
        self._stores_waiting = vehicle.stores_waiting  # the vehicle's files with a write waiting
        self._out: list = []
        self._link = None  # the link of the message being handled
        self._params_link = self._missions_link = self._logs_link = None  # the links the transfers answer
        self._directed: dict = {}  # link -> what poll made for it alone
        self._announced: list = []  # (link, message) for every other link that has spoken (a new value)
        self.counters = {"received": 0, "ignored_other_system": 0, "bad_data": 0, "refused": 0,
                         "handler_errors": 0, "ignored_not_gcs": 0}
        self.last_handler_error = ""
        self.gcs_last_heartbeat_s: float | None = None
        # Vehicle time before which this session neither hears nor says anything: a rebooted
        # vehicle's boot (autopilot/io/reboot.py); 0 at a first start.
        self.silent_until_s = 0.0
        self.accel_calibrated_s = 0.0  # vehicle time of the last level or accelerometer calibration (preflight.py)
        # The thermal camera's own component (camera_component.py), when the scenario fits one:
        # what is addressed to its component id is its, not the autopilot's
        self.camera_component = None
        self._handlers = {
            "HEARTBEAT": self._on_heartbeat,
            "COMMAND_LONG": lambda m, now: self._on_command(Command.from_long(m), now),
            "COMMAND_INT": lambda m, now: self._on_command(Command.from_int(m), now),
            "SET_MODE": self._on_set_mode,
            "PARAM_REQUEST_LIST": self._on_param_request_list,
            "PARAM_REQUEST_READ": lambda m, now: self._out.extend(self.params.request_read(m)),
            "PARAM_SET": self._on_param_set,
            "REQUEST_DATA_STREAM": self._on_request_data_stream,
            "FILE_TRANSFER_PROTOCOL": self._on_ftp,
            "LOG_REQUEST_LIST": self._on_log_request,
            "LOG_REQUEST_DATA": self._on_log_request,
            "LOG_ERASE": self._on_log_request,
            "LOG_REQUEST_END": self._on_log_request,
            "MISSION_REQUEST_LIST": lambda m, now: self._out.extend(self.missions.on_request_list(m)),
            "MISSION_COUNT": self._on_mission_count,
            "MISSION_WRITE_PARTIAL_LIST": self._on_mission_write_partial,
            "MISSION_ITEM_INT": self._on_mission_item,
            "MISSION_ITEM": self._on_mission_item,
            "MISSION_REQUEST_INT": lambda m, now: self._out.extend(self.missions.on_request(m)),
            "MISSION_REQUEST": lambda m, now: self._out.extend(self.missions.on_request(m)),
            "MISSION_CLEAR_ALL": lambda m, now: self._out.extend(self.missions.on_clear_all(m)),
            "MISSION_SET_CURRENT": lambda m, now: self._out.extend(self.missions.on_set_current(m)),
            "DEVICE_OP_READ": lambda m, now: self.queue(device_ops.read_reply(self.codec, m)),
            "DEVICE_OP_WRITE": lambda m, now: self.queue(device_ops.write_reply(self.codec, m)),
            "ADSB_VEHICLE": lambda m, now: self.vehicle.adsb_vehicle(report_of(m)),
            "LANDING_TARGET": lambda m, now: self.vehicle.landing_target(
                m.frame, m.angle_x, m.angle_y, m.distance, (m.x, m.y, m.z), m.position_valid == 1),
            "TERRAIN_DATA": lambda m, now: terrain.on_terrain_data(self.vehicle, m),
            "TERRAIN_CHECK": lambda m, now: self.queue(terrain.terrain_check_reply(self.vehicle, self.telemetry_codec, m)),
            "UAVIONIX_ADSB_OUT_CFG": self._on_adsb_config,
            "UAVIONIX_ADSB_TRANSCEIVER_HEALTH_REPORT": self._on_adsb_health,
            "FENCE_POINT": self._on_legacy_point,
            "FENCE_FETCH_POINT": self._on_legacy_point,
            "RALLY_POINT": self._on_legacy_point,
            "RALLY_FETCH_POINT": self._on_legacy_point,
            "MANUAL_CONTROL": self._on_manual_control,
            "RC_CHANNELS_OVERRIDE": self._on_rc_override,
            "SET_POSITION_TARGET_LOCAL_NED": self._on_setpoint_local,
            "SET_POSITION_TARGET_GLOBAL_INT": self._on_setpoint_global,
            "SET_ATTITUDE_TARGET": lambda m, now: handle_attitude_target(self.vehicle, m),
            "TIMESYNC": self._on_timesync,
            "DISTANCE_SENSOR": lambda m, now: self.vehicle.distance_sensor(
                m.orientation, m.current_distance, m.min_distance, m.max_distance, m.type, m.signal_quality),
            "OBSTACLE_DISTANCE": lambda m, now: self.vehicle.obstacle_distance(
                m.distances, m.increment_f or m.increment, m.angle_offset, m.min_distance, m.max_distance),
            "OBSTACLE_DISTANCE_3D": lambda m, now: self.vehicle.obstacle_distance_3d(
                m.time_boot_ms, m.frame, (m.x, m.y, m.z), m.min_distance, m.max_distance),
            "SETUP_SIGNING": lambda m, now: self.signing.setup(m, self.vehicle.armed),
            # The request older ground stations send before REQUEST_MESSAGE existed.
            "AUTOPILOT_VERSION_REQUEST": lambda m, now: self.queue(self.build(mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION)),
        }
        # a companion's poses and the EKF origin; a gimbal manager's attitudes
        for name, handle in {**EXTERNAL_NAV_HANDLERS, **MOUNT_MESSAGE_HANDLERS}.items():
            self._handlers[name] = partial(_with_session, handle, self)

    # ----- output helpers used by the services ------------------------------------------------
    def queue(self, msg) -> None:
        """A message, or the list a builder made (DISTANCE_SENSOR: one per sensor and sector)."""
        if type(msg) is list:
            self._out.extend(msg)
        elif msg is not None:
            self._out.append(msg)

    def build(self, msg_id: int):
        """The message `msg_id` as the vehicle's state makes it now, or None if not built here; a
        list where one id is several messages (DISTANCE_SENSOR). A builder that fails (a bug) is an
        internal error: that message is not sent, the rest are."""
        builder = BUILDERS.get(msg_id)
        if builder is None:
            return None
        try:
            return builder(self.vehicle, self.telemetry_codec)
        except Exception as exc:  # noqa: BLE001 - telemetry must never stop the loop
            self.handler_failed(f"telemetry {msg_id}", exc)
            return None

    def _take(self) -> list:
        out, self._out = self._out, []
        return out

    # ----- input ------------------------------------------------------------------------------
    def _for_me(self, msg) -> bool:
        # MANUAL_CONTROL names its field `target`; every other addressed message `target_system`.
        target = getattr(msg, "target_system", getattr(msg, "target", 0))
        return target in (0, self.system_id)

    def _accepted_sender(self, msg) -> bool:
        """MAV_OPTIONS bit 0 (GCS_SYSID_ENFORCE): as ArduPilot's accept_packet, only the vehicle's
        own system, the ground station's (MAV_GCS_SYSID) and radio status are heard; the rest is
        dropped unanswered (measured: no COMMAND_ACK, no PARAM_VALUE). Routing is not affected."""
        params = self.vehicle.params
        if not int(params["MAV_OPTIONS"]) & GCS_SYSID_ENFORCE:
            return True
        sender = msg.get_srcSystem()
        return (sender in (self.system_id, int(params["MAV_GCS_SYSID"]))
                or msg.get_type() in ("RADIO", "RADIO_STATUS"))

    def receive(self, msg, now_s: float, link_s: float | None = None, link=None) -> list:
        if now_s < self.silent_until_s:  # still booting: what was sent meanwhile is lost
            return []
        self._link = link
        if msg.get_type() == "BAD_DATA":
            self.counters["bad_data"] += 1
            return []
        self.counters["received"] += 1
        self.link_s = now_s if link_s is None else link_s
        if not self._for_me(msg):
            self.counters["ignored_other_system"] += 1
            return []
        camera = self.camera_component
        if camera is not None and getattr(msg, "target_component", None) == camera.COMPONENT:
            try:
                return camera.receive(msg, self.link_s)
            except Exception as exc:  # noqa: BLE001 - a bug must not stop the vehicle loop
                self.handler_failed(f"camera {msg.get_type()}", exc)
                return []
        follow_feed = FOLLOW_FEEDS.get(msg.get_type())
        if follow_feed is not None:  # another system's position: FOLLOW's lead, whoever sends it, heard
            try:                     # before MAV_OPTIONS' enforcement, as ArduPilot's AP_Follow is
                follow_feed(self.vehicle, msg, now_s)
            except Exception as exc:  # noqa: BLE001 - a bug must not stop the vehicle loop
                self.handler_failed(msg.get_type(), exc)
            return self._take()
        if not self._accepted_sender(msg):
            self.counters["ignored_not_gcs"] += 1
            return []
        handler = self._handlers.get(msg.get_type())
        if handler is not None:
            try:
                handler(msg, now_s)
            except Exception as exc:  # noqa: BLE001 - a bug must not stop the vehicle loop
                self.handler_failed(msg.get_type(), exc)
        return self._take()

    def overhear(self, msg, system_id: int, now_s: float) -> None:
        """A message another vehicle of this process sent (io/shared_air.py), from `system_id`:
        taken only as the vehicle takes any system's position (FOLLOW's lead); no answer."""
        if now_s < self.silent_until_s or not self.vehicle.hears_positions():
            return
        try:
            on_global_position_int(self.vehicle, msg, now_s, system_id)
        except Exception as exc:  # noqa: BLE001 - a bug must not stop the vehicle loop
            self.handler_failed("overheard GLOBAL_POSITION_INT", exc)

    def handler_failed(self, where: str, exc: BaseException) -> None:
        """A bug in a message handler: counted and kept for the exit report (the tests require zero
        of these), and an internal error of the vehicle, reported as ArduPilot reports one."""
        self.counters["handler_errors"] += 1
        self.last_handler_error = f"{where}: {type(exc).__name__}: {exc}"
        self.vehicle.internal_error(exc, where, in_flight_code=False)

    def _on_heartbeat(self, msg, now_s):
        if msg.type == mav.MAV_TYPE_GCS:
            self._ground_station_seen()

    def _ground_station_seen(self) -> None:
        """The ground station is there (ArduPilot's sysid_mygcs_seen): its heartbeat, and also the
        pilot input it sends (MANUAL_CONTROL, RC_CHANNELS_OVERRIDE), hold off the GCS failsafe."""
        self.gcs_last_heartbeat_s = self.link_s
        self.vehicle.failsafes.gcs_regained(self.vehicle)

    def _on_param_request_list(self, msg, now_s):
        self._params_link = self._link
        self.send_banner()  # as ArduPilot: "a convenient way to get extra information"
        self._out.extend(self.params.request_list(msg, self.link_s))

    def _on_param_set(self, msg, now_s):
        # ArduCopter sends a parameter's new value to every active channel, not the setter alone
        answer = self.params.set(msg, self.vehicle.notify)
        self._out.extend(answer)
        self._announced.extend((self._link, m) for m in answer)

    def _on_mission_count(self, msg, now_s):
        self._missions_link = self._link
        self._out.extend(self.missions.on_count(msg, self.link_s))

    def _on_adsb_config(self, msg, now_s):
        severity, text = self.adsb_out.on_config(msg)
        self.vehicle.notify(text, severity)

    def _on_adsb_health(self, msg, now_s):
        said = self.adsb_out.on_health(msg, self._channels.setdefault(self._link, len(self._channels)))
        if said is not None:
            self.vehicle.notify(said[1], said[0])

    def _on_legacy_point(self, msg, now_s):
        texts, replies = self.legacy_points.handle(msg, self._link)
        for severity, text in texts:  # to the asking link only, as ArduPilot's link.send_text
            self._out.extend(self.texts.encode(severity, text))
        self._out.extend(replies)

    def _on_mission_write_partial(self, msg, now_s):
        self._missions_link = self._link
        self._out.extend(self.missions.on_write_partial(msg, self.link_s))

    def _on_log_request(self, msg, now_s):
        # as ArduPilot's _log_sending_link: the rest of a transfer goes to the link that began it
        idle = not self.logs.activity
        self._out.extend(self.logs.handle(msg))
        if idle and self.logs.activity:
            self._logs_link = self._link

    def take_directed(self) -> dict | None:
        """{link: messages} that poll made for one link alone; None (most ticks) if none."""
        directed = self._directed
        if not directed:
            return None
        self._directed = {}
        return directed

    def take_announced(self) -> list | None:
        """(link it answered, message) for every other link that has spoken; None (most ticks).
        A parameter set several times since the last call is announced once, with its last value
        (and to its last setter's the other links): a flood of sets from many links costs one
        message per link, not one per set and link."""
        announced = self._announced
        if not announced:
            return None
        self._announced = []
        if len(announced) == 1:
            return announced
        return list({m.param_id: (asker, m) for asker, m in announced}.values())

    def _on_command(self, c: Command, now_s):
        ack = self.commands.handle(self, c, now_s, self.link_s)
        if ack.result != Result.ACCEPTED:
            self.counters["refused"] += 1
        self._out.append(ack)

    def set_mode(self, base_mode: int, custom_mode: int) -> Result:
        if not base_mode & mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED:
            return Result.UNSUPPORTED
        return self.vehicle.set_mode(custom_mode)

    def _on_set_mode(self, msg, now_s):
        # As ArduCopter 4.7 (measured): the SET_MODE message changes the mode and is not answered
        # (earlier ArduPilots sent a COMMAND_ACK for "command 11"); the HEARTBEAT tells.
        if self.set_mode(msg.base_mode, msg.custom_mode) != Result.ACCEPTED:
            self.counters["refused"] += 1

    def _on_request_data_stream(self, msg, now_s):
        self.streams.set_group_rate(msg.req_stream_id, msg.req_message_rate, bool(msg.start_stop))

    def _on_ftp(self, msg, now_s):
        # Like ArduPilot, any target_component is served (no component behind us to route to).
        sender = (msg.get_srcSystem(), msg.get_srcComponent())
        for reply in self.ftp.handle(msg.payload, sender, self.link_s):
            self._out.append(self.codec.file_transfer_protocol_encode(0, *sender, reply.encode()))
        if self.ftp.banner_due:
            self.ftp.banner_due = False
            self.send_banner()

    def send_banner(self) -> None:
        """The banner texts (autopilot/version.py), in answer to the link that asked (as
        ArduPilot sends them on the channel that asked)."""
        for severity, text in version.banner(self.vehicle.board_id, self.vehicle.params):
            self._out.extend(self.texts.encode(severity, text))

    def _on_manual_control(self, msg, now_s):
        if rc_input.manual_control(self.vehicle, msg, now_s):
            self._ground_station_seen()
        else:
            self.counters["ignored_not_gcs"] += 1

    def _on_rc_override(self, msg, now_s):
        if rc_input.rc_channels_override(self.vehicle, msg, now_s):
            self._ground_station_seen()
        else:
            self.counters["ignored_not_gcs"] += 1

    def _on_mission_item(self, msg, now_s):
        result = guided_request(self.vehicle, msg)
        if result is None:  # an upload's item
            self._out.extend(self.missions.on_item(msg, self.link_s))
        else:
            self._out.append(self.codec.mission_ack_encode(msg.get_srcSystem(), msg.get_srcComponent(), result,
                                                           mav.MAV_MISSION_TYPE_MISSION))

    def _on_setpoint_local(self, msg, now_s):
        if not handle_local_ned(self.vehicle, msg):
            self.counters["refused"] += 1

    def _on_setpoint_global(self, msg, now_s):
        if not handle_global_int(self.vehicle, msg):
            self.counters["refused"] += 1

    def _on_timesync(self, msg, now_s):
        if msg.tc1 == 0:
            self._out.append(self.codec.timesync_encode(int(now_s * 1e9), msg.ts1))

    # ----- output -----------------------------------------------------------------------------
    def _direct(self, link, messages: list) -> None:
        if messages:  # a transfer started by a message from no link in particular: everyone's
            (self._out if link is None else self._directed.setdefault(link, [])).extend(messages)

    def idle(self, now_s: float, link_s: float) -> bool:
        """Whether poll(now_s, link_s) would send nothing and change nothing: no stream due yet,
        no transfer, no status text or reached item waiting, no GCS silent for too long."""
        last = self.gcs_last_heartbeat_s
        return (now_s + 1e-9 < self.streams.next_due_s and not self.vehicle.events
                and not self.missions.uploads and not self.params.streaming and not self._stores_waiting
                and not self.vehicle.mission_progress.has_reached and not self.vehicle.camera.feedback_due
                and not self.logs.activity
                and (self.camera_component is None or not self.camera_component.due(now_s))
                and (last is None or link_s - last <= self.vehicle.params["FS_GCS_TIMEOUT"]))

    def poll(self, now_s: float, link_s: float | None = None) -> list:
        if now_s < self.silent_until_s:
            return []
        link_s = self.link_s = now_s if link_s is None else link_s
        out, vehicle = self._out, self.vehicle
        if self.missions.uploads:
            self._direct(self._missions_link, self.missions.poll(link_s))
        if self.params.streaming:
            self._direct(self._params_link, self.params.poll(link_s))
        if self.logs.activity:
            self._direct(self._logs_link, self.logs.poll())
        if self._stores_waiting:
            vehicle.poll_stores(link_s)
        if vehicle.params.vehicle_saved:  # values the vehicle saved itself (AUTOTUNE): to every link
            saved, vehicle.params.vehicle_saved = vehicle.params.vehicle_saved, []
            self._announced.extend((None, self.params.value_message(name)) for name in saved if name in vehicle.params)
        last = self.gcs_last_heartbeat_s
        if last is not None and link_s - last > vehicle.params["FS_GCS_TIMEOUT"]:
            vehicle.failsafes.gcs_lost(vehicle)
        reached = vehicle.mission_progress.drain_reached()
        if reached:  # ArduPilot keeps one pending MISSION_ITEM_REACHED: items reached together
            # (a waypoint and the "do" item verified in the same step) report the last one only
            out.append(self.codec.mission_item_reached_encode(reached[-1]))
        camera = vehicle.camera
        if camera.feedback_due:  # a picture taken: its CAMERA_FEEDBACK to every link
            camera.feedback_due = False
            feedback = self.build(mav.MAVLINK_MSG_ID_CAMERA_FEEDBACK)
            if feedback is not None:
                out.append(feedback)
        if vehicle.adsb_forwards_due:  # SITL's traffic with no ADS-B receiver set: forwarded as it came
            due, vehicle.adsb_forwards_due = vehicle.adsb_forwards_due, []
            out.extend(forwarded(self.telemetry_codec, due, self._transceiver_seq))
            self._transceiver_seq = (self._transceiver_seq + len(due)) & 0xFF
        if vehicle.collisions_due:  # ADS-B avoidance's reports: to every link
            due, vehicle.collisions_due = vehicle.collisions_due, []
            out.extend(collision(self.telemetry_codec, c) for c in due)
        due = self.streams.due(now_s)
        if vehicle.mode_changes != self._mode_changes_told:
            # As ArduCopter: a mode change sends a HEARTBEAT at once (one, if one is due anyway)
            self._mode_changes_told = vehicle.mode_changes
            if mav.MAVLINK_MSG_ID_HEARTBEAT not in due:
                due = [mav.MAVLINK_MSG_ID_HEARTBEAT, *due]
        for msg_id in due:  # heartbeat first, then the rest; most ticks none
            msg = self.build(msg_id)
            if type(msg) is list:
                out.extend(msg)
            elif msg is not None:
                out.append(msg)
        if self.camera_component is not None:  # its heartbeat and the stills taken: to every link
            try:
                out.extend(self.camera_component.poll(now_s))
            except Exception as exc:  # noqa: BLE001 - a bug must not stop the vehicle loop
                self.handler_failed("camera poll", exc)
        if vehicle.events:
            for severity, text in vehicle.drain_events():
                out.extend(self.texts.encode(severity, text))
        if not out:
            return []
        self._out = []
        return out


def _with_session(handle, session, msg, now) -> None:
    """A table handler (external_nav_messages.py, mount_commands.py) in the session's (message,
    now) shape."""
    handle(session, msg)
