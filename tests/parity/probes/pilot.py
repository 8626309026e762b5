"""The pilot (issue 28, item 3), as pymavlink scripts drive it: RC_CHANNELS_OVERRIDE and
MANUAL_CONTROL, the flight-mode switch, aux switches and MAV_CMD_DO_AUX_FUNCTION, the throttle
arming checks, and the radio failsafe (SIM_RC_FAIL), measured.

* receiver_at_rest: RC_CHANNELS with no transmitter (SITL's simulated receiver).
* sysid: overrides and MANUAL_CONTROL sent from system 245 (MAVSDK's ManualControl's id) and from
  the ground station's 255, and after MAV_GCS_SYSID names 245; MANUAL_CONTROL aimed elsewhere.
* override_fields: 0 gives a channel back, UINT16_MAX leaves it, channels 9-16's own rules, and
  the overrides lapsing after RC_OVERRIDE_TIME.
* alt_hold_sticks: from a GUIDED hover to ALT_HOLD with no override (the receiver's throttle is
  closed: it descends), then with the throttle held at mid by override (it holds).
* mode_switch: the flight-mode channel moved by override through FLTMODE1..6's bands; a mode
  chosen by the ground station stays while the switch does not move; the switch back at rest.
* aux_command: MAV_CMD_DO_AUX_FUNCTION's answers: modes, a bad position, an unknown function,
  the emergency stop and what arming says under it, a pause where none can be.
* aux_switch: RC8_OPTION RTL moved by override in flight, and back; RC7's SaveWaypoint announce.
* arming_throttle: ARM with the throttle stick up in ALT_HOLD, STABILIZE and GUIDED.
* pilot_takeoff: ALT_HOLD armed on the ground, the throttle raised: the climb.
* radio_failsafe: SIM_RC_FAIL 1 (no pulses) hovering in GUIDED: the reaction's time, mode, texts
  and height path, and the radio back; then SIM_RC_FAIL 2 (throttle 950) hovering again.
* mavsdk_manual_control: MAVSDK's ManualControl plugin as its example drives it (inputs streamed,
  altitude control started, armed, the throttle pushed up), from MAVSDK's own system id 245,
  which ArduCopter does not take pilot input from: what each call answers and whether it flew.
Numbers carry tolerances for two airframes and controllers; times are the vehicle's own.
"""
from __future__ import annotations

import asyncio

from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.manual_control import ManualControlAsync, ManualControlError
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from firefly.groundstation.flight.reference_flight import connect

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import ALT_HOLD, GUIDED, LAND, LOITER, RTL, STABILIZE, on_ground_disarmed, reach_flying
from .mavsdk_client import mode as mavsdk_mode
from .mavsdk_client import outcome, until
from .texts import said

AREA = "pilot"
LEAVE, RELEASE = 65535, 0
MID, LOW, HIGH = 1500, 1000, 1900
RC_CHANNELS_US = 100_000  # RC_CHANNELS at 10 Hz
STICKS_EVERY_MS = 100  # vehicle time between overrides held by a script: well inside RC_OVERRIDE_TIME
SETTLE_S = 1.0  # past the 200 ms switch debounce and the 10 Hz aux-switch reads

RATE = Tol(abs=0.4, rel=0.2, why="climb and descent rates: two airframes and controllers, same limits")
HEIGHT = Tol(abs=1.5, why="heights along a path: the two vehicles' vertical controllers differ")
HOLD = Tol(abs=0.6, why="a height held with the throttle at mid")
REACTION = Tol(abs=0.6, why="the failsafe's reaction: ArduCopter's 100 Hz radio reads against Firefly's "
                            "10 Hz checks, and telemetry at 10 Hz")


def chans(c: Client) -> list[int]:
    """RC_CHANNELS sent from now on: chancount and channels 1-9."""
    c.fresh("RC_CHANNELS")
    m = c.last["RC_CHANNELS"]
    return [m.chancount] + [getattr(m, f"chan{i}_raw") for i in range(1, 10)]


def override(c: Client, *pwm: int, sysid: int = 255, ext: tuple = ()) -> None:
    """RC_CHANNELS_OVERRIDE as a script sends it: 8 channels (the rest "leave"), from `sysid`."""
    fields = (list(pwm) + [LEAVE] * 8)[:8]
    old = c.conn.mav.srcSystem
    c.conn.mav.srcSystem = sysid
    try:
        c.conn.mav.rc_channels_override_send(1, 1, *fields, *ext)
    finally:
        c.conn.mav.srcSystem = old


def manual_control(c: Client, x: int, y: int, z: int, r: int, sysid: int = 255, target: int = 1) -> None:
    old = c.conn.mav.srcSystem
    c.conn.mav.srcSystem = sysid
    try:
        c.conn.mav.manual_control_send(target, x, y, z, r, 0)
    finally:
        c.conn.mav.srcSystem = old


class Sticks:
    """Overrides held by a script: these 8 PWMs sent every STICKS_EVERY_MS of vehicle time while
    on, driven by the vehicle's messages."""

    def __init__(self, c: Client):
        self.c = c
        self.pwm: list[int] | None = None
        self.sent_ms = -STICKS_EVERY_MS

    def __call__(self, msg) -> None:
        if self.pwm is not None and self.c.now_ms - self.sent_ms >= STICKS_EVERY_MS:
            self.send()

    def hold(self, *pwm: int) -> None:
        self.pwm = (list(pwm) + [LEAVE] * 8)[:8]
        self.send()

    def send(self) -> None:
        self.sent_ms = self.c.now_ms
        override(self.c, *self.pwm)

    def let_go(self) -> None:
        """Stop sending; the channels return to the receiver when RC_OVERRIDE_TIME runs out."""
        self.pwm = None


def wait_mode(c: Client, mode: int, sim_s: float = 5.0) -> bool:
    return c.try_wait(lambda: c.mode == mode, sim_s)


def mode_now(c: Client) -> int:
    c.fresh_heartbeat()
    return c.mode


# ----- the probes ------------------------------------------------------------------------------
def receiver_at_rest(c: Client, sticks: Sticks, t: Trace) -> None:
    t.fact("rc_channels", chans(c))
    t.fact("mode", mode_now(c))


def sysid(c: Client, sticks: Sticks, t: Trace) -> None:
    override(c, MID, MID, 1700, MID, sysid=245)
    c.idle(0.5)
    t.fact("override_from_245", chans(c)[1:5])
    override(c, MID, MID, 1700, MID)
    c.idle(0.5)
    t.fact("override_from_255", chans(c)[1:5])
    override(c, RELEASE, RELEASE, RELEASE, RELEASE)
    c.idle(0.5)
    manual_control(c, 500, -500, 800, 250, sysid=245)
    c.idle(0.5)
    t.fact("manual_control_from_245", chans(c)[1:5])
    manual_control(c, 500, -500, 800, 250, target=2)
    c.idle(0.5)
    t.fact("manual_control_to_system_2", chans(c)[1:5])
    manual_control(c, 500, -500, 800, 250)
    c.idle(0.5)
    t.fact("manual_control_from_255", chans(c)[1:5])
    manual_control(c, 0, 0, -100, 0)  # negative thrust: the whole message ignored
    c.idle(0.5)
    t.fact("manual_control_negative_z", chans(c)[1:5])
    manual_control(c, 32767, 32767, 32767, 32767)  # INT16_MAX: each axis released
    c.idle(0.5)
    t.fact("manual_control_released", chans(c)[1:5])
    t.fact("set_gcs_sysid", c.set_param("MAV_GCS_SYSID", 245))
    override(c, MID, MID, 1300, MID, sysid=245)
    c.idle(0.5)
    t.fact("override_from_245_as_gcs", chans(c)[1:5])
    override(c, MID, MID, 1800, MID)
    c.idle(0.5)
    t.fact("override_from_255_not_gcs", chans(c)[1:5])
    override(c, RELEASE, RELEASE, RELEASE, RELEASE, sysid=245)
    c.set_param("MAV_GCS_SYSID", 255)
    c.idle(0.5)
    t.fact("after", chans(c)[1:5])


def override_fields(c: Client, sticks: Sticks, t: Trace) -> None:
    override(c, 1600, 1400, 1200, 1700, LEAVE, 1300)
    c.idle(0.5)
    t.fact("set", chans(c))
    override(c, RELEASE, LEAVE, LEAVE, LEAVE)
    c.idle(0.5)
    t.fact("channel_1_released", chans(c))
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, ext=(1700,) + (0,) * 9)
    c.idle(0.5)
    t.fact("channel_9_set", chans(c)[9])
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, ext=(0,) * 10)
    c.idle(0.5)
    t.fact("channel_9_zero_leaves", chans(c)[9])
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, ext=(65534,) + (0,) * 9)
    c.idle(0.5)
    t.fact("channel_9_released", chans(c)[9])
    override(c, 1600, 1400, 1200, 1700)
    c.idle(2.0)
    t.fact("after_2s", chans(c))
    c.idle(2.0)
    t.fact("after_4s_lapsed", chans(c))


def alt_hold_sticks(c: Client, sticks: Sticks, t: Trace) -> None:
    reach_flying(c, 15.0)
    start = c.rel_alt_m()
    c.set_mode(ALT_HOLD)
    t.fact("mode", c.mode if wait_mode(c, ALT_HOLD) else None)
    c.idle(1.0)
    a1 = c.rel_alt_m()
    c.idle(3.0)
    a4 = c.rel_alt_m()
    t.fact("descends_without_override", a4 < start - 2.0)
    t.fact("descent_rate_m_s", (a1 - a4) / 3.0, RATE)
    sticks.hold(MID, MID, MID, MID)
    c.idle(3.0)
    held = c.rel_alt_m()
    c.idle(3.0)
    t.fact("height_change_at_mid_m", c.rel_alt_m() - held, HOLD)
    sticks.hold(MID, MID, 1800, MID)
    c.idle(1.0)
    b1 = c.rel_alt_m()
    c.idle(2.0)
    t.fact("climb_rate_m_s", (c.rel_alt_m() - b1) / 2.0, RATE)
    sticks.hold(MID, MID, MID, MID)
    c.set_mode(GUIDED)
    wait_mode(c, GUIDED)
    sticks.let_go()


def mode_switch(c: Client, sticks: Sticks, t: Trace) -> None:
    on_ground_disarmed(c)
    c.set_mode(STABILIZE)
    wait_mode(c, STABILIZE)
    seen = []
    for pwm in (1165, 1295, 1425, 1555, 1685, 1815, 1231, 1750, 2300):
        override(c, LEAVE, LEAVE, LEAVE, LEAVE, pwm)
        c.idle(SETTLE_S)
        seen.append(mode_now(c))
    t.fact("modes_by_pwm", seen)
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, 1295)  # LAND (FLTMODE2)
    c.idle(SETTLE_S)
    c.set_mode(GUIDED)
    wait_mode(c, GUIDED)
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, 1300)  # the same position
    c.idle(SETTLE_S)
    t.fact("gcs_mode_kept", mode_now(c))
    override(c, LEAVE, LEAVE, LEAVE, LEAVE, RELEASE)  # back to the receiver's 1800: FLTMODE6
    c.idle(SETTLE_S)
    t.fact("released", mode_now(c))


def aux_command(c: Client, sticks: Sticks, t: Trace) -> None:
    on_ground_disarmed(c)
    c.set_mode(LOITER)
    wait_mode(c, LOITER)
    start = c.now_ms
    results = {}
    for name, p1, p2 in (("rtl_high", 4, 2), ("rtl_low", 4, 0), ("land_high", 18, 2), ("land_middle", 18, 1),
                         ("smart_rtl_high", 42, 2), ("brake_high", 33, 2), ("position_3", 4, 3),
                         ("unknown_9999", 9999, 2), ("do_nothing_0", 0, 2), ("zigzag_savewp", 61, 0),
                         ("pause_high", 178, 2), ("camera_trigger", 9, 2), ("inverted_43", 43, 2),
                         ("camera_video_166", 166, 2), ("estop_high", 31, 2)):
        results[name] = [c.command(mav.MAV_CMD_DO_AUX_FUNCTION, p1, p2)]
        c.idle(0.5)
        results[name].append(mode_now(c))
    t.fact("results_and_modes", results)
    t.fact("said", said(c.texts_since(start)))  # what the commands alone made it say
    c.set_mode(GUIDED)
    wait_mode(c, GUIDED)
    arm_at = c.now_ms
    t.fact("arm_under_estop", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(1.0)
    t.fact("said_arming_under_estop", said(c.texts_since(arm_at)))
    t.fact("estop_low", c.command(mav.MAV_CMD_DO_AUX_FUNCTION, 31, 0))
    c.idle(0.5)
    t.fact("arm_after_estop", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(0.5)
    c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    c.try_wait(lambda: not c.armed, 3)


def aux_switch(c: Client, sticks: Sticks, t: Trace) -> None:
    t.fact("set_option", c.set_param("RC8_OPTION", 4))  # RTL on channel 8 (SITL's receiver: 1800, middle)
    reach_flying(c, 10.0)
    start = c.now_ms
    sticks.hold(MID, MID, MID, MID, LEAVE, LEAVE, LEAVE, HIGH)
    c.idle(SETTLE_S)
    t.fact("high", mode_now(c))
    sticks.hold(MID, MID, MID, MID, LEAVE, LEAVE, LEAVE, LOW)
    c.idle(SETTLE_S)
    t.fact("low", mode_now(c))  # out of RTL: the flight-mode switch's mode (FLTMODE6, STABILIZE)
    c.set_mode(GUIDED)
    wait_mode(c, GUIDED)
    sticks.hold(MID, MID, MID, MID, LEAVE, LEAVE, HIGH, LOW)  # RC7: SaveWaypoint (SITL's copter.parm)
    c.idle(SETTLE_S)
    t.fact("savewp_mode", mode_now(c))
    t.fact("said", said(c.texts_since(start)))
    sticks.let_go()
    override(c, RELEASE, RELEASE, RELEASE, RELEASE, RELEASE, RELEASE, RELEASE, RELEASE)
    c.set_param("RC8_OPTION", 0)
    c.set_mode(LAND)
    c.wait(lambda: not c.armed, 60, what="landed and disarmed")


def arming_throttle(c: Client, sticks: Sticks, t: Trace) -> None:
    on_ground_disarmed(c)
    results = {}
    for name, mode, pwm in (("alt_hold_1800", ALT_HOLD, 1800), ("alt_hold_1550", ALT_HOLD, 1550),
                            ("stabilize_1100", STABILIZE, 1100), ("guided_1800", GUIDED, 1800),
                            ("loiter_1800", LOITER, 1800)):
        sticks.hold(MID, MID, pwm, MID)
        c.set_mode(mode)
        wait_mode(c, mode)
        c.idle(0.5)
        at = c.now_ms
        result = c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
        c.idle(0.5)
        results[name] = [result, [x for x in said(c.texts_since(at)) if x.startswith("Arm")]]
        sticks.hold(MID, MID, LOW, MID)
        c.idle(0.3)
        if c.armed or result == mav.MAV_RESULT_ACCEPTED:
            c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
            c.try_wait(lambda: not c.armed, 3)
    t.fact("results", results)
    sticks.let_go()


def pilot_takeoff(c: Client, sticks: Sticks, t: Trace) -> None:
    on_ground_disarmed(c)
    sticks.hold(MID, MID, LOW, MID)
    c.set_mode(ALT_HOLD)
    wait_mode(c, ALT_HOLD)
    c.idle(0.5)
    t.fact("arm", c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1))
    c.idle(1.0)
    t.fact("on_ground_at_low_throttle", c.rel_alt_m() < 0.3)
    sticks.hold(MID, MID, 1800, MID)
    c.idle(2.0)
    a2 = c.rel_alt_m()
    c.idle(2.0)
    t.fact("climb_rate_m_s", (c.rel_alt_m() - a2) / 2.0, RATE)
    sticks.hold(MID, MID, MID, MID)
    c.set_mode(LAND)
    sticks.let_go()
    c.wait(lambda: not c.armed, 60, what="landed and disarmed")


def _failsafe_reaction(c: Client, t: Trace, prefix: str, fail: int, watch_s: float) -> None:
    """From a GUIDED hover: SIM_RC_FAIL = fail, then the reaction watched for watch_s."""
    reach_flying(c, 10.0)
    c.idle(1.0)
    path: list[tuple[int, float, int]] = []

    def record(msg) -> None:
        if msg.get_type() == "GLOBAL_POSITION_INT":
            path.append((c.now_ms, msg.relative_alt / 1000.0, c.mode))
    with c.listening(record):
        c.set_param("SIM_RC_FAIL", fail)
        at = c.now_ms  # the echo: the vehicle has it (a late client would otherwise count its own lag)
        c.wait(lambda: c.now_ms >= at + watch_s * 1000, watch_s + 10, what="the failsafe watched")
    # when it was said (the mode is only seen at the next 1 Hz HEARTBEAT)
    told = next(((ms - at) / 1000.0 for ms, _, text in c.texts if ms >= at and text.startswith("Radio Failsafe")),
                None)
    t.fact(f"{prefix}_said_after_s", told, REACTION)
    t.fact(f"{prefix}_mode", path[-1][2] if path else None)
    for s in (3, 6, 10):
        alt = next((a for ms, a, _ in path if ms >= at + s * 1000), None)
        t.fact(f"{prefix}_height_at_{s}s", alt, HEIGHT)
    t.fact(f"{prefix}_said", said(c.texts_since(at)))


def radio_failsafe(c: Client, sticks: Sticks, t: Trace) -> None:
    _failsafe_reaction(c, t, "no_pulses", 1, 12.0)
    at = c.now_ms
    c.set_param("SIM_RC_FAIL", 0)
    c.idle(2.0)
    t.fact("back_said", said(c.texts_since(at)))
    t.fact("back_mode", mode_now(c))
    t.fact("back_rc_channels", chans(c))
    c.set_mode(LAND)
    c.wait(lambda: not c.armed, 90, what="landed and disarmed")
    # the receiver's own failsafe values: throttle 950, the rest 1500; they stay after SIM_RC_FAIL 0
    _failsafe_reaction(c, t, "throttle_950", 2, 12.0)
    t.fact("throttle_950_rc_channels", chans(c))
    at = c.now_ms
    c.set_param("SIM_RC_FAIL", 0)
    c.idle(2.0)
    t.fact("throttle_950_back_said", said(c.texts_since(at)))
    t.fact("throttle_950_back_rc_channels", chans(c))


async def _manual_outcome(call) -> str:
    return await outcome(call, (ManualControlError,))


async def mavsdk_manual_control(url: str) -> Trace:
    t = Trace()
    mavsdk, system = await connect(url)
    telemetry, action, manual = TelemetryAsync(system), ActionAsync(system), ManualControlAsync(system)
    sticks = [0.0, 0.0, 0.5, 0.0]  # x, y, z (0..1, 0.5 mid), r as MAVSDK takes them

    async def stream():  # as MAVSDK's example: at least 10 Hz, kept up for the whole flight
        while True:
            await manual.set_manual_control_input(*sticks)
            await asyncio.sleep(0.02)
    streamer = asyncio.ensure_future(stream())
    try:
        await until(telemetry.subscribe_health(), lambda h: h.is_armable and h.is_home_position_ok, "armable")
        await asyncio.sleep(0.2)
        t.fact("start_altitude_control", await _manual_outcome(manual.start_altitude_control()))
        t.fact("mode", await mavsdk_mode(telemetry))
        t.fact("arm", await outcome(action.arm()))
        sticks[2] = 1.0  # throttle full up, for 4 s of vehicle time (10 Hz samples of its own stream)
        await telemetry.set_rate_position(10.0)
        top, samples = 0.0, 0
        async for p in telemetry.subscribe_position():
            top, samples = max(top, p.relative_altitude_m), samples + 1
            if samples >= 40:
                break
        t.fact("climbed_above_1m", top > 1.0)
        sticks[2] = 0.5
        t.fact("armed_after", await until(telemetry.subscribe_armed(), lambda a: True, "armed state"))
    except AssertionError as exc:
        print(f"pilot probe mavsdk_manual_control stopped: {exc}")
    finally:
        streamer.cancel()
        mavsdk.destroy()
    return t


PROBES = {
    "receiver_at_rest": receiver_at_rest, "sysid": sysid, "override_fields": override_fields,
    "alt_hold_sticks": alt_hold_sticks, "mode_switch": mode_switch, "aux_command": aux_command,
    "aux_switch": aux_switch, "arming_throttle": arming_throttle, "pilot_takeoff": pilot_takeoff,
    "radio_failsafe": radio_failsafe,
}


def run(target, names: list[str] | None = None) -> dict[str, Trace]:
    traces: dict[str, Trace] = {}
    c = target.boot()
    try:
        c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_RC_CHANNELS, RC_CHANNELS_US)
        sticks = Sticks(c)
        with c.listening(sticks):
            for name, probe in PROBES.items():
                if names is not None and name not in names:
                    continue
                trace = traces[name] = Trace()
                try:
                    probe(c, sticks, trace)
                except (ProbeTimeout, StopIteration, ArithmeticError, ValueError, KeyError) as exc:
                    print(f"pilot probe {name} stopped: {exc!r}")  # the facts after it are missing
                    sticks.let_go()
    finally:
        c.close()
        target.close()
    if names is None or "mavsdk_manual_control" in names:
        c = target.boot()  # a fresh vehicle whose port MAVSDK takes over
        url = c.url.replace("udpin:", "udpin://")
        c.close()
        try:
            traces["mavsdk_manual_control"] = asyncio.run(mavsdk_manual_control(url))
        finally:
            target.close()
    return traces
