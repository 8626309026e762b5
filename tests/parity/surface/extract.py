"""Enumerate ArduCopter's user-reachable surface from its sources and write arducopter.json.

    python -m tests.parity.surface.extract [GIT_DIR_OR_TREE] [--out PATH]

The ArduPilot tree is read at ARDUPILOT_COMMIT (tests/parity/recording.py) through `git show`, so
either the bare mirror or a working tree of the same repository will do. What is counted:

* commands: the `case MAV_CMD_...:` labels of the two COMMAND_INT dispatchers a copter runs,
  GCS_MAVLINK_Copter::handle_command_int_packet and, behind its default, the common
  GCS_MAVLINK::handle_command_int_packet. COMMAND_LONG is converted to COMMAND_INT and handed to
  the same dispatcher (GCS_MAVLINK::try_command_long_as_command_int) except for a command that
  stores a location (command_long_stores_location) for which no frame is known
  (mav_frame_for_command_long): that one is refused over COMMAND_LONG and is "int" only.
* messages: the `case MAVLINK_MSG_ID_...:` labels of GCS_MAVLINK_Copter::handle_message and of
  GCS_MAVLINK::handle_message behind it, plus the messages looked at on the way in
  (GCS_MAVLINK::packetReceived, AP_Follow::handle_msg, AP_Avoidance::handle_msg).
* modes: every enumerator of Mode::Number in ArduCopter/mode.h, with whether
  Copter::mode_from_mode_num (ArduCopter/mode.cpp) builds it into the SITL binary.
* mission_commands: what a mission can run: ModeAuto::start_command's cases, the ones
  AP_Mission::start_command runs itself, and the jumps AP_Mission::get_next_cmd resolves.
* sim_parameters: the SIM_ parameter tree rooted at SIM::var_info (GOBJECT(sitl, "SIM_", ...)
  in ArduCopter/Parameters.cpp), following AP_SUBGROUPINFO / AP_SUBGROUPEXTENSION.

`#if` guards are evaluated with SITL_MACROS below: the value each guard macro has in the SITL
build of ArduCopter at this commit (taken with `g++ -dM -E` over that build's compile commands).
A case whose guard is false is left out of the lists and kept under "compiled_out" with the
guard. A guard naming a macro not in the table stops the script, so a new commit cannot be read
silently wrong.
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable

from pymavlink.dialects.v20 import ardupilotmega as mavlink

from ..recording import ARDUPILOT_COMMIT

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE / "arducopter.json"
SOURCE_CANDIDATES = (
    Path("/work/.mirror/blitzy-public-samples+ardupilot-blitzy/repo"),
    Path("/work/ref/ardupilot"),
)
GENERATED_BY = "python -m tests.parity.surface.extract"

# The value of every macro an `#if` in the files read here names, in ArduCopter's SITL build at
# ARDUPILOT_COMMIT (CONFIG_HAL_BOARD=HAL_BOARD_SITL, FRAME_CONFIG=MULTICOPTER_FRAME). None: not
# defined. Obtained by preprocessing each translation unit with its compile command from
# build/sitl/compile_commands.json and asking `#if NAME` of every name below.
SITL_MACROS: dict[str, int | None] = {
    "AC_MAVLINK_SOLO_BUTTON_COMMAND_HANDLING_ENABLED": 1,
    "AC_NAV_GUIDED": 1,
    "AC_PAYLOAD_PLACE_ENABLED": 1,
    "AC_POLYFENCE_FENCE_POINT_PROTOCOL_SUPPORT": 2,
    "AIRSPEED_MAX_SENSORS": 2,
    "AP_ADSB_AVOIDANCE_ENABLED": 1,
    "AP_AHRS_ENABLED": 1,
    "AP_AHRS_EXTERNAL_WIND_ESTIMATE_ENABLED": 1,
    "AP_AHRS_POSITION_RESET_ENABLED": 1,
    "AP_ARMING_ENABLED": 1,
    "AP_BATTERY_ENABLED": 1,
    "AP_BOOTLOADER_FLASHING_ENABLED": 0,
    "AP_CAMERA_ENABLED": 1,
    "AP_COMPASS_CALIBRATION_FIXED_YAW_ENABLED": 1,
    "AP_EFI_MAV_ENABLED": 1,
    "AP_FENCE_ENABLED": 2,
    "AP_FILESYSTEM_FORMAT_ENABLED": 1,
    "AP_FOLLOW_ENABLED": 1,
    "AP_GENERATOR_LOWEHEISER_ENABLED": 1,
    "AP_GPS_ENABLED": 1,
    "AP_GRIPPER_ENABLED": 1,
    "AP_HOME_ENABLED": 1,
    "AP_LANDINGGEAR_ENABLED": 1,
    "AP_MAVLINK_AUTOPILOT_VERSION_REQUEST_ENABLED": 1,
    "AP_MAVLINK_COMMAND_LONG_ENABLED": 1,
    "AP_MAVLINK_FOLLOW_HANDLING_ENABLED": 1,
    "AP_MAVLINK_FTP_ENABLED": 1,
    "AP_MAVLINK_MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES_ENABLED": 1,
    "AP_MAVLINK_MSG_DEVICE_OP_ENABLED": 1,
    "AP_MAVLINK_MSG_SERIAL_CONTROL_ENABLED": 1,
    "AP_MAVLINK_RALLY_POINT_PROTOCOL_ENABLED": 1,
    "AP_MAVLINK_SERVO_RELAY_ENABLED": 1,
    "AP_MAVLINK_SET_GPS_GLOBAL_ORIGIN_MESSAGE_ENABLED": 1,
    "AP_MISSION_ENABLED": 1,
    "AP_MISSION_NAV_PAYLOAD_PLACE_ENABLED": 1,
    "AP_NOTIFY_MAVLINK_LED_CONTROL_SUPPORT_ENABLED": 1,
    "AP_NOTIFY_MAVLINK_PLAY_TUNE_SUPPORT_ENABLED": 1,
    "AP_OPENDRONEID_ENABLED": 1,
    "AP_OPTICALFLOW_ENABLED": 1,
    "AP_RCPROTOCOL_ENABLED": 1,
    "AP_RCPROTOCOL_MAVLINK_RADIO_ENABLED": 1,
    "AP_RC_CHANNEL_ENABLED": 1,
    "AP_RTC_ENABLED": 1,
    "AP_SCRIPTING_ENABLED": 1,
    "AP_SERVORELAYEVENTS_ENABLED": 1,
    "AP_SIGNED_FIRMWARE": 0,
    "AP_SIM_AIS_ENABLED": 1,
    "AP_SIM_ENABLED": 1,
    "AP_SIM_FLIGHTAXIS_ENABLED": 1,
    "AP_SIM_GLIDER_ENABLED": 1,
    "AP_SIM_GPS_ENABLED": 1,
    "AP_SIM_INS_FILE_ENABLED": 1,
    "AP_SIM_MAX_GPS_SENSORS": 4,
    "AP_SIM_SHIP_ENABLED": 1,
    "AP_SIM_SLUNGPAYLOAD_ENABLED": 1,
    "AP_SIM_STRATOBLIMP_ENABLED": 1,
    "AP_SIM_TETHER_ENABLED": 1,
    "AP_SIM_VOLZ_ENABLED": 1,
    "AP_TERRAIN_AVAILABLE": 1,
    "AP_WINCH_ENABLED": 1,
    "AUTOTUNE_ENABLED": 1,
    "BARO_MAX_INSTANCES": 3,
    "COMPASS_CAL_ENABLED": 1,
    "HAL_ADSB_ENABLED": 1,
    "HAL_CANMANAGER_ENABLED": 1,
    "HAL_COMPASS_MAX_SENSORS": 3,
    "HAL_GCS_ENABLED": 1,
    "HAL_HIGH_LATENCY2_ENABLED": 1,
    "HAL_INS_ACCELCAL_ENABLED": 1,
    "HAL_INS_TEMPERATURE_CAL_ENABLE": 1,
    "HAL_LOGGING_ENABLED": 1,
    "HAL_MOUNT_ENABLED": 1,
    "HAL_NUM_CAN_IFACES": 2,
    "HAL_PARACHUTE_ENABLED": 1,
    "HAL_PROXIMITY_ENABLED": 1,
    "HAL_SPRAYER_ENABLED": 1,
    "HAL_VISUALODOM_ENABLED": 1,
    "INS_MAX_INSTANCES": 3,
    "MAX_CONNECTED_MAGS": 8,
    "MODE_ACRO_ENABLED": 1,
    "MODE_AUTOROTATE_ENABLED": 0,
    "MODE_AUTO_ENABLED": 1,
    "MODE_BRAKE_ENABLED": 1,
    "MODE_CIRCLE_ENABLED": 1,
    "MODE_DRIFT_ENABLED": 1,
    "MODE_FLIP_ENABLED": 1,
    "MODE_FLOWHOLD_ENABLED": 1,
    "MODE_FOLLOW_ENABLED": 1,
    "MODE_GUIDED_ENABLED": 1,
    "MODE_GUIDED_NOGPS_ENABLED": 1,
    "MODE_LOITER_ENABLED": 1,
    "MODE_POSHOLD_ENABLED": 1,
    "MODE_RTL_ENABLED": 1,
    "MODE_SMARTRTL_ENABLED": 1,
    "MODE_SPORT_ENABLED": 0,
    "MODE_SYSTEMID_ENABLED": 1,
    "MODE_THROW_ENABLED": 1,
    "MODE_TURTLE_ENABLED": 1,
    "MODE_ZIGZAG_ENABLED": 1,
    "OSD_PARAM_ENABLED": 1,
    "SFML_JOYSTICK": None,
    "TOY_MODE_ENABLED": 0,
    "WITH_SITL_OSD": None,
    "WITH_SITL_TONEALARM": None,
}


# ---------------------------------------------------------------------------------------------
# reading the tree


class Tree:
    """Files of an ArduPilot git repository (bare or not) at one commit."""

    def __init__(self, git_dir: Path, commit: str) -> None:
        self.git_dir = git_dir
        self.commit = commit
        self._cache: dict[str, str] = {}
        self._listing: dict[str, list[str]] = {}
        self._batch: subprocess.Popen[bytes] | None = None

    def _git(self, *args: str) -> str:
        done = subprocess.run(["git", "-C", str(self.git_dir), *args], capture_output=True,
                              text=True, check=True)
        return done.stdout

    def read(self, path: str) -> str:
        if path not in self._cache:
            if self._batch is None:  # one `git cat-file --batch` serves every read
                self._batch = subprocess.Popen(["git", "-C", str(self.git_dir), "cat-file", "--batch"],
                                               stdin=subprocess.PIPE, stdout=subprocess.PIPE)
            assert self._batch.stdin is not None and self._batch.stdout is not None
            self._batch.stdin.write(f"{self.commit}:{path}\n".encode())
            self._batch.stdin.flush()
            header = self._batch.stdout.readline().decode().split()
            if len(header) != 3 or header[1] != "blob":
                raise SystemExit(f"{path}: not in {self.git_dir} at {self.commit}")
            body = self._batch.stdout.read(int(header[2]) + 1)[:-1]
            self._cache[path] = body.decode("utf-8", errors="replace")
        return self._cache[path]

    def close(self) -> None:
        if self._batch is not None:
            assert self._batch.stdin is not None
            self._batch.stdin.close()
            self._batch.wait()
            self._batch = None

    def listdir(self, folder: str) -> list[str]:
        if folder not in self._listing:
            out = self._git("ls-tree", "--name-only", self.commit, folder.rstrip("/") + "/")
            self._listing[folder] = sorted(line for line in out.splitlines() if line)
        return self._listing[folder]

    def grep(self, pattern: str, pathspec: str) -> list[str]:
        done = subprocess.run(["git", "-C", str(self.git_dir), "grep", "-l", "-E", pattern,
                               self.commit, "--", pathspec], capture_output=True, text=True)
        prefix = f"{self.commit}:"
        return sorted(line[len(prefix):] for line in done.stdout.splitlines() if line)


# ---------------------------------------------------------------------------------------------
# comments, `#if` guards, function bodies

_STRIP = re.compile(r"//[^\n]*|/\*.*?\*/|\"(?:\\.|[^\"\\\n])*\"|'(?:\\.|[^'\\\n])*'", re.S)


def strip_comments(text: str, keep_strings: bool = False) -> str:
    """Blank out comments (keeping newlines) and, unless asked not to, string literals' text."""

    def blank(m: re.Match[str]) -> str:
        s = m.group(0)
        if s.startswith("/"):
            return re.sub(r"[^\n]", " ", s)
        if keep_strings:
            return s
        return s[0] + " " * (len(s) - 2) + s[-1]

    return _STRIP.sub(blank, text)


class UnknownMacro(Exception):
    pass


_DEFINED = re.compile(r"\bdefined\s*(?:\(\s*(\w+)\s*\)|(\w+))")
_BUILD_TYPE = re.compile(r"\bAPM_BUILD_TYPE\s*\(\s*(\w+)\s*\)")
BUILD_DIRECTORY = "APM_BUILD_ArduCopter"
_IDENT = re.compile(r"\b[A-Za-z_]\w*\b")
_NUMBER_SUFFIX = re.compile(r"\b(\d+)[uUlL]+\b")


def evaluate(expr: str, unknown: set[str]) -> bool:
    """Evaluate a preprocessor condition with SITL_MACROS; unknown names are collected."""

    def defined(m: re.Match[str]) -> str:
        name = m.group(1) or m.group(2)
        if name not in SITL_MACROS:
            unknown.add(name)
            return "0"
        return "1" if SITL_MACROS[name] is not None else "0"

    def ident(m: re.Match[str]) -> str:
        name = m.group(0)
        if name in ("and", "or", "not"):
            return name
        if name not in SITL_MACROS:
            unknown.add(name)
            return "0"
        value = SITL_MACROS[name]
        return str(value if value is not None else 0)

    # APM_BUILD_TYPE(t) is ((t) == APM_BUILD_DIRECTORY); this is the ArduCopter build
    py = _BUILD_TYPE.sub(lambda m: "1" if m.group(1) == BUILD_DIRECTORY else "0", expr)
    py = _DEFINED.sub(defined, py)
    py = _NUMBER_SUFFIX.sub(r"\1", py)
    py = py.replace("&&", " and ").replace("||", " or ")
    py = re.sub(r"!(?!=)", " not ", py)
    py = _IDENT.sub(ident, py)
    return bool(eval(py, {"__builtins__": {}}, {}))  # noqa: S307 - digits and operators only


class Line:
    """One line of a C++ file; `active` evaluates its guards only when asked, so SITL_MACROS
    needs just the macros guarding what is read."""

    def __init__(self, number: int, text: str, full: str, guards: tuple[str, ...],
                 unknown: set[str]) -> None:
        self.number = number  # 1-based
        self.text = text      # comments and string contents blanked
        self.full = full      # comments blanked, string literals kept
        self.guards = guards  # enclosing conditions, outermost first
        self._unknown = unknown

    @property
    def active(self) -> bool:
        """Compiled in the SITL build."""
        return all([evaluate(g, self._unknown) for g in self.guards])


def scan(text: str, unknown: set[str]) -> list[Line]:
    """Each line of a C++ file with the `#if` conditions around it."""
    raw = strip_comments(text).split("\n")
    kept = strip_comments(text, keep_strings=True).split("\n")
    lines: list[Line] = []
    # one frame per open #if: the conditions of its branches so far, and the current branch's
    stack: list[tuple[list[str], str]] = []
    i = 0
    while i < len(raw):
        number = i + 1
        line = raw[i]
        while line.rstrip().endswith("\\") and i + 1 < len(raw):  # continued directive
            i += 1
            line = line.rstrip()[:-1] + " " + raw[i]
        directive = re.match(r"\s*#\s*(if|ifdef|ifndef|elif|else|endif)\b(.*)", line)
        if directive:
            kind, rest = directive.group(1), directive.group(2).strip()
            if kind in ("if", "ifdef", "ifndef"):
                cond = {"if": rest, "ifdef": f"defined({rest})", "ifndef": f"!defined({rest})"}[kind]
                stack.append(([cond], cond))
            elif kind in ("elif", "else"):
                branches = stack[-1][0]
                negated = " && ".join(f"!({c})" for c in branches)
                current = f"{negated} && ({rest})" if kind == "elif" else negated
                stack[-1] = (branches + [rest] if kind == "elif" else branches, current)
            else:
                stack.pop()
        guards = tuple(frame[1] for frame in stack)
        lines.append(Line(number, line, kept[number - 1], guards, unknown))
        i += 1
    return lines


def closing(text: str, pos: int) -> int:
    """Offset of the bracket closing the one at text[pos] ('(' or '{')."""
    opening = text[pos]
    shut = {"(": ")", "{": "}"}[opening]
    depth = 0
    for at in range(pos, len(text)):
        if text[at] == opening:
            depth += 1
        elif text[at] == shut:
            depth -= 1
            if depth == 0:
                return at
    return len(text)


def function_spans(text: str, qualname: str) -> list[tuple[int, int]]:
    """1-based line ranges (first, last) of every definition of Class::function in a file."""
    clean = strip_comments(text)
    spans = []
    head = re.compile(r"^[A-Za-z_][^;{}()\n]*?\b" + re.escape(qualname) + r"\s*\(", re.M)
    for m in head.finditer(clean):
        # the body starts at the first '{' after the parameter list, unless a ';' comes first
        pos = closing(clean, m.end() - 1)
        brace = clean.find("{", pos)
        semicolon = clean.find(";", pos)
        if brace < 0 or (0 <= semicolon < brace):
            continue  # a declaration
        pos = closing(clean, brace)
        spans.append((clean.count("\n", 0, m.start()) + 1, clean.count("\n", 0, pos) + 1))
    return spans


@dataclass(frozen=True)
class Found:
    symbol: str
    source: str
    active: bool
    guards: tuple[str, ...]


class Reader:
    def __init__(self, tree: Tree) -> None:
        self.tree = tree
        self.unknown: set[str] = set()
        self._scanned: dict[str, list[Line]] = {}

    def lines(self, path: str) -> list[Line]:
        if path not in self._scanned:
            self._scanned[path] = scan(self.tree.read(path), self.unknown)
        return self._scanned[path]

    def in_function(self, path: str, qualname: str, pattern: str) -> list[Found]:
        """Every match of pattern's group 1 inside the definitions of qualname in path."""
        spans = function_spans(self.tree.read(path), qualname)
        if not spans:
            raise SystemExit(f"{path}: no definition of {qualname} found")
        lines = self.lines(path)
        found = []
        source = f"{path}:{qualname}"
        for first, last in spans:
            if not lines[first - 1].active:
                continue  # the other branch of an #if/#else pair of definitions
            for line in lines[first - 1:last]:
                for symbol in re.findall(pattern, line.text):
                    found.append(Found(symbol, source, line.active, line.guards))
        return found


CASE_CMD = r"\bcase\s+(MAV_CMD_\w+)\s*:"
CASE_MSG = r"\bcase\s+MAVLINK_MSG_ID_(\w+)\s*:"


# ---------------------------------------------------------------------------------------------
# resolving names with pymavlink's ardupilotmega dialect


XML_DIRS = ("modules/mavlink/message_definitions/v1.0",)
_xml_ids: dict[str, int] = {}
not_in_pymavlink: set[str] = set()


def _xml_id(name: str) -> int | None:
    """A MAV_CMD or message id from ArduPilot's own MAVLink XML (its modules/mavlink submodule,
    checked out in a working tree; a bare mirror has no submodules), for the few names
    pymavlink's dialect does not have yet."""
    if not _xml_ids:
        for root in SOURCE_CANDIDATES:
            for folder in XML_DIRS:
                for xml in sorted((root / folder).glob("*.xml")):
                    text = xml.read_text(errors="replace")
                    for m in re.finditer(r'<entry\s+value="(\d+)"\s+name="(MAV_CMD_\w+)"', text):
                        _xml_ids.setdefault(m.group(2), int(m.group(1)))
                    for m in re.finditer(r'<message\s+id="(\d+)"\s+name="(\w+)"', text):
                        _xml_ids.setdefault(f"MAVLINK_MSG_ID_{m.group(2)}", int(m.group(1)))
    return _xml_ids.get(name)


def command_id(name: str) -> int:
    value = getattr(mavlink, name, None)
    if isinstance(value, int) and value in mavlink.enums["MAV_CMD"]:
        return value
    fallback = _xml_id(name)
    if fallback is None:
        raise SystemExit(f"{name}: not a MAV_CMD of pymavlink's ardupilotmega dialect nor of "
                         f"ArduPilot's MAVLink XML")
    not_in_pymavlink.add(name)
    return fallback


def message_id(name: str) -> int:
    value = getattr(mavlink, f"MAVLINK_MSG_ID_{name}", None)
    if isinstance(value, int) and value in mavlink.mavlink_map:
        return value
    fallback = _xml_id(f"MAVLINK_MSG_ID_{name}")
    if fallback is None:
        raise SystemExit(f"{name}: not a message of pymavlink's ardupilotmega dialect nor of "
                         f"ArduPilot's MAVLink XML")
    not_in_pymavlink.add(name)
    return fallback


def _dedupe(found: Iterable[Found]) -> tuple[dict[str, Found], list[Found]]:
    """First active occurrence per symbol (dispatch order), and the compiled-out ones."""
    taken: dict[str, Found] = {}
    out: list[Found] = []
    for f in found:
        if f.active:
            taken.setdefault(f.symbol, f)
    for f in found:
        if not f.active and f.symbol not in taken and all(o.symbol != f.symbol for o in out):
            out.append(f)
    return taken, out


def _compiled_out(kind: str, found: list[Found], name_of: Any, id_of: Any) -> list[dict[str, Any]]:
    return [{"kind": kind, "name": name_of(f.symbol), "id": id_of(f.symbol), "source": f.source,
             "guard": " && ".join(f.guards)} for f in found]


# ---------------------------------------------------------------------------------------------
# the kinds

GCS_COMMON = "libraries/GCS_MAVLink/GCS_Common.cpp"
GCS_COPTER = "ArduCopter/GCS_MAVLink_Copter.cpp"


def extract_commands(r: Reader) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    found = (r.in_function(GCS_COPTER, "GCS_MAVLINK_Copter::handle_command_int_packet", CASE_CMD)
             + r.in_function(GCS_COMMON, "GCS_MAVLINK::handle_command_int_packet", CASE_CMD))
    taken, out = _dedupe(found)

    # COMMAND_LONG: converted and dispatched as COMMAND_INT, unless it carries a location whose
    # frame COMMAND_LONG cannot say and no assumed frame is known for it
    long_enabled = evaluate("AP_MAVLINK_COMMAND_LONG_ENABLED", r.unknown)
    r.in_function(GCS_COMMON, "GCS_MAVLINK::try_command_long_as_command_int", r"(\w+)")  # exists
    stores = {f.symbol for f in r.in_function(GCS_COMMON, "GCS_MAVLINK::command_long_stores_location",
                                              CASE_CMD) if f.active}
    framed = {f.symbol for f in
              r.in_function(GCS_COMMON, "GCS_MAVLINK::mav_frame_for_command_long",
                            r"\{\s*(MAV_CMD_\w+)\s*,\s*MAV_FRAME_\w+\s*\}")
              + r.in_function(GCS_COPTER, "GCS_MAVLINK_Copter::mav_frame_for_command_long",
                              r"==\s*(MAV_CMD_\w+)") if f.active}
    commands = []
    for symbol, f in taken.items():
        paths = ["int"]
        if long_enabled and not (symbol in stores and symbol not in framed):
            paths.insert(0, "long")
        commands.append({"name": symbol, "id": command_id(symbol), "paths": paths,
                         "source": f.source})
    commands.sort(key=lambda c: (c["id"], c["name"]))
    return commands, _compiled_out("commands", out, lambda s: s, command_id)


MESSAGE_SOURCES = (
    # (file, function, pattern) in the order a received message meets them
    (GCS_COPTER, "GCS_MAVLINK_Copter::handle_message", CASE_MSG),
    (GCS_COMMON, "GCS_MAVLINK::handle_message", CASE_MSG),
    (GCS_COMMON, "GCS_MAVLINK::packetReceived", r"msgid\s*==\s*MAVLINK_MSG_ID_(\w+)"),
    ("libraries/AP_Follow/AP_Follow.cpp", "AP_Follow::handle_msg", CASE_MSG),
    ("libraries/AP_Avoidance/AP_Avoidance.cpp", "AP_Avoidance::handle_msg",
     r"msgid\s*!=\s*MAVLINK_MSG_ID_(\w+)"),  # it returns early for every other message
)


def extract_messages(r: Reader) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    found: list[Found] = []
    for path, function, pattern in MESSAGE_SOURCES:
        found += r.in_function(path, function, pattern)
    taken, out = _dedupe(found)
    messages = [{"name": s, "id": message_id(s), "source": f.source} for s, f in taken.items()]
    messages.sort(key=lambda m: (m["id"], m["name"]))
    return messages, _compiled_out("messages", out, lambda s: s, message_id)


def extract_modes(r: Reader) -> list[dict[str, Any]]:
    text = strip_comments(r.tree.read("ArduCopter/mode.h"))
    block = re.search(r"enum\s+class\s+Number\s*:\s*\w+\s*\{(.*?)\}", text, re.S)
    if block is None:
        raise SystemExit("ArduCopter/mode.h: enum class Number not found")
    built = {f.symbol: f for f in r.in_function("ArduCopter/mode.cpp", "Copter::mode_from_mode_num",
                                                r"\bcase\s+Mode::Number::(\w+)\s*:")}
    # AUTO_RTL is not built by mode_from_mode_num: Copter::set_mode turns it into AUTO
    special = {f.symbol: f for f in r.in_function("ArduCopter/mode.cpp", "Copter::set_mode",
                                                  r"mode\s*==\s*Mode::Number::(\w+)\s*\)")}
    modes = []
    for name, number in re.findall(r"(\w+)\s*=\s*(\d+)", block.group(1)):
        entry: dict[str, Any] = {"name": name, "number": int(number), "source": "ArduCopter/mode.h"}
        f = built.get(name) or special.get(name)
        entry["in_sitl_build"] = bool(f and f.active)
        if f is not None and f.guards:
            entry["guard"] = " && ".join(f.guards)
        if f is None:
            entry["guard"] = "not constructed by Copter::mode_from_mode_num"
        modes.append(entry)
    modes.sort(key=lambda m: m["number"])
    return modes


MISSION = "libraries/AP_Mission/AP_Mission.cpp"


def extract_mission_commands(r: Reader) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    found = (r.in_function(MISSION, "AP_Mission::get_next_cmd", r"\.id\s*==\s*(MAV_CMD_DO_JUMP\w*)")
             + r.in_function("ArduCopter/mode_auto.cpp", "ModeAuto::start_command", CASE_CMD)
             + r.in_function(MISSION, "AP_Mission::start_command", CASE_CMD))
    taken, out = _dedupe(found)
    nav_extra = {f.symbol for f in r.in_function(MISSION, "AP_Mission::is_nav_cmd",
                                                 r"==\s*(MAV_CMD_\w+)") if f.active}
    nav_last = getattr(mavlink, "MAV_CMD_NAV_LAST")
    condition_last = getattr(mavlink, "MAV_CMD_CONDITION_LAST")

    def role(symbol: str) -> str:
        cid = command_id(symbol)
        if cid <= nav_last or symbol in nav_extra:  # AP_Mission::is_nav_cmd
            return "nav"
        return "condition" if cid < condition_last else "do"

    mission = [{"name": s, "id": command_id(s), "role": role(s), "source": f.source}
               for s, f in taken.items()]
    mission.sort(key=lambda c: (c["id"], c["name"]))
    return mission, _compiled_out("mission_commands", out, lambda s: s, command_id)


_TABLE = re.compile(r"const\s+(?:struct\s+)?AP_Param::GroupInfo\s+([\w:]+)::(\w+)\s*\[\s*\]\s*=\s*\{")
_ENTRY = re.compile(
    r"AP_GROUPINFO(?P<flavour>_FLAGS|_FRAME)?\s*\(\s*\"(?P<name>\w*)\"\s*,\s*\d+\s*,\s*[\w:]+\s*,"
    r"\s*(?P<element>\w+)(?P<rest>[^;]*?)\)\s*,"
    r"|AP_(?P<sub>SUBGROUPINFO|SUBGROUPPTR)\s*\(\s*[^,]+,\s*\"(?P<sprefix>\w*)\"\s*,\s*\d+\s*,"
    r"\s*[\w:]+\s*,\s*(?P<sclass>[\w:]+)\s*\)"
    r"|AP_SUBGROUPEXTENSION\s*\(\s*\"(?P<eprefix>\w*)\"\s*,\s*\d+\s*,\s*(?P<eclass>[\w:]+)\s*,"
    r"\s*(?P<etable>\w+)\s*\)")


class ParamTables:
    """AP_Param::GroupInfo tables, found by (class name without namespace, table name)."""

    def __init__(self, r: Reader) -> None:
        self.r = r
        self.where: dict[tuple[str, str], tuple[str, int, int]] = {}
        self._types: dict[tuple[str, str], dict[str, str]] = {}
        for path in r.tree.listdir("libraries/SITL"):
            if path.endswith(".cpp"):
                self._index(path)

    def _index(self, path: str) -> None:
        clean = strip_comments(self.r.tree.read(path))
        for m in _TABLE.finditer(clean):
            key = (m.group(1).split("::")[-1], m.group(2))
            first = clean.count("\n", 0, m.start()) + 1
            pos = closing(clean, m.end() - 1)
            self.where.setdefault(key, (path, first, clean.count("\n", 0, pos) + 1))

    def member_types(self, path: str, cls: str) -> dict[str, str]:
        """AP_Param member types (AP_Float, AP_Vector3f, ...) of class cls, declared in a header
        beside path."""
        key = (path, cls)
        if key not in self._types:
            folder = path.rsplit("/", 1)[0]
            head = re.compile(r"\b(?:class|struct)\s+" + re.escape(cls) + r"\b[^;{]*\{")
            types: dict[str, str] = {}
            for header in self.r.tree.listdir(folder):
                if not header.endswith(".h"):
                    continue
                text = strip_comments(self.r.tree.read(header))
                for m in head.finditer(text):
                    body = text[m.end():closing(text, m.end() - 1)]
                    for kind, member in re.findall(r"\bAP_(Float|Int8|Int16|Int32|Vector3f)\s+(\w+)",
                                                   body):
                        types[member] = "ambiguous" if types.get(member, kind) != kind else kind
            self._types[key] = types
        return self._types[key]

    def lookup(self, cls: str, table: str) -> tuple[str, int, int]:
        key = (cls.split("::")[-1], table)
        if key not in self.where:
            for path in self.r.tree.grep(rf"GroupInfo\s+([A-Za-z_:]*::)?{key[0]}::{table}\s*\[",
                                      "libraries/*.cpp"):
                self._index(path)
        if key not in self.where:
            raise SystemExit(f"no AP_Param table {cls}::{table} found")
        return self.where[key]


def extract_sim_parameters(r: Reader) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    params = r.tree.read("ArduCopter/Parameters.cpp")
    root = re.search(r"GOBJECT\s*\(\s*sitl\s*,\s*\"(\w+)\"\s*,\s*([\w:]+)\s*\)", params)
    if root is None:
        raise SystemExit("ArduCopter/Parameters.cpp: no GOBJECT(sitl, ...)")
    tables = ParamTables(r)
    found: list[dict[str, Any]] = []
    left_out: list[dict[str, Any]] = []

    def walk(prefix: str, cls: str, table: str, guards: tuple[str, ...]) -> None:
        path, first, last = tables.lookup(cls, table)
        lines = r.lines(path)[first - 1:last]
        for line in lines:
            for m in _ENTRY.finditer(line.full):
                g = tuple(dict.fromkeys(guards + line.guards))
                if m.group("name") is not None:
                    name = prefix + m.group("name")
                    frame_only = m.group("flavour") == "_FRAME" and "COPTER" not in m.group("rest")
                    if not line.active or frame_only:
                        left_out.append({"kind": "sim_parameters", "name": name, "source": path,
                                         "guard": "frame flags" + m.group("rest") if frame_only
                                         else " && ".join(g)})
                    else:
                        kind = tables.member_types(path, cls.split("::")[-1]).get(m.group("element"))
                        if kind == "ambiguous":
                            raise SystemExit(f"{path}: cannot tell the type of {m.group('element')}")
                        # an AP_Vector3f is served as three parameters
                        for n in ([name + a for a in ("_X", "_Y", "_Z")] if kind == "Vector3f"
                                  else [name]):
                            found.append({"name": n, "source": path})
                elif m.group("sub") is not None:
                    sub_prefix, sub_cls = prefix + m.group("sprefix"), m.group("sclass")
                    if not line.active:
                        left_out.append({"kind": "sim_parameters", "name": sub_prefix + "*",
                                         "source": path, "guard": " && ".join(g)})
                    elif m.group("sub") == "SUBGROUPPTR":
                        left_out.append({"kind": "sim_parameters", "name": sub_prefix + "*",
                                         "source": path,
                                         "guard": f"AP_SUBGROUPPTR: only when the simulated model "
                                                  f"allocates a {sub_cls}"})
                    else:
                        walk(sub_prefix, sub_cls, "var_info", g)
                else:
                    ext_prefix = prefix + m.group("eprefix")
                    if line.active:
                        walk(ext_prefix, m.group("eclass"), m.group("etable"), g)

    walk(root.group(1), root.group(2), "var_info", ())
    names = [p["name"] for p in found]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise SystemExit(f"SIM parameter names found twice: {dupes}")
    found.sort(key=lambda p: p["name"])
    left_out.sort(key=lambda p: p["name"])
    return found, left_out


# ---------------------------------------------------------------------------------------------


def extract(tree: Tree) -> dict[str, Any]:
    r = Reader(tree)
    try:
        return _extract(r)
    finally:
        tree.close()


def _extract(r: Reader) -> dict[str, Any]:
    tree = r.tree
    commands, commands_out = extract_commands(r)
    messages, messages_out = extract_messages(r)
    modes = extract_modes(r)
    mission, mission_out = extract_mission_commands(r)
    sim, sim_out = extract_sim_parameters(r)
    if r.unknown:
        raise UnknownMacro(sorted(r.unknown))
    for entry in commands + mission + messages:
        if entry["name"] in not_in_pymavlink:
            entry["in_pymavlink"] = False  # id from ArduPilot's MAVLink XML
    counts = {"commands": len(commands),
              "commands_long": sum("long" in c["paths"] for c in commands),
              "commands_int_only": sum(c["paths"] == ["int"] for c in commands),
              "messages": len(messages), "modes": len(modes),
              "modes_in_sitl_build": sum(m["in_sitl_build"] for m in modes),
              "mission_commands": len(mission), "sim_parameters": len(sim)}
    return {
        "ardupilot_commit": tree.commit,
        "generated_by": GENERATED_BY,
        "counted": {
            "commands": "distinct MAV_CMD case labels compiled into the SITL build in "
                        "GCS_MAVLINK_Copter::handle_command_int_packet and "
                        "GCS_MAVLINK::handle_command_int_packet; paths: 'long' when COMMAND_LONG "
                        "reaches the same handler through try_command_long_as_command_int",
            "messages": "distinct MAVLINK_MSG_ID case labels compiled into the SITL build in "
                        "GCS_MAVLINK_Copter::handle_message and GCS_MAVLINK::handle_message, plus "
                        "messages read on receipt by GCS_MAVLINK::packetReceived, "
                        "AP_Follow::handle_msg and AP_Avoidance::handle_msg",
            "modes": "every enumerator of Mode::Number in ArduCopter/mode.h; in_sitl_build: "
                     "whether Copter::mode_from_mode_num (or set_mode for AUTO_RTL) has it",
            "mission_commands": "ModeAuto::start_command's cases, AP_Mission::start_command's "
                                "own cases and the jumps AP_Mission::get_next_cmd resolves; "
                                "role by AP_Mission::is_nav_cmd, then CONDITION below "
                                "MAV_CMD_CONDITION_LAST, else do",
            "sim_parameters": "SIM_ parameters of SIM::var_info and the groups it includes "
                              "(AP_SUBGROUPINFO, AP_SUBGROUPEXTENSION), SITL build guards applied; "
                              "AP_SUBGROUPPTR groups (present only for other models) left out",
        },
        "counts": counts,
        "commands": commands,
        "messages": messages,
        "modes": modes,
        "mission_commands": mission,
        "sim_parameters": sim,
        "compiled_out": commands_out + messages_out + mission_out + sim_out,
    }


def find_source(given: str | None) -> Path:
    if given:
        return Path(given)
    for candidate in SOURCE_CANDIDATES:
        if candidate.exists():
            return candidate
    raise SystemExit("no ArduPilot repository found; pass its path")


def render(doc: dict[str, Any]) -> str:
    return json.dumps(doc, indent=1) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", nargs="?", help="ArduPilot git directory or working tree")
    parser.add_argument("--out", default=str(DEFAULT_OUT))
    args = parser.parse_args(argv)
    tree = Tree(find_source(args.source), ARDUPILOT_COMMIT)
    try:
        doc = extract(tree)
    except UnknownMacro as e:
        print("guards name macros missing from SITL_MACROS:", " ".join(e.args[0]), file=sys.stderr)
        return 2
    Path(args.out).write_text(render(doc))
    for kind, n in doc["counts"].items():
        print(f"{kind}: {n}")
    print(f"compiled out of the SITL build: {len(doc['compiled_out'])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
