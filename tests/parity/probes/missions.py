"""Mission progress as a client sees it: uploads, MISSION_START, AUTO entered and left, landing,
re-uploads, MIS_RESTART 0 and 1, MISSION_SET_CURRENT, DO_JUMP, a mission without takeoff, items in a
local frame, uploads refused part-way and fence and rally items.

Each scenario starts on a fresh vehicle and is a list of steps. Per step the facts are the ACK or
MISSION_ACK result where there is one, and what followed until the next step: the items reached
(MISSION_ITEM_REACHED), the mission texts ("Mission: 2 WP", "Reached command #2", ...), the
changes of MISSION_CURRENT's seq, and the state at the step's end (MISSION_CURRENT fields, mode,
armed), read from messages sent after it.
"""
from __future__ import annotations

import math

from ..client import Client, mav
from ..facts import Trace
from .states import AUTO, GUIDED, LAND, STABILIZE, mode_name, on_ground_disarmed

AREA = "missions"
REL = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
EARTH_M_PER_DEG = 111_195.0
MISSION_TEXTS = ("Mission: ", "Reached command", "Jump", "Skipping")


class Steps:
    """A scenario's steps on one client, each step's window summarised into facts."""

    def __init__(self, client: Client, trace: Trace):
        self.c, self.trace = client, trace
        self.n = 0
        self.name: str | None = None
        self.seq = client.last["MISSION_CURRENT"].seq  # the current item, as last held
        self.seq_seen = self.seq                         # the seq of the last MISSION_CURRENT
        client.log.clear()
        client.logging = True
        lat, lon = client.last["GLOBAL_POSITION_INT"].lat, client.last["GLOBAL_POSITION_INT"].lon
        self.home = (lat, lon)

    # ----- windows --------------------------------------------------------------------------
    def step(self, name: str) -> None:
        """Close the step in progress and open one named `name`, before its action is taken."""
        self.close()
        self.n += 1
        self.name = f"{self.n:02d} {name}"

    def result(self, value) -> None:
        self.trace.fact(f"{self.name}.result", value)

    def close(self) -> None:
        """Summarise the window of the step in progress, if any."""
        if self.name is None:
            return
        # The state at the window's end from messages sent after it (MISSION_CURRENT streams at
        # 10 Hz, HEARTBEAT at 1 Hz): what the vehicle is, not what it was a moment ago. The
        # MISSION_CURRENT after the heartbeat gives the two-beat rule below its second beat: an
        # item started just before the window closed (a waypoint's MISSION_ITEM_REACHED ends a
        # wait, its successor's first beat follows) otherwise counted here or in the next window
        # by where the 1 Hz heartbeat happened to fall, on either vehicle.
        self.c.fresh("MISSION_CURRENT", exact=True)
        self.c.fresh_heartbeat(exact=True)
        self.c.fresh("MISSION_CURRENT", exact=True)
        log = list(self.c.log)
        self.c.log.clear()
        texts = [m.text for _, m in log if m.get_type() == "STATUSTEXT" and m.text.startswith(MISSION_TEXTS)]
        # MISSION_CURRENT seqs as they changed, each held for two 10 Hz beats at least: an item
        # done within a beat (a takeoff at altitude) shows in one vehicle's stream and not the
        # other's by timing alone; the texts say it was started.
        changes: list[int] = []
        for _, m in log:
            if m.get_type() != "MISSION_CURRENT":
                continue
            if m.seq == self.seq_seen != self.seq:
                self.seq = m.seq
                changes.append(m.seq)
            self.seq_seen = m.seq
        cur = self.c.last["MISSION_CURRENT"]
        self.trace.fact(f"{self.name}.reached", [m.seq for _, m in log if m.get_type() == "MISSION_ITEM_REACHED"])
        self.trace.fact(f"{self.name}.texts", texts)
        self.trace.fact(f"{self.name}.current_changes", changes)
        self.trace.fact(f"{self.name}.current", [cur.seq, cur.total, cur.mission_state, cur.mission_mode])
        self.trace.fact(f"{self.name}.state", f"{mode_name(self.c.mode)}{' armed' if self.c.armed else ''}")
        self.name = None

    def finish(self) -> None:
        self.close()
        self.c.logging = False

    # ----- doing ----------------------------------------------------------------------------
    def command(self, name: str, command: int, *params) -> int | None:
        self.step(name)
        self.result(self.c.command(command, *params))

    def set_mode(self, mode: int) -> None:
        self.step(f"mode {mode_name(mode)}")
        self.result(self.c.set_mode(mode))

    def set_param(self, name: str, value: float) -> None:
        self.step(f"param {name}={value:g}")
        self.result(self.c.set_param(name, value))

    def arm(self) -> None:
        self.command("arm", mav.MAV_CMD_COMPONENT_ARM_DISARM, 1)
        self.c.wait(lambda: self.c.armed, 10, what="armed")

    def upload(self, items: list) -> None:
        self.step(f"upload {len(items)} items")
        self.result(upload(self.c, items))

    def set_current(self, seq: int) -> None:
        self.step(f"set current {seq}")
        self.c.conn.mav.mission_set_current_send(1, 1, seq)

    def drain(self, sim_s: float) -> None:
        self.c.idle(sim_s, exact=True)

    def wait(self, name: str, condition, sim_s: float = 120) -> None:
        """A step that is a wait: its window starts when the condition holds."""
        self.c.wait(condition, sim_s, what=name, exact=True)
        self.step(name)

    def seen(self, kind: str, condition):
        """A condition on messages of `kind` received from now on. It looks at each message once:
        a wait asks it after every message."""
        log, looked, held = self.c.log, [len(self.c.log)], [False]

        def holds() -> bool:
            start, looked[0] = looked[0], len(log)
            held[0] = held[0] or any(m.get_type() == kind and condition(m) for _, m in log[start:])
            return held[0]
        return holds

    def wait_reached(self, seq: int, sim_s: float = 120) -> None:
        self.wait(f"reached {seq}", self.seen("MISSION_ITEM_REACHED", lambda m: m.seq == seq), sim_s)

    def wait_current(self, seq: int) -> None:
        self.wait(f"current {seq}", self.seen("MISSION_CURRENT", lambda m: m.seq == seq))

    def wait_complete(self) -> None:
        self.wait("complete", self.seen("MISSION_CURRENT", lambda m: m.mission_state == mav.MISSION_STATE_COMPLETE))

    def wait_disarmed(self) -> None:
        self.wait("disarmed", lambda: not self.c.armed, 300)

    def land(self) -> None:
        self.set_mode(LAND)
        self.wait_disarmed()
        self.drain(3)

    def guided_takeoff(self, alt: float = 10.0) -> None:
        self.set_mode(GUIDED)
        self.arm()
        self.command("takeoff", mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt)
        self.wait("at altitude", lambda: self.c.rel_alt_m() > alt - 0.7, 90)

    # ----- geometry -------------------------------------------------------------------------
    def wp(self, n_m: float, e_m: float, alt: float = 10.0, command=mav.MAV_CMD_NAV_WAYPOINT):
        lat, lon = self.home
        dlat = n_m / EARTH_M_PER_DEG
        dlon = e_m / (EARTH_M_PER_DEG * math.cos(math.radians(lat * 1e-7)))
        return (command, REL, 0, 0, 0, 0, lat + int(dlat * 1e7), lon + int(dlon * 1e7), alt)


HOME_ITEM = (mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_INT, 0, 0, 0, 0, 0, 0, 0)  # a mission's seq 0


def send_item(client: Client, seq: int, item: tuple, kind: int) -> None:
    """MISSION_ITEM_INT `seq` of a list of `kind`, from (command, frame, p1..p4, x, y, z)."""
    c, f, p1, p2, p3, p4, x, y, z = item
    client.conn.mav.mission_item_int_send(1, 1, seq, f, c, 0, 1, p1, p2, p3, p4, x, y, z, kind)


def upload(client: Client, items: list | None, sim_s: float = 20.0,
           kind: int = mav.MAV_MISSION_TYPE_MISSION) -> int | None:
    """Upload items by MISSION_ITEM_INT, a mission's after a home item (seq 0) (None: MISSION_COUNT
    0, no home either); the MISSION_ACK type."""
    full = [] if items is None else ([HOME_ITEM] if kind == mav.MAV_MISSION_TYPE_MISSION else []) + list(items)
    answered: list = []

    def answer(msg):
        msg_kind = msg.get_type()
        if msg_kind in ("MISSION_REQUEST", "MISSION_REQUEST_INT") and msg.seq < len(full):
            send_item(client, msg.seq, full[msg.seq], kind)
        elif msg_kind == "MISSION_ACK":
            answered.append(msg.type)

    with client.listening(answer):
        client.conn.mav.mission_count_send(1, 1, len(full), kind)
        return answered[0] if client.try_wait(lambda: bool(answered), sim_s) else None


def takeoff(alt=10.0):
    return (mav.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 0, 0, 0, 0, alt)


def rtl():
    return (mav.MAV_CMD_NAV_RETURN_TO_LAUNCH, REL, 0, 0, 0, 0, 0, 0, 0)


def land_here():
    return (mav.MAV_CMD_NAV_LAND, REL, 0, 0, 0, 0, 0, 0, 0)


def jump(seq, repeat):
    return (mav.MAV_CMD_DO_JUMP, REL, seq, repeat, 0, 0, 0, 0, 0)


def change_speed(speed):
    return (mav.MAV_CMD_DO_CHANGE_SPEED, REL, 1, speed, -1, 0, 0, 0, 0)


# ----- scenarios -------------------------------------------------------------------------------
def reupload_after_landing(s: Steps) -> None:
    """Fly a mission, land (disarmed), upload a new one, take off in GUIDED, AUTO: flown from its
    first item, not resumed at the old index."""
    s.set_param("MIS_RESTART", 0)
    s.upload([takeoff(), s.wp(15, 0), rtl()])
    s.set_mode(GUIDED)
    s.arm()
    s.command("mission start", mav.MAV_CMD_MISSION_START)
    s.wait_disarmed()
    s.drain(3)
    s.upload([takeoff(), s.wp(0, 15), s.wp(15, 15), rtl()])
    s.drain(2)
    s.guided_takeoff()
    s.set_mode(AUTO)
    s.wait_reached(2)
    s.set_mode(GUIDED)
    s.drain(3)
    s.land()


def interrupted_resume(s: Steps, restart: int) -> None:
    """Leave AUTO mid-mission, come back, upload a new list while flying, come back again."""
    s.set_param("MIS_RESTART", restart)
    s.upload([takeoff(), s.wp(12, 0), s.wp(12, 12), s.wp(0, 12), rtl()])
    s.guided_takeoff()
    s.set_mode(AUTO)
    s.wait_reached(2)
    s.set_mode(GUIDED)
    s.drain(3)
    s.set_mode(AUTO)
    if restart:
        # from the start again: item 2 lies a few metres back, about 4 s away on both vehicles, so
        # the step waits for it rather than cutting a fixed window at its edge; then one second on
        # the 12 m leg to item 3, far from either end
        s.wait_reached(2)
        s.drain(1)
    else:
        s.drain(4)
    s.set_mode(GUIDED)
    s.drain(2)
    s.upload([takeoff(), s.wp(-10, 0), s.wp(-10, -10), s.wp(0, -10), s.wp(5, 5), rtl()])
    s.drain(2)
    s.set_mode(AUTO)
    s.drain(4)
    s.land()


def completed_then_auto(s: Steps) -> None:
    """A mission that ends in the air completes; MISSION_SET_CURRENT then; AUTO again restarts it."""
    s.set_param("MIS_RESTART", 0)
    s.upload([takeoff(), s.wp(10, 0)])
    s.guided_takeoff()
    s.set_mode(AUTO)
    s.wait_complete()
    s.drain(3)
    s.set_current(2)
    s.drain(3)
    s.set_mode(GUIDED)
    s.drain(2)
    s.set_mode(AUTO)
    s.drain(6)
    s.set_mode(GUIDED)
    s.drain(1)
    s.land()


def set_current(s: Steps) -> None:
    """MISSION_SET_CURRENT disarmed, flying in GUIDED, in AUTO; seq 0, out of range, a DO item."""
    s.set_param("MIS_RESTART", 0)
    s.upload([takeoff(), s.wp(10, 0), change_speed(3), s.wp(10, 30), s.wp(0, 30), rtl()])
    s.set_mode(STABILIZE)
    for seq in (4, 9, 3, 0):
        s.set_current(seq)
        s.drain(2)
    s.guided_takeoff()
    s.set_current(4)
    s.drain(2)
    s.set_mode(AUTO)
    s.wait_current(5)
    s.set_current(2)
    s.wait_current(4)
    s.set_current(0)
    s.wait_current(2)
    # Out of range while flying the 30 m leg to item 4 at 3 m/s, seconds from either end (the
    # windows before close on 1 Hz heartbeats: up to 4 s after the leg began), so that what the
    # window sees hangs neither on when the previous waypoint was reached nor on the next one.
    s.wait_current(4)
    s.set_current(9)
    s.drain(1)
    s.land()


def do_jump(s: Steps) -> None:
    """DO_JUMP twice back to a waypoint, with a DO_CHANGE_SPEED in the loop; ends with LAND."""
    s.set_param("MIS_RESTART", 0)
    s.upload([takeoff(), s.wp(6, 0), change_speed(4), s.wp(6, 6), jump(2, 2), s.wp(0, 0), land_here()])
    s.set_mode(GUIDED)
    s.arm()
    s.command("mission start", mav.MAV_CMD_MISSION_START)
    s.wait_disarmed()
    s.drain(4)


def no_takeoff(s: Steps) -> None:
    """A mission without takeoff: AUTO disarmed, MISSION_START armed on the ground (refused), then
    in the air; MISSION_START again once it completed starts it over."""
    s.set_param("MIS_RESTART", 0)
    s.set_mode(STABILIZE)
    s.upload([s.wp(8, 0), s.wp(8, 8)])
    s.drain(2)
    s.set_mode(AUTO)
    s.drain(3)
    s.set_mode(GUIDED)
    s.arm()
    s.command("mission start", mav.MAV_CMD_MISSION_START)
    s.command("takeoff", mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 10)
    s.wait("at altitude", lambda: s.c.rel_alt_m() > 9.3, 90)
    s.command("mission start", mav.MAV_CMD_MISSION_START)
    s.wait_complete()
    s.drain(2)
    s.command("mission start", mav.MAV_CMD_MISSION_START)
    s.wait_complete()
    s.drain(2)
    s.land()


def clear_and_download(s: Steps) -> None:
    """MISSION_CLEAR_ALL and a download (count, items' commands) before and after an upload."""
    s.step("download empty")
    s.result(download_commands(s.c))
    s.upload([takeoff(), s.wp(10, 0), jump(2, 1), rtl()])
    s.step("download after upload")
    s.result(download_commands(s.c))
    s.step("clear")
    s.result(clear(s.c))
    s.step("download after clear")
    s.result(download_commands(s.c))


def local_frame_items(s: Steps) -> None:
    """An item with a position in MAV_FRAME_LOCAL_NED (refused: a position is a latitude and
    longitude) and one without a position in that frame (taken)."""
    s.step("upload local NED waypoint")
    s.result(upload(s.c, [takeoff(), (mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_LOCAL_NED, 0, 0, 0, 0, 100_000, 0, -10)]))
    s.step("upload local NED change speed")
    s.result(upload(s.c, [takeoff(), (mav.MAV_CMD_DO_CHANGE_SPEED, mav.MAV_FRAME_LOCAL_NED, 1, 3, -1, 0, 0, 0, 0)]))
    s.step("download after")
    s.result(download_commands(s.c))


def partial_uploads(s: Steps) -> None:
    """An upload refused part-way over a longer mission, a home-only upload after a clear, an
    upload refused part-way after a clear, and MISSION_COUNT 0: what the list holds after each."""
    bad = (mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_LOCAL_NED, 0, 0, 0, 0, 100_000, 0, -10)
    s.upload([takeoff(), s.wp(10, 0, command=mav.MAV_CMD_NAV_LOITER_TIME), change_speed(3), s.wp(10, 10), rtl()])
    for name, action in (
            ("upload refused at item 2 of 4", lambda: upload(s.c, [s.wp(5, 0), bad, land_here()])),
            ("download after the refusal", lambda: download_commands(s.c)),
            ("clear", lambda: clear(s.c)),
            ("upload home only", lambda: upload(s.c, [])),
            ("download after home only", lambda: download_commands(s.c)),
            ("clear again", lambda: clear(s.c)),
            ("upload refused at item 2 after a clear", lambda: upload(s.c, [takeoff(), bad])),
            ("download after the refusal after a clear", lambda: download_commands(s.c)),
            ("upload count 0", lambda: upload(s.c, None)),
            ("download after count 0", lambda: download_commands(s.c)),
            ("upload home only after count 0", lambda: upload(s.c, [])),
            ("download at the end", lambda: download_commands(s.c))):
        s.step(name)
        s.result(action())


def fence_and_rally_items(s: Steps) -> None:
    """One-item fence and rally uploads, each list checking items by its own rules: the result of
    each, and the lists' lengths at the end."""
    lat, lon = s.home
    F, R = mav.MAV_MISSION_TYPE_FENCE, mav.MAV_MISSION_TYPE_RALLY
    G, REL_INT = mav.MAV_FRAME_GLOBAL_INT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
    cases = [
        ("fence circle", F, (mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, G, 100, 0, 0, 0, lat, lon, 0)),
        ("fence circle in MISSION frame", F, (mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, mav.MAV_FRAME_MISSION, 100, 0, 0, 0, lat, lon, 0)),
        ("fence waypoint", F, (mav.MAV_CMD_NAV_WAYPOINT, G, 0, 0, 0, 0, lat, lon, 0)),
        ("fence vertex count 300", F, (mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, G, 300, 0, 0, 0, lat, lon, 0)),
        ("rally point", R, (mav.MAV_CMD_NAV_RALLY_POINT, REL_INT, 0, 0, 0, 0, lat, lon, 40)),
        ("rally waypoint", R, (mav.MAV_CMD_NAV_WAYPOINT, REL_INT, 0, 0, 0, 0, lat, lon, 40)),
        ("rally at 40000 m", R, (mav.MAV_CMD_NAV_RALLY_POINT, REL_INT, 0, 0, 0, 0, lat, lon, 40_000)),
        ("rally in local NED", R, (mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_LOCAL_NED, 0, 0, 0, 0, lat, lon, 40)),
        ("rally at latitude 95", R, (mav.MAV_CMD_NAV_RALLY_POINT, REL_INT, 0, 0, 0, 0, 950_000_000, lon, 40)),
    ]
    for name, kind, item in cases:
        s.step(f"upload {name}")
        s.result(upload(s.c, [item], kind=kind))
    for name, kind in (("fence", F), ("rally", R)):
        s.step(f"download {name}")
        s.result(download_commands(s.c, kind=kind))


def fence_during_mission_upload(s: Steps) -> None:
    """A fence uploaded while a mission upload is under way (after its item 0, before item 1):
    each list's MISSION_ACK, and both lists after."""
    lat, lon = s.home
    lists = {
        mav.MAV_MISSION_TYPE_MISSION: [HOME_ITEM, takeoff(), s.wp(10, 0)],
        mav.MAV_MISSION_TYPE_FENCE: [(mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, mav.MAV_FRAME_GLOBAL_INT,
                                      100, 0, 0, 0, lat, lon, 0)],
    }
    acks: dict = {}
    fence_started: list = []

    def answer(msg):
        kind = msg.get_type()
        if kind in ("MISSION_REQUEST", "MISSION_REQUEST_INT") and msg.mission_type in lists:
            items = lists[msg.mission_type]
            if msg.mission_type == mav.MAV_MISSION_TYPE_MISSION and msg.seq == 1 and not fence_started:
                fence_started.append(True)  # the mission waits for item 1 while the fence goes up
                s.c.conn.mav.mission_count_send(1, 1, 1, mav.MAV_MISSION_TYPE_FENCE)
                return
            if msg.seq < len(items):
                send_item(s.c, msg.seq, items[msg.seq], msg.mission_type)
        elif kind == "MISSION_ACK":
            acks.setdefault(msg.mission_type, msg.type)

    s.step("upload a fence during a mission upload")
    with s.c.listening(answer):
        s.c.conn.mav.mission_count_send(1, 1, len(lists[0]), mav.MAV_MISSION_TYPE_MISSION)
        s.c.try_wait(lambda: len(acks) == 2, 20)
    s.result({"mission": acks.get(mav.MAV_MISSION_TYPE_MISSION), "fence": acks.get(mav.MAV_MISSION_TYPE_FENCE)})
    s.step("download mission")
    s.result(download_commands(s.c))
    s.step("download fence")
    s.result(download_commands(s.c, kind=mav.MAV_MISSION_TYPE_FENCE))


def download_commands(client: Client, sim_s: float = 10.0,
                      kind: int = mav.MAV_MISSION_TYPE_MISSION) -> list[int] | None:
    """MISSION_REQUEST_LIST and each item by MISSION_REQUEST_INT: the items' commands (a
    mission's home included), or None if the download stalled."""
    count: list = []
    items: dict[int, int] = {}

    def answer(msg):
        if msg.get_type() == "MISSION_COUNT" and msg.mission_type == kind:
            count.append(msg.count)
            if msg.count:
                client.conn.mav.mission_request_int_send(1, 1, 0, kind)
        elif msg.get_type() == "MISSION_ITEM_INT" and msg.mission_type == kind and count and msg.seq not in items:
            items[msg.seq] = msg.command
            if msg.seq + 1 < count[0]:
                client.conn.mav.mission_request_int_send(1, 1, msg.seq + 1, kind)
            else:
                client.conn.mav.mission_ack_send(1, 1, mav.MAV_MISSION_ACCEPTED, kind)

    with client.listening(answer):
        client.conn.mav.mission_request_list_send(1, 1, kind)
        done = client.try_wait(lambda: bool(count) and len(items) == count[0], sim_s)
        return [items[i] for i in sorted(items)] if done else None


def clear(client: Client, sim_s: float = 5.0) -> int | None:
    acks: list = []
    with client.listening(lambda msg: acks.append(msg.type) if msg.get_type() == "MISSION_ACK" else None):
        client.conn.mav.mission_clear_all_send(1, 1, mav.MAV_MISSION_TYPE_MISSION)
        return acks[0] if client.try_wait(lambda: bool(acks), sim_s) else None


SCENARIOS = {
    "reupload_after_landing": reupload_after_landing,
    "interrupted_resume_restart0": lambda s: interrupted_resume(s, 0),
    "interrupted_resume_restart1": lambda s: interrupted_resume(s, 1),
    "completed_then_auto": completed_then_auto,
    "set_current": set_current,
    "do_jump": do_jump,
    "no_takeoff": no_takeoff,
    "clear_and_download": clear_and_download,
    "local_frame_items": local_frame_items,
    "partial_uploads": partial_uploads,
    "fence_and_rally_items": fence_and_rally_items,
    "fence_during_mission_upload": fence_during_mission_upload,
}


def run(target) -> dict[str, Trace]:
    traces = {}
    try:
        for name, scenario in SCENARIOS.items():
            client = target.boot()
            for msg_id in (mav.MAVLINK_MSG_ID_MISSION_CURRENT, mav.MAVLINK_MSG_ID_GLOBAL_POSITION_INT):
                client.command(mav.MAV_CMD_SET_MESSAGE_INTERVAL, msg_id, 100_000)
            client.wait(lambda: "MISSION_CURRENT" in client.last and "GLOBAL_POSITION_INT" in client.last,
                        10, what="MISSION_CURRENT and position")
            on_ground_disarmed(client)
            trace = traces[name] = Trace()
            steps = Steps(client, trace)
            scenario(steps)
            steps.finish()
    finally:
        target.close()
    return traces
