"""Hostile MAVLink messages of every kind the vehicle handles, drawn from any `random.Random`.

The state-space walk (state_machine.py) draws from a seeded `random.Random` in its long run and
from hypothesis' `st.randoms()` in the property test, so both send the same kinds of messages and
hypothesis can still shrink them. Values are what a fuzzer or a half-written ground station sends:
NaN, +-inf, 1e30, float32 extremes and random bit patterns, integer extremes, any frame 0..255,
command ids from the vehicle's table and any u16, mission items of any command (DO_JUMP with NaN,
fence vertices and circles 5001-5004, rally points 5100), FTP requests with any header.

`known_reproductions` are the single messages reported to break the vehicle in some state; the
walk sends them in every state it reaches.
"""
from __future__ import annotations

import math
import struct

from firefly.autopilot.mavlink.commands import HANDLERS
from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.modes import MODE_BY_NUMBER
from firefly.autopilot.params import PARAM_TABLE

SYSTEM_ID = 1
NAN, INF = math.nan, math.inf
SPECIAL = (0.0, -0.0, 1.0, -1.0, 2989.0, 21196.0, 4.0, 9.0, 1e30, -1e30, 3.4e38, -3.4e38, 1e-30, 3e6, -3e6,
           1e7, 2.5, 255.0, 65535.0, NAN, NAN, INF, -INF)
I32 = (0, 1, -1, 2**31 - 1, -2**31, -353632610, 1491652300, 900_000_000, -900_000_000, 1_800_000_000)
MODES = tuple(sorted(MODE_BY_NUMBER))
COMMANDS = tuple(sorted(HANDLERS)) + (
    mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_CMD_NAV_LOITER_UNLIM, mav.MAV_CMD_DO_JUMP, mav.MAV_CMD_DO_LAND_START,
    mav.MAV_CMD_DO_SET_ROI, mav.MAV_CMD_DO_FENCE_ENABLE, mav.MAV_CMD_PREFLIGHT_CALIBRATION,
    mav.MAV_CMD_PREFLIGHT_REBOOT_SHUTDOWN, 5001, 5002, 5003, 5004, 5100, 0, 65535)
MISSION_COMMANDS = (16, 16, 16, 17, 18, 19, 20, 21, 22, 82, 84, 85, 112, 115, 177, 177, 177, 178, 179, 189, 201,
                    93, 0, 65535)
FENCE_COMMANDS = (5000, 5001, 5001, 5002, 5003, 5004)
PARAM_NAMES = [s.name for s in PARAM_TABLE] + ["", "X" * 16, "SYSID_THISMAV", "FENCE_ENABLE"]
GCS_TYPES = (mav.MAV_TYPE_GCS,) * 4 + (0, 2, 13, 27, 255)
FTP_OPCODES = tuple(range(0, 16)) + (128, 129, 200)
FTP_PATHS = (b"@PARAM/param.pck", b"@PARAM/param.pck?withdefaults=1", b"/", b"", b"@SYS/threads.txt",
             b"x" * 239)


# ----- values ---------------------------------------------------------------------------------------
def f32(r) -> float:
    """A float a float32 field carries: special values, small integers, any value, any bit pattern."""
    x = r.random()
    if x < 0.4:
        return r.choice(SPECIAL)
    if x < 0.6:
        return float(r.randint(-1000, 1000))
    if x < 0.85:
        return r.uniform(-1e5, 1e5)
    return struct.unpack("<f", struct.pack("<I", r.getrandbits(32)))[0]


def i32(r) -> int:
    return r.choice(I32) if r.random() < 0.4 else r.randint(-2**31, 2**31 - 1)


def u8(r) -> int:
    return r.choice((0, 1, 255)) if r.random() < 0.3 else r.randint(0, 255)


def u16(r) -> int:
    return r.choice((0, 1, 65535)) if r.random() < 0.3 else r.randint(0, 65535)


def i16(r) -> int:
    return r.choice((0, -32768, 32767, 1000, -1000)) if r.random() < 0.4 else r.randint(-32768, 32767)


def frame(r) -> int:
    return r.choice((0, 1, 3, 5, 6, 8, 10, 11)) if r.random() < 0.7 else u8(r)


def target(r) -> int:
    """Mostly this vehicle or broadcast; sometimes another system."""
    return r.choice((SYSTEM_ID, SYSTEM_ID, SYSTEM_ID, SYSTEM_ID, 0, 0, 2, 255))


def command_id(r) -> int:
    return r.choice(COMMANDS) if r.random() < 0.85 else u16(r)


def mission_type(r) -> int:
    return r.choice((0, 0, 1, 2)) if r.random() < 0.9 else r.choice((3, 255, u8(r)))


def param_f(r, sane: float, p_hostile: float = 0.3) -> float:
    """`sane`, or with probability p_hostile any float32."""
    return f32(r) if r.random() < p_hostile else sane


def near(origin, r, radius_m: float) -> tuple[int, int]:
    """A latitude/longitude (1e-7 degrees) within radius_m of origin."""
    dn, de = r.uniform(-radius_m, radius_m), r.uniform(-radius_m, radius_m)
    lat = origin.lat_deg + dn / 111_320.0
    lon = origin.lon_deg + de / (111_320.0 * math.cos(math.radians(origin.lat_deg)))
    return int(round(lat * 1e7)), int(round(lon * 1e7))


# ----- FTP ------------------------------------------------------------------------------------------
def ftp_payload(seq: int, session: int, opcode: int, size: int = 0, offset: int = 0, data: bytes = b"",
                req_opcode: int = 0, burst_complete: int = 0) -> list:
    header = struct.pack("<HBBBBBxI", seq & 0xFFFF, session & 0xFF, opcode & 0xFF, size & 0xFF, req_opcode & 0xFF,
                         burst_complete & 0xFF, offset & 0xFFFFFFFF)
    return list((header + data)[:251].ljust(251, b"\0"))


def hostile_ftp(c, r):
    if r.random() < 0.15:
        payload = [r.getrandbits(8) for _ in range(251)]
    else:
        path = r.choice(FTP_PATHS)
        data = path if r.random() < 0.7 else bytes(r.getrandbits(8) for _ in range(r.randint(0, 239)))
        size = len(data) if r.random() < 0.7 else u8(r)
        offset = r.choice((0, 0, 239, 4096, 2**32 - 1)) if r.random() < 0.8 else r.getrandbits(32)
        payload = ftp_payload(u16(r), r.choice((0, 0, 1, 2, 255)), r.choice(FTP_OPCODES), size, offset, data)
    return c.file_transfer_protocol_encode(0, target(r), r.choice((0, 1)), payload)


# ----- messages -------------------------------------------------------------------------------------
def command_long(c, r, command=None):
    return c.command_long_encode(target(r), 1, command_id(r) if command is None else command, u8(r),
                                 *(f32(r) for _ in range(7)))


def command_int(c, r, command=None):
    return c.command_int_encode(target(r), 1, frame(r), command_id(r) if command is None else command, 0, 0,
                                *(f32(r) for _ in range(4)), i32(r), i32(r), f32(r))


def mission_item_int(c, r, seq=None, kind=None):
    """Any mission item: any command, frame and value; `seq`/`kind` when an upload awaits one."""
    kind = mission_type(r) if kind is None else kind
    command = r.choice(FENCE_COMMANDS if kind == 1 else (5100,) if kind == 2 else MISSION_COMMANDS) \
        if r.random() < 0.8 else command_id(r)
    return c.mission_item_int_encode(target(r), 1, u16(r) if seq is None else seq, frame(r), command, u8(r) % 3,
                                     u8(r) % 2, *(f32(r) for _ in range(4)), i32(r), i32(r), f32(r), kind)


def mission_item(c, r, seq=None, kind=None):
    kind = mission_type(r) if kind is None else kind
    return c.mission_item_encode(target(r), 1, u16(r) if seq is None else seq, frame(r),
                                 r.choice(MISSION_COMMANDS + FENCE_COMMANDS + (5100,)), 0, 1,
                                 *(f32(r) for _ in range(7)), kind)


def hostile_message(c, r, awaiting=None):
    """One hostile message of any kind the session handles (and a few it does not). `awaiting`:
    {mission_type: next seq} of uploads in progress, so items can land inside a transfer."""
    kind = r.randrange(32)
    if kind < 6:
        return command_long(c, r)
    if kind < 9:
        return command_int(c, r)
    if kind == 9:
        return c.set_mode_encode(target(r), u8(r), r.choice(MODES) if r.random() < 0.8 else r.getrandbits(32))
    if kind == 10:
        return c.set_position_target_local_ned_encode(0, target(r), 1, frame(r), u16(r), *(f32(r) for _ in range(11)))
    if kind == 11:
        return c.set_position_target_global_int_encode(0, target(r), 1, frame(r), u16(r), i32(r), i32(r),
                                                       *(f32(r) for _ in range(9)))
    if kind == 12:
        name = r.choice(PARAM_NAMES).encode() if r.random() < 0.9 else bytes(r.getrandbits(8) for _ in range(16))
        return c.param_set_encode(target(r), 1, name, f32(r), r.randint(0, 10))
    if kind == 13:
        return c.param_request_read_encode(target(r), 1, r.choice(PARAM_NAMES).encode(), i16(r))
    if kind == 14:
        return c.param_request_list_encode(target(r), 1)
    if kind == 15:
        return c.mission_count_encode(target(r), 1, r.choice((0, 1, 2, 3, 5, 12, 201, 701, 702)) if r.random() < 0.8
                                      else u16(r), mission_type(r))
    if kind in (16, 17):
        if awaiting and r.random() < 0.7:
            k = r.choice(sorted(awaiting))
            return mission_item_int(c, r, awaiting[k], k)
        return mission_item_int(c, r)
    if kind == 18:
        if awaiting and r.random() < 0.7:
            k = r.choice(sorted(awaiting))
            return mission_item(c, r, awaiting[k], k)
        return mission_item(c, r)
    if kind == 19:
        build = r.choice((c.mission_request_int_encode, c.mission_request_encode))
        return build(target(r), 1, r.choice((0, 1, 2, 65535)) if r.random() < 0.5 else u16(r), mission_type(r))
    if kind == 20:
        return c.mission_request_list_encode(target(r), 1, mission_type(r))
    if kind == 21:
        return c.mission_clear_all_encode(target(r), 1, mission_type(r))
    if kind == 22:
        return c.mission_set_current_encode(target(r), 1, r.choice((0, 1, 2, 3, 65535)) if r.random() < 0.7 else u16(r))
    if kind == 23:
        return c.manual_control_encode(target(r), i16(r), i16(r), i16(r), i16(r), u16(r))
    if kind == 24:
        return c.rc_channels_override_encode(target(r), 1, *(r.choice((0, 65535, 1000, 1500, 2000, 799, 2201))
                                                            if r.random() < 0.6 else u16(r) for _ in range(8)))
    if kind == 25:
        return c.request_data_stream_encode(target(r), 1, u8(r) % 13 if r.random() < 0.8 else u8(r), u16(r), u8(r) % 2)
    if kind == 26:
        mode = r.choice(MODES) if r.random() < 0.7 else r.getrandbits(32)
        return c.heartbeat_encode(r.choice(GCS_TYPES), 8, u8(r), mode, 4)
    if kind == 27:
        return c.timesync_encode(r.choice((0, 0, 1, -1, 2**63 - 1, -2**63)), r.randint(-2**63, 2**63 - 1))
    if kind in (28, 29):
        return hostile_ftp(c, r)
    if kind == 30:
        if r.random() < 0.1:  # a key: what the vehicle sends from then on is signed
            key = bytes(r.getrandbits(8) for _ in range(32)) if r.random() < 0.5 else bytes(32)
            return c.setup_signing_encode(target(r), 1, key, r.getrandbits(64))
        return c.system_time_encode(r.getrandbits(64), 0)  # not handled
    if r.random() < 0.7:  # the dataflash log's download, in any state (armed, mid-flight, mid-transfer)
        return r.choice((
            lambda: c.log_request_list_encode(target(r), 1, u16(r) if r.random() < 0.3 else 0,
                                              u16(r) if r.random() < 0.5 else 0xFFFF),
            lambda: c.log_request_data_encode(target(r), 1, r.choice((0, 1, 2, u16(r))),
                                              r.getrandbits(32) if r.random() < 0.3 else 90 * u8(r),
                                              r.getrandbits(32) if r.random() < 0.3 else 90 * r.randint(0, 20)),
            lambda: c.log_erase_encode(target(r), 1),
            lambda: c.log_request_end_encode(target(r), 1)))()
    return c.named_value_float_encode(0, b"GND_TEMP", f32(r))  # not for the vehicle


def known_reproductions(c, origin) -> list:
    """Single messages reported to kill the vehicle in some state (before home, mostly)."""
    lat, lon = int(round(origin.lat_deg * 1e7)), int(round(origin.lon_deg * 1e7))
    return [
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_DO_SET_MODE, 0, 1, 9, 0, 0, 0, 0, 0),  # LAND
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_DO_SET_MODE, 0, 1, 3, 0, 0, 0, 0, 0),  # AUTO
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_DO_SET_MODE, 0, 1, 6, 0, 0, 0, 0, 0),  # RTL
        c.set_mode_encode(SYSTEM_ID, 1, 9),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_NAV_LAND, 0, 0, 0, 0, 0, 0, 0, 0),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0, 0, 0, 0, 0, 0),
        c.command_int_encode(SYSTEM_ID, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, mav.MAV_CMD_DO_REPOSITION, 0, 0,
                             -1, mav.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, NAN, lat, lon, 10),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_DO_SET_HOME, 0, 0, 0, 0, 0,
                              origin.lat_deg, origin.lon_deg, 3e6),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_DO_SET_HOME, 0, 0, 0, 0, 0,
                              origin.lat_deg, origin.lon_deg, -3e6),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_MISSION_START, 0, 0, 0, 0, 0, 0, 0, 0),
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 3e6),
        c.set_position_target_global_int_encode(0, SYSTEM_ID, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000,
                                                lat, lon, 3e6, 0, 0, 0, 0, 0, 0, 0, 0),
        # found by the walk: an answer whose message id does not fit MESSAGE_INTERVAL's u16 ...
        c.command_long_encode(SYSTEM_ID, 1, mav.MAV_CMD_GET_MESSAGE_INTERVAL, 0, 3e6, 0, 0, 0, 0, 0, 0),
        # ... and a yaw of 1000 rad held as is, which NAV_CONTROLLER_OUTPUT (EXTRA stream) cannot carry
        c.request_data_stream_encode(SYSTEM_ID, 1, mav.MAV_DATA_STREAM_ALL, 4, 1),
        c.set_position_target_local_ned_encode(0, SYSTEM_ID, 1, mav.MAV_FRAME_BODY_OFFSET_NED, 0b100111111000,
                                               0, 0, 0, 0, 0, 0, 0, 0, 0, 1000.0, 0),
    ]
