"""The payload outputs ArduCopter drives itself (issue 32): the parachute (AP_Parachute, CHUTE_*,
with SITL's simulated one, SIM_PARA_*) and the sprayer (AC_Sprayer, SPRAY_*), each answering its
command and mission item and moving its outputs, read off SERVO_OUTPUT_RAW.

motor_order    the quad's motors on outputs 1-4, told apart by what they do: hovering in GUIDED,
               which outputs first work harder as the vehicle rolls into a move east ("a": 2 over
               1), pitches into a move north (4 over 3) and turns its nose right (1 and 2 over 3
               and 4): ArduCopter's QUAD PLUS has 1 right, 2 left, 3 front, 4 back, 1 and 2 turning
               the other way from 3 and 4.
chute_off      defaults (CHUTE_ENABLED 0): DO_PARACHUTE's answers and CHUTE_ENABLED after each;
               enabled by command with the relay release (CHUTE_TYPE 0), the arming checks on
               the relay; disabled again, armed.
chute_servo    CHUTE_ENABLED 1, CHUTE_TYPE 10 (a servo) on output 9 (SERVO9_FUNCTION 27), SITL's
               parachute on that pin: the CHUTE_* values and types, the output at rest; a release
               on the ground, armed on the ground, flying below CHUTE_ALT_MIN (5 m) and above it
               (40 m): answers, texts, arming, the output's on time and hold, the fall (sink rate
               a second in, time to the ground, speed at it); then the arming check after a
               release, and with the parachute disabled.
chute_free_fall CHUTE_ALT_MIN 0, CHUTE_DELAY_MS 0, CHUTE_OPTIONS 1 (hold open), no simulated
               parachute: released at 5 m, the output at once and held, the fall unbraked.
chute_sink     CHUTE_CRT_SINK 3: a GUIDED descent at up to 3.5 m/s (WPNAV_SPEED_DN) from 40 m
               releases it by itself once sinking faster than 3 m/s for a second.
chute_mission  AUTO: takeoff to 8 m (below CHUTE_ALT_MIN), a waypoint, DO_PARACHUTE 2, a waypoint,
               LAND: what is said, reached and current, arming and mode after, the output.
gripper        GRIP_ENABLE 1, GRIP_TYPE 1 (a servo) on output 9 (SERVO9_FUNCTION 28), SITL's gripper on
               that pin (its jaws take up a 1 kg load on the ground): the GRIP_* values and types,
               the output at rest; DO_GRIPPER's answers, texts and output for each action on the
               ground; the hover's motor outputs carrying the load, after releasing it in the air
               and after grabbing again there (nothing to take up); then a mission's DO_GRIPPER.
sprayer        SPRAY_ENABLE 0 then 1, the pump on output 9 (SERVO9_FUNCTION 22) and the spinner on
               10 (23): DO_SPRAYER's answers and outputs on the ground, hovering, flying north at
               6 m/s (the pump follows the speed: SPRAY_PUMP_RATE % of its range per m/s), after
               stopping (off a second after the speed falls below SPRAY_SPEED_MIN), and in AUTO
               between DO_SPRAYER 1 and 0 items on a 100 m leg flown at 10 m/s (the pump at the
               top of its range).
"""
from __future__ import annotations

from ..client import Client, mav
from ..facts import Tol, Trace
from ..targets import run_each
from .missions import upload
from .states import GUIDED, AUTO, reach_flying
from .surface_mission import Geometry, item
from .texts import said

AREA = "payload_outputs"
PUMP, SPINNER = 9, 10  # the sprayer's outputs
CHUTE = 9  # the parachute's servo output
CHUTE_BOOT = {"CHUTE_ENABLED": 1, "CHUTE_TYPE": 10, "SERVO9_FUNCTION": 27}
SIM_PARACHUTE = {"SIM_PARA_ENABLE": 1, "SIM_PARA_PIN": CHUTE}
GRIPPER = 9  # the gripper's servo output
GRIPPER_BOOT = {"GRIP_ENABLE": 1, "GRIP_TYPE": 1, "SERVO9_FUNCTION": 28, "SIM_GRPS_ENABLE": 1, "SIM_GRPS_PIN": GRIPPER}
GRIP_PARAMS = ("GRIP_ENABLE", "GRIP_TYPE", "GRIP_GRAB", "GRIP_RELEASE", "GRIP_NEUTRAL", "GRIP_REGRAB", "GRIP_CAN_ID",
               "GRIP_AUTOCLOSE")
LOAD_SHOWS_US = 30  # the hover's motor outputs rise by more than this carrying SITL's 1 kg (measured 91 us)
CHUTE_PARAMS = ("CHUTE_ENABLED", "CHUTE_TYPE", "CHUTE_SERVO_ON", "CHUTE_SERVO_OFF", "CHUTE_ALT_MIN",
                "CHUTE_DELAY_MS", "CHUTE_CRT_SINK", "CHUTE_OPTIONS")
SPRAY_PARAMS = ("SPRAY_ENABLE", "SPRAY_PUMP_RATE", "SPRAY_SPINNER", "SPRAY_SPEED_MIN", "SPRAY_PUMP_MIN")
# An ARM sent again this soon after the last (1.5 s of both sim and wall time) is a retry to
# Firefly's command service, answered with the last one's result: arming attempts wait longer.
ARM_GAP_S = 1.6
RELEASE_ALT_M = 40.0
LOW_ALT_M = 5.0
GROUND_M = 0.3  # below this height above home the vehicle has come down
TIMING = Tol(abs=0.15, why="the output and the position are read off 20 Hz streams, and each vehicle runs "
                           "its parachute at its own loop rate (ArduCopter 400 Hz, Firefly 100 Hz)")
FREE_FALL_S = Tol(abs=0.15, why="a fall from 5 m read off a 20 Hz stream; the airframes' drag differs a little "
                                "at these speeds")
IMPACT = Tol(abs=1.0, why="the last 20 Hz sample before the ground, up to 50 ms (0.5 m/s) early, and each "
                          "airframe's own drag (SITL's quad sheds 0.6 m/s more over 5 m)")
SINK = Tol(abs=0.3, why="the sink rate at the release, read off a 20 Hz stream, near the descent's steady 3.5 m/s")
PUMP_PWM = Tol(abs=15, why="the pump follows the ground speed, read at 3 Hz: within 0.2 m/s of the other "
                            "vehicle's is 16 us")
SHUT_OFF_S = (1.0, 1.0 + 2 / 3 + 0.1)  # a second counted in 3 Hz updates, and the 20 Hz streams' lag


def _param(c: Client, name: str) -> list:
    """[value, MAV_PARAM_TYPE] as PARAM_VALUE reports it."""
    c.conn.mav.param_request_read_send(1, 1, name.encode(), -1)
    c.last.pop("PARAM_VALUE", None)
    if not c.try_wait(lambda: "PARAM_VALUE" in c.last and c.last["PARAM_VALUE"].param_id == name, 5):
        return [None, None]
    m = c.last["PARAM_VALUE"]
    return [m.param_value, m.param_type]


def _outputs(c: Client, *servos: int) -> list[int]:
    c.fresh("SERVO_OUTPUT_RAW")
    m = c.last["SERVO_OUTPUT_RAW"]
    return [getattr(m, f"servo{n}_raw") for n in servos]


def _command(c: Client, trace: Trace, name: str, command: int, *params: float, outputs=(CHUTE,),
             settle_s: float = 1.0) -> None:
    """The answer, what was said, the arming after and the outputs, `settle_s` later."""
    t0 = c.now_ms
    trace.fact(f"{name}.result", c.command(command, *params))
    c.idle(settle_s)
    c.fresh_heartbeat()
    # (bounded: a client stalled on a loaded machine reads on, at 20x, past the auto-disarm of a
    # vehicle armed on the ground)
    trace.fact(f"{name}.said", said(c.texts_since(t0, within_s=settle_s + 0.5)))
    trace.fact(f"{name}.armed", c.armed)
    trace.fact(f"{name}.outputs", _outputs(c, *outputs))


class Watch:
    """SERVO_OUTPUT_RAW and GLOBAL_POSITION_INT as they come (asked at 20 Hz), stamped in vehicle time."""

    def __init__(self, c: Client):
        self.c = c
        self.servos: list[tuple[int, object]] = []
        self.positions: list[tuple[int, object]] = []
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 50_000)
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, 50_000)

    def __call__(self, msg) -> None:
        kind = msg.get_type()
        if kind == "SERVO_OUTPUT_RAW":
            self.servos.append((self.c.now_ms, msg))
        elif kind == "GLOBAL_POSITION_INT":
            self.positions.append((self.c.now_ms, msg))

    def output(self, n: int) -> list[tuple[int, int]]:
        return [(t, getattr(m, f"servo{n}_raw")) for t, m in self.servos]

    def first(self, n: int, pwm: int, after_ms: int) -> int | None:
        return next((t for t, value in self.output(n) if t >= after_ms and value == pwm), None)

    def first_not(self, n: int, pwm: int, after_ms: int) -> int | None:
        return next((t for t, value in self.output(n) if t >= after_ms and value != pwm), None)

    def vz_at(self, t_ms: int) -> float | None:
        near = min(self.positions, key=lambda p: abs(p[0] - t_ms), default=None)
        return None if near is None else near[1].vz / 100.0

    def landed_at(self, after_ms: int) -> int | None:
        return next((t for t, m in self.positions if t >= after_ms and m.relative_alt / 1000.0 < GROUND_M), None)

    def top_sink(self, from_ms: int, to_ms: int) -> float | None:
        values = [m.vz / 100.0 for t, m in self.positions if from_ms <= t <= to_ms]
        return max(values) if values else None


def _seconds(a_ms: int | None, b_ms: int | None) -> float | None:
    return None if a_ms is None or b_ms is None else (b_ms - a_ms) / 1000.0


def _climb_to(c: Client, alt_m: float) -> None:
    m = c.last["GLOBAL_POSITION_INT"]
    c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000,
                                                   m.lat, m.lon, alt_m, 0, 0, 0, 0, 0, 0, 0, 0)
    c.wait(lambda: abs(c.rel_alt_m() - alt_m) < 0.3, 60, what=f"{alt_m:g} m")
    c.idle(2.0)


def _arm(c: Client, trace: Trace, name: str) -> None:
    t0 = c.now_ms
    trace.fact(f"{name}.result", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(ARM_GAP_S)
    # (the periodic "PreArm: " report may fall in the window or not: only the ARM's own answer)
    trace.fact(f"{name}.texts", [text for text in c.texts_since(t0) if text.startswith("Arm: ")])
    if c.armed:
        c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
        c.wait(lambda: not c.armed, 5, what="disarmed")


def _release_and_fall(c: Client, trace: Trace, watch: Watch, after_s: float) -> int:
    """DO_PARACHUTE 2 flying, watched until `after_s` after the vehicle is down: the answer, what
    was said, the arming and when the output fired. The vehicle time of the release."""
    with c.listening(watch):
        t0 = c.now_ms
        trace.fact("release.result", c.command(mav.MAV_CMD_DO_PARACHUTE, 2))
        c.wait(lambda: c.rel_alt_m() < GROUND_M, 30, what="the ground")
        c.idle(after_s)
    trace.fact("release.said", said(c.texts_since(t0)))
    trace.fact("release.armed", c.armed)
    trace.fact("release.output_on_after_s", _seconds(t0, watch.first(CHUTE, 1300, t0)), TIMING)
    return t0


def _fall(trace: Trace, watch: Watch, t0: int, timing: Tol) -> None:
    """How long the fall took and how fast it hit the ground."""
    ground = watch.landed_at(t0)
    trace.fact("release.ground_s", _seconds(t0, ground), timing)
    trace.fact("release.impact_m_s", watch.top_sink(t0, ground or t0), IMPACT)


def _outputs_while(c: Client, seconds: float, send) -> list[tuple[int, int, int, int]]:
    """The four motor outputs over `seconds` from sending a target (send())."""
    seen: list[tuple[int, int, int, int]] = []

    def take(msg) -> None:
        if msg.get_type() == "SERVO_OUTPUT_RAW":
            seen.append((msg.servo1_raw, msg.servo2_raw, msg.servo3_raw, msg.servo4_raw))
    with c.listening(take):
        send()
        c.idle(seconds)
    return seen


def _first_ahead(seen: list[tuple[int, int, int, int]], a, b) -> str | None:
    """Which side's outputs first work harder than the other's by more than 3 us (a and b pick
    a side's sum out of the four outputs): "a", "b" or None."""
    for outputs in seen:
        lead = a(*outputs) - b(*outputs)
        if abs(lead) > 3:
            return "a" if lead > 0 else "b"
    return None


def motor_order(c: Client, trace: Trace) -> None:
    reach_flying(c, 10.0)
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 20_000)
    c.idle(2.0)

    def velocity(vn: float, ve: float, yaw_rate: float = 0.0, mask: int = 0b010111000111):
        return lambda: c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, mask,
                                                                    0, 0, 0, vn, ve, 0, 0, 0, 0, 0, yaw_rate)
    stop = velocity(0.0, 0.0)
    east = _outputs_while(c, 0.6, velocity(0.0, 5.0))
    trace.fact("rolling_right.ahead", _first_ahead(east, lambda s1, s2, s3, s4: s2, lambda s1, s2, s3, s4: s1))
    _outputs_while(c, 4.0, stop)
    north = _outputs_while(c, 0.6, velocity(5.0, 0.0))
    trace.fact("pitching_down.ahead", _first_ahead(north, lambda s1, s2, s3, s4: s4, lambda s1, s2, s3, s4: s3))
    _outputs_while(c, 4.0, stop)
    turning = _outputs_while(c, 1.0, velocity(0.0, 0.0, 1.5, 0b000111000111))
    trace.fact("turning_right.ahead", _first_ahead(turning, lambda s1, s2, s3, s4: s1 + s2,
                                                   lambda s1, s2, s3, s4: s3 + s4))


def chute_off(c: Client, trace: Trace) -> None:
    c.set_mode(GUIDED)
    for action in (2, 3, -1, 0, 1):
        t0 = c.now_ms
        trace.fact(f"action{action}.result", c.command(mav.MAV_CMD_DO_PARACHUTE, action))
        c.idle(0.5)
        trace.fact(f"action{action}.said", said(c.texts_since(t0)))
        trace.fact(f"action{action}.enabled", _param(c, "CHUTE_ENABLED")[0])
    _arm(c, trace, "arm_relay_type")  # CHUTE_TYPE 0: released by a relay with RELAYn_FUNCTION 3
    trace.fact("relay_function_set", c.set_param("RELAY1_FUNCTION", 3))
    _arm(c, trace, "arm_relay_function")
    c.set_param("RELAY1_FUNCTION", 1)
    t0 = c.now_ms
    trace.fact("release_landed.result", c.command(mav.MAV_CMD_DO_PARACHUTE, 2))
    c.idle(0.5)
    trace.fact("release_landed.said", said(c.texts_since(t0)))
    c.command(mav.MAV_CMD_DO_PARACHUTE, 0)
    _arm(c, trace, "arm_disabled")


def chute_servo(c: Client, trace: Trace) -> None:
    for name in CHUTE_PARAMS:
        trace.fact(f"param.{name}", _param(c, name))
    watch = Watch(c)
    trace.fact("rest.outputs", _outputs(c, CHUTE))
    c.set_mode(GUIDED)
    _command(c, trace, "ground", mav.MAV_CMD_DO_PARACHUTE, 2)
    _command(c, trace, "ground_action3", mav.MAV_CMD_DO_PARACHUTE, 3)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.wait(lambda: c.armed, 10, what="armed")
    _command(c, trace, "armed_ground", mav.MAV_CMD_DO_PARACHUTE, 2)
    reach_flying(c, LOW_ALT_M)
    _command(c, trace, "too_low", mav.MAV_CMD_DO_PARACHUTE, 2)
    _climb_to(c, RELEASE_ALT_M)
    t0 = _release_and_fall(c, trace, watch, 3.0)
    on = watch.first(CHUTE, 1300, t0)
    trace.fact("release.output_held_s", _seconds(on, watch.first_not(CHUTE, 1300, on or t0)), TIMING)
    trace.fact("release.output_after", _outputs(c, CHUTE))
    trace.fact("release.sink_1s", watch.vz_at(t0 + 1000), Tol(abs=0.5, why="20 Hz stream"))
    _fall(trace, watch, t0, TIMING)
    _arm(c, trace, "arm_after_release")
    t0 = c.now_ms
    trace.fact("prearm_after_release.result", c.command(mav.MAV_CMD_RUN_PREARM_CHECKS))
    c.idle(1.0)
    trace.fact("prearm_after_release.texts", [text for text in c.texts_since(t0) if "Chute" in text])
    trace.fact("disable.result", c.command(mav.MAV_CMD_DO_PARACHUTE, 0))
    trace.fact("disable.enabled", _param(c, "CHUTE_ENABLED")[0])
    _arm(c, trace, "arm_disabled")
    trace.fact("enable.result", c.command(mav.MAV_CMD_DO_PARACHUTE, 1))
    _arm(c, trace, "arm_enabled_again")


def chute_free_fall(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    reach_flying(c, LOW_ALT_M)
    t0 = _release_and_fall(c, trace, watch, 3.5)
    trace.fact("release.output_still_on", _outputs(c, CHUTE))
    _fall(trace, watch, t0, FREE_FALL_S)


def chute_sink(c: Client, trace: Trace) -> None:
    c.set_param("WPNAV_SPEED_DN", 350)  # just above CHUTE_CRT_SINK: steady when it releases
    reach_flying(c, RELEASE_ALT_M)
    watch = Watch(c)
    with c.listening(watch):
        t0 = c.now_ms
        m = c.last["GLOBAL_POSITION_INT"]
        c.conn.mav.set_position_target_global_int_send(0, 1, 1, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b110111111000,
                                                       m.lat, m.lon, 12.0, 0, 0, 0, 0, 0, 0, 0, 0)
        c.wait(lambda: not c.armed, 40, what="the release")
        released = c.now_ms
        c.wait(lambda: c.rel_alt_m() < GROUND_M, 30, what="the ground")
        c.idle(2.0)
    trace.fact("said", said(c.texts_since(t0)))
    text_at = next((t for t, _, text in c.texts if t >= t0 and text == "Parachute: Released"), released)
    trace.fact("sink_at_release", watch.vz_at(text_at), SINK)
    fast_since = next((t for t, m in reversed(watch.positions) if t <= text_at and m.vz / 100.0 <= 3.0), None)
    trace.fact("sinking_before_release_s", _seconds(fast_since, text_at), TIMING)
    trace.fact("output_on_after_s", _seconds(text_at, watch.first(CHUTE, 1300, text_at)), TIMING)


def chute_mission(c: Client, trace: Trace) -> None:
    watch = Watch(c)
    c.wait(lambda: "GLOBAL_POSITION_INT" in c.last, 10, what="position")
    geo = Geometry(c.last["GLOBAL_POSITION_INT"].lat, c.last["GLOBAL_POSITION_INT"].lon)
    items = [item(mav.MAV_CMD_NAV_TAKEOFF, geo, alt=8.0), item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.5, 0.0), alt=8.0),
             item(mav.MAV_CMD_DO_PARACHUTE, geo, (2, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(30.0, 0.0), alt=8.0), item(mav.MAV_CMD_NAV_LAND, geo)]
    trace.fact("upload", upload(c, items))
    c.set_mode(GUIDED)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    c.wait(lambda: c.armed, 10, what="armed")
    reached: list[int] = []

    def take(msg) -> None:
        watch(msg)
        if msg.get_type() == "MISSION_ITEM_REACHED":
            reached.append(msg.seq)
    with c.listening(take):
        t0 = c.now_ms
        trace.fact("start", c.command(mav.MAV_CMD_MISSION_START))
        c.wait(lambda: not c.armed, 60, what="the release")
        c.wait(lambda: c.rel_alt_m() < GROUND_M, 30, what="the ground")
        c.idle(3.0)
    trace.fact("said", said(c.texts_since(t0)))
    trace.fact("reached", reached)
    c.fresh("MISSION_CURRENT")
    trace.fact("current_end", c.last["MISSION_CURRENT"].seq)
    c.fresh_heartbeat()
    trace.fact("mode_end", c.mode)
    trace.fact("armed_end", c.armed)
    trace.fact("output_values", sorted({pwm for _, pwm in watch.output(CHUTE)}))


def _mission_said(c: Client, t0: int) -> list[str]:
    """What was said once AUTO began (the upload's "Flight plan received" may come a moment late)."""
    return [text for text in said(c.texts_since(t0)) if text != "Flight plan received"]


def _hover_us(c: Client, samples: int = 20) -> float:
    """The four motors' mean output over `samples` SERVO_OUTPUT_RAWs."""
    total = 0.0
    for _ in range(samples):
        c.fresh("SERVO_OUTPUT_RAW")
        m = c.last["SERVO_OUTPUT_RAW"]
        total += (m.servo1_raw + m.servo2_raw + m.servo3_raw + m.servo4_raw) / 4.0
    return total / samples


def gripper(c: Client, trace: Trace) -> None:
    for name in GRIP_PARAMS:
        trace.fact(f"param.{name}", _param(c, name))
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    trace.fact("rest.outputs", _outputs(c, GRIPPER))
    for name, params in (("release", (1, 0)), ("release_again", (1, 0)), ("action2", (1, 2)), ("grab", (1, 1)),
                         ("grab_again", (1, 1)), ("gripper5_release", (5, 0)), ("grab_load", (1, 1))):
        # Firefly answers an unconfirmed repeat within 1.5 s of vehicle time as a retry (commands.py's
        # RETRY_WINDOW_S) where ArduCopter runs it again: each command comes well after the last
        c.idle(0.5)
        _command(c, trace, name, mav.MAV_CMD_DO_GRIPPER, *params, outputs=(GRIPPER,))
    c.idle(3.0)  # SITL's jaws shut on the load 2.3 s after a grab from open
    reach_flying(c, 10.0)
    c.idle(3.0)
    loaded = _hover_us(c)
    _command(c, trace, "release_flying", mav.MAV_CMD_DO_GRIPPER, 1, 0, outputs=(GRIPPER,), settle_s=3.0)
    unloaded = _hover_us(c)
    trace.fact("load_raised_hover", loaded - unloaded > LOAD_SHOWS_US)
    _command(c, trace, "grab_flying", mav.MAV_CMD_DO_GRIPPER, 1, 1, outputs=(GRIPPER,), settle_s=3.0)
    trace.fact("no_load_taken_up_flying", abs(_hover_us(c) - unloaded) < LOAD_SHOWS_US / 2)
    m = c.last["GLOBAL_POSITION_INT"]
    geo = Geometry(m.lat, m.lon)
    items = [item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.0, 0.0), alt=10.0), item(mav.MAV_CMD_DO_GRIPPER, geo, (1, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(10.0, 0.0), alt=10.0),
             item(mav.MAV_CMD_NAV_LOITER_UNLIM, geo, at=(10.0, 0.0), alt=10.0)]
    trace.fact("mission.upload", upload(c, items))
    t0 = c.now_ms
    c.set_mode(AUTO)
    c.wait(lambda: "MISSION_CURRENT" in c.last and c.last["MISSION_CURRENT"].seq == 4, 60, what="the loiter")
    c.idle(1.0)
    trace.fact("mission.said", _mission_said(c, t0))
    trace.fact("mission.outputs_after", _outputs(c, GRIPPER))


def sprayer(c: Client, trace: Trace) -> None:
    for name in SPRAY_PARAMS:
        trace.fact(f"param.{name}", _param(c, name))
    c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, 100_000)
    trace.fact("rest.outputs", _outputs(c, PUMP, SPINNER))
    both = (PUMP, SPINNER)
    _command(c, trace, "disabled_on", mav.MAV_CMD_DO_SPRAYER, 1, outputs=both)
    c.set_param("SPRAY_ENABLE", 1)
    _command(c, trace, "ground_on", mav.MAV_CMD_DO_SPRAYER, 1, outputs=both)
    _command(c, trace, "ground_off", mav.MAV_CMD_DO_SPRAYER, 0, outputs=both)
    _command(c, trace, "ground_2", mav.MAV_CMD_DO_SPRAYER, 2, outputs=both)
    reach_flying(c, 10.0)
    _command(c, trace, "hover_on", mav.MAV_CMD_DO_SPRAYER, 1, outputs=both)
    watch = Watch(c)
    with c.listening(watch):
        for _ in range(25):  # 5 s north at 6 m/s
            c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, 0b110111000111,
                                                          0, 0, 0, 6.0, 0, 0, 0, 0, 0, 0, 0)
            c.idle(0.2)
        trace.fact("cruise.outputs", _outputs(c, *both), PUMP_PWM)
        c.conn.mav.set_position_target_local_ned_send(0, 1, 1, mav.MAV_FRAME_LOCAL_NED, 0b110111000111,
                                                      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)
        stopped = c.now_ms
        c.idle(6.0)
    slow = next((t for t, m in watch.positions if t >= stopped and m.vx / 100.0 < 1.0), None)
    off = watch.first(SPINNER, 1100, stopped)
    # off at the first 3 Hz update more than a second after the first one below the speed: 1.0 to
    # 1.67 s after slowing, by the updates' phase (measured 1.45 and 1.55; Firefly 1.1 to 1.35)
    after = _seconds(slow, off)
    trace.fact("stop.spinner_off_within_shut_off", after is not None and SHUT_OFF_S[0] < after <= SHUT_OFF_S[1])
    trace.fact("stop.outputs", _outputs(c, *both))
    _command(c, trace, "hover_off", mav.MAV_CMD_DO_SPRAYER, 0, outputs=both)
    # AUTO: a 100 m leg north at WPNAV_SPEED (10 m/s) between DO_SPRAYER 1 and DO_SPRAYER 0
    m = c.last["GLOBAL_POSITION_INT"]
    geo = Geometry(m.lat, m.lon)
    items = [item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(0.0, 0.0), alt=10.0), item(mav.MAV_CMD_DO_SPRAYER, geo, (1, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(100.0, 0.0), alt=10.0),
             item(mav.MAV_CMD_DO_SPRAYER, geo, (0, 0, 0, 0)),
             item(mav.MAV_CMD_NAV_WAYPOINT, geo, at=(100.0, 10.0), alt=10.0),
             item(mav.MAV_CMD_NAV_LOITER_UNLIM, geo, at=(100.0, 10.0), alt=10.0)]
    trace.fact("mission.upload", upload(c, items))
    watch = Watch(c)
    with c.listening(watch):
        t0 = c.now_ms
        c.set_mode(AUTO)
        c.wait(lambda: "MISSION_CURRENT" in c.last and c.last["MISSION_CURRENT"].seq == 5, 60, what="the last leg")
        on_leg_end = c.now_ms
        c.idle(1.0)
    trace.fact("mission.said", _mission_said(c, t0))
    leg = [(t, pump, spinner) for (t, pump), (_, spinner) in zip(watch.output(PUMP), watch.output(SPINNER))
           if t0 <= t <= on_leg_end]
    trace.fact("mission.pump_top", max((pump for _, pump, _ in leg), default=None), PUMP_PWM)
    trace.fact("mission.spinner_values", sorted({spinner for _, _, spinner in leg}))
    trace.fact("mission.outputs_after", _outputs(c, *both))


PROBES = {"motor_order": (motor_order, None), "chute_off": (chute_off, None), "chute_servo": (chute_servo, {**CHUTE_BOOT, **SIM_PARACHUTE}),
          "chute_free_fall": (chute_free_fall, {**CHUTE_BOOT, "CHUTE_ALT_MIN": 0, "CHUTE_DELAY_MS": 0,
                                                "CHUTE_OPTIONS": 1}),
          "chute_sink": (chute_sink, {**CHUTE_BOOT, "CHUTE_CRT_SINK": 3}),
          "chute_mission": (chute_mission, {**CHUTE_BOOT, **SIM_PARACHUTE}),
          "gripper": (gripper, GRIPPER_BOOT),
          "sprayer": (sprayer, {"SERVO9_FUNCTION": 22, "SERVO10_FUNCTION": 23})}


def run(target, only: tuple[str, ...] = ()) -> dict[str, Trace]:
    return run_each(target, PROBES, only)
