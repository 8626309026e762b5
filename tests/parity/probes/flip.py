"""FLIP flown as a pilot flies it: hovering in ALT_HOLD with the throttle stick at mid by RC
override (ArduCopter SITL's own receiver holds it at the bottom), the mode switched to FLIP with
the sticks centred (a roll to the right) and with the pitch stick held back (a back flip). Read
off the ATTITUDE stream at 50 Hz, in vehicle time from the ACK: how far it turned, its peak rate,
how long until it was back within 5 degrees of level, the height it lost on the way, and the
mode it handed back to."""
from __future__ import annotations

import math

from ..client import Client, ProbeTimeout, mav
from ..facts import Tol, Trace
from .states import ALT_HOLD, GUIDED, on_ground_disarmed, reach_flying

AREA = "flip"
FLIP = 14
MID, BACK, LOW = 1500, 1900, 1000  # PWM: centred; the pitch stick pulled back (channel 2 high); bottom
STICKS_EVERY_MS = 100  # vehicle time between overrides: well inside RC_OVERRIDE_TIME
ATTITUDE_US = 20_000  # ATTITUDE at 50 Hz while flipping
SETTLE_S = 2.0
ARMABLE_WITHIN_S = 30.0
STICK_SETTLE_S = 0.3
WATCH_S = 4.0  # after the ACK: a flip hands back within 2.5 s or gives up
OVER_DEG = 90.0
LEVEL_DEG = 5.0

TURN = Tol(abs=15.0, why="how far past 90 degrees the reading goes at 50 Hz samples")
RATE = Tol(abs=60.0, rel=0.25, why="peak rotation rate: both ask 400 deg/s; the attitude target's lead and "
                                   "the rate loops' response differ")
DURATION = Tol(abs=0.3, rel=0.3, why="time to roll over and recover: airframes and controllers differ")
HEIGHT = Tol(abs=1.5, why="height lost while inverted: the throttle curves and thrust differ")


class Sticks:
    """Sends RC_CHANNELS_OVERRIDE with these PWMs every STICKS_EVERY_MS of vehicle time, driven
    by the vehicle's own messages (so a client reading a batch late still keeps it fresh)."""

    def __init__(self, c: Client):
        self.c = c
        self.pwm = [MID, MID, LOW, MID]  # throttle down until flying: ArduCopter arms only so
        self.sent_ms = -STICKS_EVERY_MS

    def __call__(self, msg) -> None:
        if self.c.now_ms - self.sent_ms >= STICKS_EVERY_MS:
            self.send()

    def send(self) -> None:
        self.sent_ms = self.c.now_ms
        self.c.conn.mav.rc_channels_override_send(1, 1, *self.pwm, 0, 0, 0, 0)


def hover(c: Client) -> None:
    """Hovering in GUIDED; arming is retried while the checks still refuse (a fresh vehicle)."""
    if not (c.armed and c.rel_alt_m() > 2.0):
        on_ground_disarmed(c)
        c.set_mode(GUIDED)
        c.wait(lambda: c.mode == GUIDED, 5, what="GUIDED")
        start = c.now_ms
        while c.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) != mav.MAV_RESULT_ACCEPTED:
            if c.now_ms - start > ARMABLE_WITHIN_S * 1000:
                raise ProbeTimeout(f"not armable: {c.texts_since(start)[-3:]}")
            c.idle(1.0)
        c.wait(lambda: c.armed, 5, what="armed")
    reach_flying(c)


def flip(c: Client, sticks: Sticks, trace: Trace, pitch_pwm: int) -> None:
    """From a hover in ALT_HOLD at mid throttle: FLIP with the pitch stick at pitch_pwm."""
    hover(c)
    sticks.pwm[2] = MID  # mid throttle: ALT_HOLD holds the height
    sticks.send()
    c.set_mode(ALT_HOLD)
    c.wait(lambda: c.mode == ALT_HOLD, 3, what="ALT_HOLD")
    c.idle(SETTLE_S)
    sticks.pwm[1] = pitch_pwm
    sticks.send()
    log: list[tuple[int, object]] = []
    by_pitch = pitch_pwm != MID

    def record(msg) -> None:
        if msg.get_type() in ("ATTITUDE", "HEARTBEAT", "GLOBAL_POSITION_INT", "STATUSTEXT", "COMMAND_ACK"):
            log.append((c.now_ms, msg))
    with c.listening(record):
        c.idle(STICK_SETTLE_S)  # the stick read, and the height before the flip logged
        sent = c.now_ms
        trace.fact("result", c.set_mode(FLIP))
        # The vehicle time of the answer, not of when this client read it (behind a fast vehicle)
        acked = next((t for t, m in log if m.get_type() == "COMMAND_ACK" and m.command == mav.MAV_CMD_DO_SET_MODE),
                     sent)
        c.wait(lambda: c.now_ms >= acked + WATCH_S * 1000, WATCH_S + 5, what="the flip watched")
    before = [m for t, m in log if m.get_type() == "GLOBAL_POSITION_INT" and t <= acked]
    start_alt = before[-1].relative_alt / 1000.0 if before else c.rel_alt_m()
    sticks.pwm[1] = MID
    sticks.send()
    attitude = [(t, m) for t, m in log if m.get_type() == "ATTITUDE" and t >= acked]
    # (time, the flipping axis's angle, the roll): a back flip also reads as a roll through 180
    angles = [(t, math.degrees(m.pitch if by_pitch else m.roll), math.degrees(m.roll)) for t, m in attitude]
    trace.fact("turned_past_90", max((abs(roll) for _, _, roll in angles), default=0.0) > OVER_DEG)
    rates = [abs(math.degrees(m.pitchspeed if by_pitch else m.rollspeed)) for _, m in attitude]
    trace.fact("peak_rate_deg_s", max(rates, default=0.0), RATE)
    over = next((t for t, _, roll in angles if abs(roll) > OVER_DEG), None)
    back = None if over is None else next(
        (t for t, a, roll in angles if t > over and abs(a) < LEVEL_DEG and abs(roll) < OVER_DEG), None)
    trace.fact("back_level_after_s", None if back is None else (back - acked) / 1000.0, DURATION)
    positions = [(t, m) for t, m in log if m.get_type() == "GLOBAL_POSITION_INT" and t <= (back or acked)]
    end_alt = positions[-1][1].relative_alt / 1000.0 if positions else start_alt
    trace.fact("height_change_m", end_alt - start_alt, HEIGHT)
    beats = [m for t, m in log if m.get_type() == "HEARTBEAT" and t >= acked + WATCH_S * 1000 - 1500]
    trace.fact("mode_after", beats[-1].custom_mode if beats else None)
    trace.fact("said", [m.text for t, m in log if m.get_type() == "STATUSTEXT" and t >= acked])


def run(target) -> dict[str, Trace]:
    traces = {"roll_right_from_alt_hold": Trace(), "back_flip_from_alt_hold": Trace()}
    c = target.boot()
    try:
        sticks = Sticks(c)
        with c.listening(sticks):
            c.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, mav.MAVLINK_MSG_ID_ATTITUDE, ATTITUDE_US)
            flip(c, sticks, traces["roll_right_from_alt_hold"], MID)
            flip(c, sticks, traces["back_flip_from_alt_hold"], BACK)
    finally:
        target.close()
    return traces
