"""Where Firefly's parameters knowingly differ from the reference ArduCopter's (one place; the
parity suite reads it).

OLD_NAMES: ArduPilot 4.5's name -> the reference's (4.7's) name of the same parameter. Firefly
models the reference's; the old name, which scenarios and scripts written for 4.5 still set, is
known in-process (it shares the value) but not served over MAVLink, as the reference does not
serve it; values saved under it are taken up, as ArduPilot converts old storage.

DEFAULT_DIFFERENCES: a parameter the reference serves whose Firefly default is not the
reference's, and why. The reference's defaults are those of SITL's `--model quad` with copter.parm.

FIREFLY_ONLY: parameters Firefly serves that the reference does not, and why they exist.

IN_PROCESS_ONLY: modelled names known to scenarios, scripts, the Python API and older saved files
but not served over MAVLink (the reference does not serve them: a ground station sees exactly its
parameter set, plus FIREFLY_ONLY), and why they are kept.

SEMANTIC_DIFFERENCES: served under the reference's name, but meaning something else in Firefly.
"""
from __future__ import annotations

OLD_NAMES: dict[str, str] = {
    "SYSID_THISMAV": "MAV_SYSID",
    "SR0_RAW_SENS": "MAV1_RAW_SENS",
    "SR0_EXT_STAT": "MAV1_EXT_STAT",
    "SR0_POSITION": "MAV1_POSITION",
    "SR0_EXTRA1": "MAV1_EXTRA1",
    "SR0_EXTRA2": "MAV1_EXTRA2",
    "SR0_EXTRA3": "MAV1_EXTRA3",
    "SR0_RC_CHAN": "MAV1_RC_CHAN",
    "FS_BATT_ENABLE": "BATT_FS_LOW_ACT",
    "SIM_GPS_NUMSATS": "SIM_GPS1_NUMSATS",
    "SIM_GPS_GLITCH_X": "SIM_GPS1_GLTCH_X",
    "SIM_GPS_GLITCH_Y": "SIM_GPS1_GLTCH_Y",
    "SIM_GPS_GLITCH_Z": "SIM_GPS1_GLTCH_Z",
}

_AIRFRAME = "tuned for Firefly's airframe (sim/airframe.py: 1.5 kg, 10-inch props), not SITL's quad model"
_STREAMS = ("Firefly streams telemetry unasked, as ArduPilot SITL 4.5 did (SR0_*); the reference "
            "streams nothing until a ground station asks")

DEFAULT_DIFFERENCES: dict[str, str] = {
    "PSC_VELXY_D": _AIRFRAME,
    "PSC_VELZ_I": _AIRFRAME,
    "ATC_RAT_YAW_P": "this airframe's yaw reaction torque is small (c = d/b = 2.4 cm): the reference's "
                     "0.3 gives a yaw-rate loop slower than the angle loop",
    "ATC_RAT_YAW_I": "scaled with ATC_RAT_YAW_P",
    "MOT_THST_HOVER": "copter.parm's 0.39 is SITL's quad; Firefly's airframe hovers near 0.35",
    "BATT_CAPACITY": "Firefly's airframe carries a 5000 mAh 3S pack",
    "FENCE_RADIUS": "ArduPilot's own default; copter.parm lowers it to 150 m for its autotests",
    "SIM_WIND_DIR": "set from the scenario's [wind] at start; moot while SIM_WIND_SPD is 0",
    "MAV1_RAW_SENS": _STREAMS,
    "MAV1_EXT_STAT": _STREAMS,
    "MAV1_POSITION": _STREAMS,
    "MAV1_EXTRA1": _STREAMS,
    "MAV1_EXTRA2": _STREAMS,
    "MAV1_EXTRA3": _STREAMS,
}

FIREFLY_ONLY: dict[str, str] = {
    **{name: "external navigation's (AP_VisualOdom): ArduCopter serves it once VISO_TYPE is set (the "
             "reference's set was recorded with VISO_TYPE 0); Firefly serves it always, so that it can be "
             "set before enabling"
       for name in ("VISO_SCALE", "VISO_QUAL_MIN", "VISO_POS_X", "VISO_POS_Y", "VISO_POS_Z", "VISO_ORIENT",
                    "VISO_DELAY_MS", "VISO_VEL_M_NSE", "VISO_POS_M_NSE", "VISO_YAW_M_NSE")},
    "SIM_LINK_DOWN": "Firefly's own link fault: the ground-station link cut for some wall seconds",
    "SIM_LINK_LOSS": "Firefly's own link fault: a share of MAVLink frames lost each way",
    **{name: "FOLLOW's lead (AP_Follow): ArduCopter serves it once FOLL_ENABLE is 1 (the reference's set "
             "was recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("FOLL_SYSID", "FOLL_DIST_MAX", "FOLL_OFS_TYPE", "FOLL_OFS_X", "FOLL_OFS_Y", "FOLL_OFS_Z",
                    "FOLL_YAW_BEHAVE", "FOLL_POS_P", "FOLL_ALT_TYPE", "FOLL_OPTIONS", "FOLL_ACCEL_NE",
                    "FOLL_JERK_NE", "FOLL_ACCEL_D", "FOLL_JERK_D", "FOLL_ACCEL_H", "FOLL_JERK_H")},
    **{name: "the camera's (AP_Camera): ArduCopter serves it once CAM1_TYPE is set and the vehicle rebooted "
             "(the reference's set was recorded with CAM1_TYPE 0); Firefly serves it always, so that it can "
             "be set before the camera is"
       for name in ("CAM1_DURATION", "CAM1_SERVO_ON", "CAM1_SERVO_OFF", "CAM1_TRIGG_DIST", "CAM1_RELAY_ON",
                    "CAM1_INTRVAL_MIN", "CAM1_FEEDBAK_PIN", "CAM1_FEEDBAK_POL", "CAM1_OPTIONS", "CAM1_MNT_INST",
                    "CAM1_HFOV", "CAM1_VFOV")},
    **{name: "the rangefinder's (AP_RangeFinder): ArduCopter serves it once RNGFND1_TYPE is set and the vehicle "
             "rebooted (the reference's set was recorded with RNGFND1_TYPE 0); Firefly serves it always, so that "
             "it can be set before the rangefinder is"
       for name in ("RNGFND1_PIN", "RNGFND1_SCALING", "RNGFND1_OFFSET", "RNGFND1_FUNCTION", "RNGFND1_MIN",
                    "RNGFND1_MAX", "RNGFND1_STOP_PIN", "RNGFND1_RMETRIC", "RNGFND1_PWRRNG", "RNGFND1_GNDCLR",
                    "RNGFND1_ADDR", "RNGFND1_POS_X", "RNGFND1_POS_Y", "RNGFND1_POS_Z", "RNGFND1_ORIENT")},
    **{name: "the optical flow sensor's (AP_OpticalFlow): ArduCopter serves it once FLOW_TYPE is set (the "
             "reference's set was recorded with FLOW_TYPE 0); Firefly serves it always, so that it can be set "
             "before the sensor is"
       for name in ("FLOW_FXSCALER", "FLOW_FYSCALER", "FLOW_ORIENT_YAW", "FLOW_POS_X", "FLOW_POS_Y", "FLOW_POS_Z",
                    "FLOW_ADDR")},
    **{name: "ADS-B's (AP_ADSB, AP_Avoidance): ArduCopter serves it once ADSB_TYPE / AVD_ENABLE is set (the "
             "reference's set was recorded with both 0); Firefly serves it always, so that it can be set before "
             "enabling"
       for name in ("ADSB_LIST_MAX", "ADSB_LIST_RADIUS", "ADSB_ICAO_ID", "ADSB_EMIT_TYPE", "ADSB_LEN_WIDTH",
                    "ADSB_OFFSET_LAT", "ADSB_OFFSET_LON", "ADSB_RF_SELECT", "ADSB_SQUAWK", "ADSB_RF_CAPABLE",
                    "ADSB_LIST_ALT", "ADSB_ICAO_SPECL", "ADSB_LOG", "ADSB_OPTIONS", "AVD_F_ACTION", "AVD_W_ACTION",
                    "AVD_F_RCVRY", "AVD_OBS_MAX", "AVD_W_TIME", "AVD_F_TIME", "AVD_W_DIST_XY", "AVD_F_DIST_XY",
                    "AVD_W_DIST_Z", "AVD_F_DIST_Z", "AVD_F_ALT_MIN")},
    **{name: "the path planner's (AP_OAPathPlanner): ArduCopter serves it once OA_TYPE is set (the reference's "
             "set was recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("OA_MARGIN_MAX", "OA_OPTIONS", "OA_DB_SIZE", "OA_DB_EXPIRE", "OA_DB_QUEUE_SIZE",
                    "OA_DB_OUTPUT", "OA_DB_BEAM_WIDTH", "OA_DB_RADIUS_MIN", "OA_DB_DIST_MAX", "OA_DB_ALT_MIN",
                    "OA_BR_LOOKAHEAD", "OA_BR_CONT_RATIO", "OA_BR_CONT_ANGLE", "OA_BR_TYPE")},
    **{name: "precision landing's (AC_PrecLand): ArduCopter serves it once PLND_ENABLED is set (the reference's "
             "set was recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("PLND_TYPE", "PLND_YAW_ALIGN", "PLND_LAND_OFS_X", "PLND_LAND_OFS_Y", "PLND_EST_TYPE",
                    "PLND_ACC_P_NSE", "PLND_CAM_POS_X", "PLND_CAM_POS_Y", "PLND_CAM_POS_Z", "PLND_BUS", "PLND_LAG",
                    "PLND_XY_DIST_MAX", "PLND_STRICT", "PLND_RET_MAX", "PLND_TIMEOUT", "PLND_RET_BEHAVE",
                    "PLND_ALT_MIN", "PLND_ALT_MAX", "PLND_OPTIONS")},
    **{name: "the parachute's (AP_Parachute): ArduCopter serves it once CHUTE_ENABLED is set (the reference's set "
             "was recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("CHUTE_TYPE", "CHUTE_SERVO_ON", "CHUTE_SERVO_OFF", "CHUTE_ALT_MIN", "CHUTE_DELAY_MS",
                    "CHUTE_CRT_SINK", "CHUTE_OPTIONS")},
    **{name: "the sprayer's (AC_Sprayer): ArduCopter serves it once SPRAY_ENABLE is set (the reference's set was "
             "recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("SPRAY_PUMP_RATE", "SPRAY_SPINNER", "SPRAY_SPEED_MIN", "SPRAY_PUMP_MIN")},
    **{name: "the gripper's (AP_Gripper): ArduCopter serves it once GRIP_ENABLE is set (the reference's set was "
             "recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("GRIP_TYPE", "GRIP_GRAB", "GRIP_RELEASE", "GRIP_NEUTRAL", "GRIP_REGRAB", "GRIP_CAN_ID",
                    "GRIP_AUTOCLOSE")},
    **{name: "the winch's (AP_Winch): ArduCopter serves it once WINCH_TYPE is set (the reference's set was "
             "recorded with it 0); Firefly serves it always, so that it can be set before enabling"
       for name in ("WINCH_RATE_MAX", "WINCH_POS_P", "WINCH_OPTIONS")},
    **{name: "the camera mount's (AP_Mount): ArduCopter serves it once MNT1_TYPE is set and the vehicle rebooted "
             "(the reference's set was recorded with MNT1_TYPE 0); Firefly serves it always, so that it can be "
             "set before the mount is"
       for name in ("MNT1_DEFLT_MODE", "MNT1_RC_RATE", "MNT1_ROLL_MIN", "MNT1_ROLL_MAX", "MNT1_PITCH_MIN",
                    "MNT1_PITCH_MAX", "MNT1_YAW_MIN", "MNT1_YAW_MAX", "MNT1_RETRACT_X", "MNT1_RETRACT_Y",
                    "MNT1_RETRACT_Z", "MNT1_NEUTRAL_X", "MNT1_NEUTRAL_Y", "MNT1_NEUTRAL_Z", "MNT1_LEAD_RLL",
                    "MNT1_LEAD_PTCH", "MNT1_SYSID_DFLT", "MNT1_DEVID", "MNT1_OPTIONS")},
}

_OLD_NAME = "ArduPilot 4.5's name of {}, which scenarios and scripts written for 4.5 set"
IN_PROCESS_ONLY: dict[str, str] = {
    **{old: _OLD_NAME.format(new) for old, new in OLD_NAMES.items()},
    "SIM_GPS_DISABLE": "ArduPilot 4.5's inverse of SIM_GPS1_ENABLE (both act), which scenarios written for 4.5 set",
}

SEMANTIC_DIFFERENCES: dict[str, str] = {
}
