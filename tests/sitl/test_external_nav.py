"""External navigation against the real autopilot process: no GPS (GPS1_TYPE 0), a companion
played by a pymavlink script sending VISION_POSITION_ESTIMATE from the simulator's truth
(SIMSTATE), the EKF origin given by SET_GPS_GLOBAL_ORIGIN: LOITER arms once there is an origin, and
GUIDED holds its point by the pose, its error and a jump included."""
from __future__ import annotations

import math

import pytest
from pymavlink import mavutil

from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink
LOITER, GUIDED = 5, 4
M_PER_DEG = 1.0e7 * 0.011131884502145034  # ArduPilot's LOCATION_SCALING_FACTOR, per degree
BOOT = ("--param", "GPS1_TYPE=0", "--param", "VISO_TYPE=1", "--param", "EK3_SRC1_POSXY=6",
        "--param", "EK3_SRC1_VELXY=6", "--param", "EK3_SRC1_VELZ=6")


class Companion:
    """Sends the vehicle's true position (SIMSTATE), as metres north and east of where it booted,
    as its pose: a motion-capture system, plus an error it is told to have."""

    def __init__(self, gcs: Gcs):
        self.gcs = gcs
        self.link = mav.MAVLink(gcs.conn, srcSystem=1, srcComponent=197)  # a companion's visual odometry
        assert gcs.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SIMSTATE, 50_000) == 0  # 20 Hz
        self.first = gcs.recv("SIMSTATE", 5)
        assert self.first is not None, "no SIMSTATE to play the companion from"
        self.error_ne = (0.0, 0.0)
        self.last: dict = {}
        self.texts: list[str] = []

    def truth_ne(self, s) -> tuple[float, float]:
        lat0 = self.first.lat / 1e7
        return ((s.lat - self.first.lat) / 1e7 * M_PER_DEG,
                (s.lng - self.first.lng) / 1e7 * M_PER_DEG * math.cos(math.radians(lat0)))

    def speak_until(self, done, timeout: float, speaking: bool = True):
        """Answer every SIMSTATE with a pose until done(self) or `timeout` wall seconds; returns
        done's value."""
        def step(msg):
            self.last[msg.get_type()] = msg
            if msg.get_type() == "STATUSTEXT":
                self.texts.append(msg.text)
            if msg.get_type() == "SIMSTATE" and speaking:
                n, e = self.truth_ne(msg)
                self.link.vision_position_estimate_send(msg.get_header().seq * 1000, n + self.error_ne[0],
                                                        e + self.error_ne[1], 0.0, 0.0, 0.0, 0.0)
            return done(self)
        found = self.gcs.recv(["SIMSTATE", "LOCAL_POSITION_NED", "GLOBAL_POSITION_INT", "STATUSTEXT",
                               "HEARTBEAT", "GPS_RAW_INT", "HOME_POSITION", "GPS_GLOBAL_ORIGIN", "COMMAND_ACK"],
                              timeout, step)
        return found is not None

    def command(self, command: int, *params) -> int:
        """A ground station's COMMAND_LONG while the companion goes on speaking: its result."""
        self.last.pop("COMMAND_ACK", None)
        self.gcs.mav.command_long_send(1, 1, command, 0, *params, *[0.0] * (7 - len(params)))
        assert self.speak_until(lambda c: "COMMAND_ACK" in c.last and c.last["COMMAND_ACK"].command == command, 5), \
            f"no COMMAND_ACK for {command}"
        return self.last["COMMAND_ACK"].result


def test_a_companion_pose_flies_without_a_gps(autopilot_factory):
    ap = autopilot_factory(extra=BOOT)
    gcs = Gcs(ap.pymavlink_url)
    try:
        companion = Companion(gcs)
        gps = gcs.recv("GPS_RAW_INT", 5)
        assert gps.fix_type == 0 and gps.satellites_visible == 0  # GPS_FIX_TYPE_NO_GPS: no receiver

        # The pose is used at once, but there is no origin: no location, and no arming in LOITER
        assert companion.speak_until(lambda c: "EKF3 IMU0 is using external nav data" in c.texts, 10)
        assert companion.speak_until(lambda c: "GLOBAL_POSITION_INT" in c.last, 5)
        assert companion.last["GLOBAL_POSITION_INT"].lat == 0 and companion.last["GLOBAL_POSITION_INT"].lon == 0
        assert companion.command(mav.MAV_CMD_DO_SET_MODE, 1, LOITER) == mav.MAV_RESULT_ACCEPTED
        assert companion.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_FAILED

        # SET_GPS_GLOBAL_ORIGIN: the origin and home at once, where the companion says
        lat, lon = companion.first.lat, companion.first.lng
        gcs.mav.set_gps_global_origin_send(1, lat, lon, 100_000)
        assert companion.speak_until(lambda c: "HOME_POSITION" in c.last and "GPS_GLOBAL_ORIGIN" in c.last, 5)
        origin = companion.last["GPS_GLOBAL_ORIGIN"]
        assert (origin.latitude, origin.longitude, origin.altitude) == (lat, lon, 100_000)
        assert abs(companion.last["HOME_POSITION"].latitude - lat) <= 2

        # LOITER arms now (two vehicle seconds on: the same ARM sooner is answered as a retry of
        # the first); GUIDED takes off and holds where the pose says it is
        assert companion.speak_until(lambda c: "LOCAL_POSITION_NED" in c.last, 5)
        t0 = companion.last["LOCAL_POSITION_NED"].time_boot_ms
        assert companion.speak_until(lambda c: c.last["LOCAL_POSITION_NED"].time_boot_ms > t0 + 2_000, 5)
        assert companion.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED, companion.texts
        assert companion.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        assert companion.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10) == mav.MAV_RESULT_ACCEPTED
        assert companion.speak_until(lambda c: "GLOBAL_POSITION_INT" in c.last
                                     and c.last["GLOBAL_POSITION_INT"].relative_alt > 9500, 30)

        # The pose drifts to 0.8 m north of the truth (within EKF3's gate): the vehicle believes it
        # holds its point, and is truly 0.8 m south of it
        companion.error_ne = (0.8, 0.0)
        t0 = companion.last["LOCAL_POSITION_NED"].time_boot_ms
        assert companion.speak_until(lambda c: c.last["LOCAL_POSITION_NED"].time_boot_ms > t0 + 10_000, 30)
        local = companion.last["LOCAL_POSITION_NED"]
        true_n, true_e = companion.truth_ne(companion.last["SIMSTATE"])
        assert abs(local.x) < 0.3 and abs(local.y) < 0.3, (local.x, local.y)
        assert abs(true_n + 0.8) < 0.3 and abs(true_e) < 0.3, (true_n, true_e)

        # A 5 m jump is held off (the vehicle stays) until EKF3 gives in about 4.3 s later (a
        # companion sending no velocity: ArduCopter 4.5 s): the estimate takes it, and the vehicle
        # flies to where the pose says its point is, 5.8 m south
        companion.error_ne = (5.8, 0.0)
        t0, said_before = companion.last["LOCAL_POSITION_NED"].time_boot_ms, len(companion.texts)
        assert companion.speak_until(lambda c: c.last["LOCAL_POSITION_NED"].time_boot_ms > t0 + 3_000, 30)
        assert abs(companion.last["LOCAL_POSITION_NED"].x) < 0.3
        assert companion.speak_until(lambda c: c.last["LOCAL_POSITION_NED"].x > 2.5, 30)
        taken_s = (companion.last["LOCAL_POSITION_NED"].time_boot_ms - t0) / 1000.0
        assert 3.8 <= taken_s <= 5.0, taken_s
        assert companion.speak_until(lambda c: c.last["LOCAL_POSITION_NED"].time_boot_ms > t0 + 15_000, 30)
        true_n, _ = companion.truth_ne(companion.last["SIMSTATE"])
        assert abs(true_n + 5.8) < 0.5, true_n
        assert companion.last["HEARTBEAT"].custom_mode == GUIDED and not any("EKF" in t for t in companion.texts[said_before:])
    finally:
        gcs.close()
