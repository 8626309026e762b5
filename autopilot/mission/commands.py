"""Mission command numbers (MAV_CMD) and what AP_Mission calls them in its "Mission: 2 WP" texts."""
from __future__ import annotations

CMD_WAYPOINT, CMD_LOITER_UNLIM, CMD_LOITER_TIME, CMD_RTL, CMD_LAND, CMD_TAKEOFF = 16, 17, 19, 20, 21, 22
CMD_DO_JUMP, CMD_DO_CHANGE_SPEED, CMD_DO_SET_HOME = 177, 178, 179
CMD_JUMP_TAG, CMD_DO_JUMP_TAG = 600, 601
NAV_LAST = 95  # MAV_CMD_NAV_LAST: every command numbered up to it is a navigation command
NAV_EXCEPTIONS = {213, 42702, 42703}  # NAV_SET_YAW_SPEED, NAV_SCRIPT_TIME, NAV_ATTITUDE_TIME
TAKEOFF_COMMANDS = {CMD_TAKEOFF, 84, 24}  # NAV_TAKEOFF, NAV_VTOL_TAKEOFF, NAV_TAKEOFF_LOCAL

CMD_DO_SET_SERVO, CMD_DO_REPEAT_SERVO, CMD_DO_SET_RELAY, CMD_DO_REPEAT_RELAY = 183, 184, 181, 182
CMD_DO_SET_RESUME_REPEAT_DIST = 215

# The "do" commands AP_Mission runs itself (servos, relays, cameras, payloads, tags): done as soon
# as they start, with no MISSION_ITEM_REACHED and no "Skipping invalid cmd" (measured: a mission
# with DO_SET_SERVO between two waypoints reports reached 1, 2, 4).
RUN_BY_MISSION = frozenset({
    211, 183, 181, 184, 182,  # DO_GRIPPER, DO_SET_SERVO, DO_SET_RELAY, DO_REPEAT_SERVO, DO_REPEAT_RELAY
    202, 203, 206,  # DO_DIGICAM_CONFIGURE, DO_DIGICAM_CONTROL, DO_SET_CAM_TRIGG_DIST
    208, 217, 216, 218, 215,  # DO_PARACHUTE, DO_SEND_SCRIPT_MESSAGE, DO_SPRAYER, DO_AUX_FUNCTION, DO_SET_RESUME_REPEAT_DIST
    1000, 600,  # DO_GIMBAL_MANAGER_PITCHYAW, JUMP_TAG
    2000, 2001, 531, 532, 534, 2500, 2501,  # image capture, camera zoom / focus / source, video
})
# The "do" commands ArduCopter's AUTO itself takes: done at once and reported reached (with the
# waypoint before, when in the same step: one MISSION_ITEM_REACHED, the later), never "invalid".
COPTER_DO = frozenset({
    CMD_DO_CHANGE_SPEED, CMD_DO_SET_HOME, 195, 197, 201,  # DO_SET_ROI_LOCATION, DO_SET_ROI_NONE, DO_SET_ROI
    205, 222, 207, 42600, 188, 189,  # DO_MOUNT_CONTROL, DO_GUIDED_LIMITS, DO_FENCE_ENABLE, DO_WINCH,
})                                   # DO_RETURN_PATH_START, DO_LAND_START

# The commands AP_Mission stores with a Location (AP_Mission::stored_in_location): only they keep
# their frame; a download gives any other MAV_FRAME_GLOBAL, whatever frame it was uploaded in
# (measured: an RTL uploaded in GLOBAL_RELATIVE_ALT comes back in frame 0).
STORED_IN_LOCATION = frozenset({
    16, 17, 18, 19, 21, 22, 30, 31, 82, 92,  # WAYPOINT, LOITERs, LAND, TAKEOFF, CHANGE_ALT, TO_ALT, SPLINE, GUIDED
    179, 188, 189, 191, 195, 201, 84, 85, 94,  # SET_HOME, RETURN_PATH/LAND_START, GO_AROUND, ROIs, VTOL, PAYLOAD
    5000, 5001, 5002, 5003, 5004, 5100,  # fence return point and vertices, rally point
})
FRAME_GLOBAL = 0

# A multicopter flies the VTOL takeoff and landing as the plain ones (ArduCopter's AUTO does).
FLOWN_AS = {84: CMD_TAKEOFF, 85: CMD_LAND}

NAMES = {
    16: "WP", 82: "SplineWP", 20: "RTL", 17: "LoitUnlim", 19: "LoitTime", 92: "GuidedEnable",
    18: "LoitTurns", 31: "LoitAltitude", 213: "SetYawSpd", 112: "CondDelay", 114: "CondDist",
    115: "CondYaw", 178: "ChangeSpeed", 179: "SetHome", 183: "SetServo", 181: "SetRelay",
    184: "RepeatServo", 182: "RepeatRelay", 202: "DigiCamCfg", 203: "DigiCamCtrl",
    206: "SetCamTrigDst", 195: "SetROILocation", 197: "SetROINone", 201: "SetROI",
    194: "SetReverse", 215: "SetRepeatDist", 222: "GuidedLimits", 22: "Takeoff", 21: "Land",
    30: "ContinueAndChangeAlt", 83: "AltitudeWait", 84: "VTOLTakeoff", 85: "VTOLLand",
    210: "InvertedFlight", 207: "FenceEnable", 212: "AutoTuneEnable", 3000: "VTOLTransition",
    223: "EngineControl", 188: "ReturnPathStart", 189: "LandStart", 93: "Delay", 211: "Gripper",
    94: "PayloadPlace", 208: "Parachute", 216: "Sprayer", 218: "AuxFunction",
    205: "MountControl", 42600: "Winch", 217: "Scripting", 177: "Jump", 601: "JumpToTag",
    600: "Tag", 191: "Go Around", 42702: "NavScriptTime", 42703: "NavAttitudeTime",
    193: "PauseContinue", 1000: "GimbalPitchYaw", 2000: "ImageStartCapture",
    2001: "ImageStopCapture", 531: "SetCameraZoom", 532: "SetCameraFocus", 534: "SetCameraSource",
    2500: "VideoStartCapture", 2501: "VideoStopCapture",
}


def is_nav(command: int) -> bool:
    return command <= NAV_LAST or command in NAV_EXCEPTIONS


def is_takeoff(command: int) -> bool:
    return command in TAKEOFF_COMMANDS


def downloaded_frame(command: int, frame: int) -> int:
    """The frame a mission download reports for an item stored as uploaded in `frame`."""
    return frame if command in STORED_IN_LOCATION else FRAME_GLOBAL


def command_name(command: int) -> str:
    return NAMES.get(command, "?")
