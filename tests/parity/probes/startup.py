"""Start-up: what a vehicle says and refuses from power-on until it can arm, for clients that
"wait until armable". Firefly boots with --startup realistic here (its default is armable at
once); the reference boots as it always does.

Every TRY_EVERY_S of vehicle time the probe tries to arm in STABILIZE (until that works once)
and in GUIDED, disarming at once when an arm is accepted, and watches the GPS fix, home and the
EKF's absolute position flag. Facts: when each became true (vehicle seconds since boot), the
last words that refused an arm in each mode, and the start-up messages in the order said.
"""
from __future__ import annotations

import re

from ..client import Client, mav
from ..facts import Tol, Trace
from .states import GUIDED, STABILIZE

AREA = "startup"
TRY_EVERY_S = 2.0
LIMIT_S = 120.0
# Arm attempts every 2 s put a stage's moment up to 2 s late on either vehicle; the reference's
# own stages move by a few tenths from boot to boot.
WHEN_TOL = Tol(abs=3.0, why="attempts every 2 s, and boot-to-boot jitter of the reference")
# Words of the reference's simulated RC switch, and the pre-arm reminder it repeats every 30 s
# (which failure it names depends on the mode the probe happens to be in at that moment).
SIMULATOR_NOISE = [re.compile(p) for p in (r"^RC\d+: ", r"^PreArm: ")]
REPLY_WITHIN_S = 0.5


def _refusal(client: Client, t0_ms: int) -> str | None:
    texts = [t for t in client.texts_since(t0_ms)
             if t.startswith("Arm: ") and not any(p.search(t) for p in SIMULATOR_NOISE)]
    return texts[-1] if texts else None


def _try_arm(client: Client) -> tuple[bool, str | None]:
    t0 = client.now_ms
    result = client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1, sim_s=2.0)
    client.idle(REPLY_WITHIN_S)
    if result == mav.MAV_RESULT_ACCEPTED:
        client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0, sim_s=2.0)
        client.wait(lambda: not client.armed, 5, what="disarm")
        return True, None
    return False, _refusal(client, t0)


def run(target) -> dict[str, Trace]:
    when, last = Trace(), Trace()
    client = target.boot(streams_hz=None, realistic_startup=True)
    try:
        client.request_streams(4)
        seen: dict[str, float] = {}

        def watch(msg) -> None:
            kind, now = msg.get_type(), client.now_ms / 1000.0
            if kind == "GPS_RAW_INT" and msg.fix_type >= 3:
                seen.setdefault("gps_fix", now)
            elif kind == "HOME_POSITION":
                seen.setdefault("home", now)
            elif kind == "EKF_STATUS_REPORT" and msg.flags & mav.EKF_POS_HORIZ_ABS:
                seen.setdefault("ekf_position", now)

        refused = {"stabilize": None, "guided": None}
        with client.listening(watch):
            while "guided_armable" not in seen:
                if client.now_ms > LIMIT_S * 1000:
                    break
                next_try = client.now_ms + TRY_EVERY_S * 1000
                client.conn.mav.command_long_send(1, 1, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                                  mav.MAVLINK_MSG_ID_HOME_POSITION, 0, 0, 0, 0, 0, 0)
                for name, mode in (("stabilize", STABILIZE), ("guided", GUIDED)):
                    if f"{name}_armable" in seen:
                        continue
                    client.set_mode(mode)
                    client.wait(lambda: client.mode == mode, 5, what=name)
                    armed, words = _try_arm(client)
                    if armed:
                        seen[f"{name}_armable"] = client.now_ms / 1000.0
                    elif words:
                        refused[name] = words
                client.set_mode(STABILIZE)
                client.wait(lambda: client.now_ms >= next_try, TRY_EVERY_S + 5, what="the next try")
        for name in ("gps_fix", "home", "ekf_position", "stabilize_armable", "guided_armable"):
            when.fact(name, seen.get(name), WHEN_TOL)
        for name, words in refused.items():
            last.fact(name, words)
        said = [t for _, _, t in client.texts
                if not t.startswith("Arm: ") and t not in ("Arming motors", "Disarming motors")
                and not any(p.search(t) for p in SIMULATOR_NOISE)]
        last.fact("said", said)
    finally:
        target.close()
    return {"when": when, "last_refusal": last}
