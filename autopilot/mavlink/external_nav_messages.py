"""A companion's navigation messages, as GCS_MAVLINK hands them to AP_VisualOdom and the EKF: the
poses (VISION_POSITION_ESTIMATE and the messages with its fields, ATT_POS_MOCAP, ODOMETRY), the
speed (VISION_SPEED_ESTIMATE), SET_GPS_GLOBAL_ORIGIN, and a GPS of its own (GPS_INPUT). What the
vehicle does with them is autopilot/external_nav.py's; here they are only read.
"""
from __future__ import annotations

from .dialect import mavlink as mav


def _pose(session, m) -> None:
    session.vehicle.vision_pose((m.x, m.y, m.z), 0, getattr(m, "reset_counter", 0))


def _odometry(session, m) -> None:
    # ArduPilot takes only a local FRD pose of the body FRD frame; any other pair is dropped
    if m.frame_id != mav.MAV_FRAME_LOCAL_FRD or m.child_frame_id != mav.MAV_FRAME_BODY_FRD:
        return
    session.vehicle.vision_speed()  # first: the EKF starting on this pose has its velocity too
    session.vehicle.vision_pose((m.x, m.y, m.z), m.quality, m.reset_counter)


def origin_taken(session) -> None:
    """An origin taken is told, as ArduCopter tells it: GPS_GLOBAL_ORIGIN, then the home it sets at
    once (the message and MAV_CMD_DO_SET_GLOBAL_ORIGIN alike)."""
    session.queue(session.build(mav.MAVLINK_MSG_ID_GPS_GLOBAL_ORIGIN))
    session.queue(session.build(mav.MAVLINK_MSG_ID_HOME_POSITION))


def _origin(session, m) -> None:
    """Taken only while the EKF has no origin (a later one, or one with a bad position, is dropped
    in silence)."""
    if session.vehicle.set_gps_global_origin(m.latitude * 1e-7, m.longitude * 1e-7, m.altitude * 1e-3):
        origin_taken(session)


def _gps_input(session, m) -> None:
    # velocities the companion says it left out are zero, as AP_GPS_MAV takes them
    ignored = m.ignore_flags
    vel = tuple(0.0 if ignored & flag else v for v, flag in ((m.vn, mav.GPS_INPUT_IGNORE_FLAG_VEL_HORIZ),
                                                                (m.ve, mav.GPS_INPUT_IGNORE_FLAG_VEL_HORIZ),
                                                                (m.vd, mav.GPS_INPUT_IGNORE_FLAG_VEL_VERT)))
    session.vehicle.gps_input(m.gps_id, m.fix_type, m.lat * 1e-7, m.lon * 1e-7, m.alt, vel, m.satellites_visible)


# message name -> handler(session, message)
EXTERNAL_NAV_HANDLERS = {
    "VISION_POSITION_ESTIMATE": _pose,
    "GLOBAL_VISION_POSITION_ESTIMATE": _pose,
    "VICON_POSITION_ESTIMATE": _pose,
    "ATT_POS_MOCAP": _pose,
    "ODOMETRY": _odometry,
    "VISION_SPEED_ESTIMATE": lambda session, m: session.vehicle.vision_speed(),
    "SET_GPS_GLOBAL_ORIGIN": _origin,
    "GPS_INPUT": _gps_input,
}
