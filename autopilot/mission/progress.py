"""Mission progress: which item of the stored mission is current, whether the mission runs, and
which items were reached — the part of ArduPilot's AP_Mission that is not storage.

AUTO drives it (modes/auto.py): it binds a runner that starts and verifies items, and calls
start_or_resume() when it begins and update() every tick. MISSION_SET_CURRENT and MISSION_START
reach it through the vehicle; disarming resets it (as ArduCopter's disarm does); the MAVLink
layer reports it (MISSION_CURRENT, MISSION_ITEM_REACHED). Indexes are into the stored items, so
item seq = index + 1 (seq 0 is home, as in ArduPilot).

AP_Mission's rules, as the reference vehicle shows them:
- the current item is always a navigation item (or none: reported as seq 0); "do" items run
  alongside the navigation item they precede, one at a time;
- stop(): AUTO was left; the current item is kept (reported NOT_STARTED);
- reset(): no current item, jump counts cleared; the state is left as it is (disarming does this,
  so a landed vehicle resumes a mission from its first item);
- resume(): a completed mission, or one without a current item, starts over; otherwise the
  current item is started again — also after a new list was uploaded, if that index still exists;
- start_or_resume(): MIS_RESTART = 1 starts over, 0 resumes;
- set_current(seq): in a running mission the item starts at once; otherwise it becomes the item
  a resume starts from (seq 0 means the first item; a completed mission's jumps are cleared);
- DO_SET_RESUME_REPEAT_DIST: a resume first flies back over the last metres flown (rewind.py).
"""
from __future__ import annotations

from enum import Enum

from ..c_casts import as_uint16
from .commands import CMD_DO_SET_RESUME_REPEAT_DIST, RUN_BY_MISSION, is_nav, is_takeoff
from .jumps import JUMPS, jump_of, tag_index
from .own_items import RUN_BY_MISSION_TEXTS, start_text
from .rewind import RETURNED, WaypointHistory
from .store import MISSION

MAX_ADVANCE = 255  # items looked at in one advance (AP_Mission's guard against endless loops)
MAX_JUMPS_FOLLOWED = 64  # jumps followed looking for one item


class MissionState(Enum):
    """AP_Mission's states by MAVLink's MISSION_STATE names (NO_MISSION: an empty list)."""
    NOT_STARTED = "NOT_STARTED"  # AP_Mission MISSION_STOPPED
    ACTIVE = "ACTIVE"  # MISSION_RUNNING
    COMPLETE = "COMPLETE"


# What a runner's verify_command answers (truthy) for an item done without a MISSION_ITEM_REACHED:
# ArduCopter's NAV_LOITER_TO_ALT returns from its verify before the report.
DONE_UNREPORTED = "done, unreported"


class NullRunner:
    """What runs items while AUTO has not bound itself: nothing starts, nothing completes."""

    def start_command(self, index: int, item) -> bool:
        return False

    def verify_command(self, index: int, item) -> bool:
        return False

    def mission_complete(self) -> None:
        pass


class MissionProgress:
    def __init__(self, store, notify=lambda text: None):
        self.store = store
        self.notify = notify  # a STATUSTEXT at INFO ("Mission: 2 WP")
        self.runner = NullRunner()
        self.state = MissionState.NOT_STARTED
        self.nav_index: int | None = None
        self.nav_loaded = False
        self.do_index: int | None = None
        self.do_loaded = False
        self.do_all_done = False
        self._jumps: dict[int, int] = {}  # DO_JUMP index -> times followed
        self._reached: list[int] = []  # seqs reached since the MAVLink layer last asked
        self.repeat_dist_m = 0  # DO_SET_RESUME_REPEAT_DIST's metres (0: a resume does not rewind)
        self.history = WaypointHistory()
        # Where AUTO was when the mission last stopped (lat, lon in 1e-7 degrees): AUTO sets it
        # as it is left, where AP_Mission notes it on every update while running.
        self.exit_e7: tuple[float, float] | None = None

    # ----- the list and the current item -------------------------------------------------------
    def jumps_followed(self) -> dict[int, int]:
        """DO_JUMP index -> times followed so far (the waypoint navigator looks ahead with it)."""
        return self._jumps

    def items(self) -> list:
        """The stored mission items (seq 1..n)."""
        return self.store.items(MISSION)

    def current_seq(self) -> int:
        """The current navigation item as MISSION_CURRENT numbers it; 0 when there is none."""
        return 0 if self.nav_index is None else self.nav_index + 1

    def status(self) -> tuple[int, int, MissionState]:
        """(current_seq(), len(items()), state): what MISSION_CURRENT reports (inlined: asked often)."""
        return 0 if self.nav_index is None else self.nav_index + 1, len(self.store.items(MISSION)), self.state

    @property
    def running(self) -> bool:
        return self.state is MissionState.ACTIVE

    def bind(self, runner) -> None:
        """The runner (AUTO) that starts and verifies items and is told of completion."""
        self.runner = runner

    # ----- AP_Mission's verbs ------------------------------------------------------------------
    def stop(self) -> None:
        self.state = MissionState.NOT_STARTED

    def reset(self) -> None:
        self.nav_index, self.nav_loaded = None, False
        self.do_index, self.do_loaded, self.do_all_done = None, False, False
        self._jumps.clear()
        self._forget_history()

    def _forget_history(self) -> None:
        """AP_Mission's reset_wp_history: the rewind's history and its distance go."""
        self.history.clear()
        self.repeat_dist_m = 0

    def start(self) -> None:
        self.state = MissionState.ACTIVE
        self.reset()
        if not self._advance_nav():
            self.complete()

    def resume(self) -> None:
        if self.state is MissionState.COMPLETE:
            self.start()
            return
        if self.state is MissionState.NOT_STARTED:
            self.state = MissionState.ACTIVE
            if self.nav_index is None:
                self.start()
                return
        if self.nav_index is not None and self.nav_index >= len(self.items()):
            self.start()  # the item belonged to a longer list uploaded before this one
            return
        rewound = self.history.rewind(self.items(), self.exit_e7, self.repeat_dist_m)
        if rewound is not None and self._start(*rewound):
            self.nav_index, self.nav_loaded = rewound[0], True
            self.history.resuming = True
            return
        if self.do_loaded and self.do_index is not None:
            self._set_current_index(self.do_index)
        elif self.nav_loaded and self.nav_index is not None:
            self._set_current_index(self.nav_index)

    def start_or_resume(self, restart: bool) -> None:
        if restart:
            self.start()
        else:
            self.resume()

    def complete(self) -> None:
        self.state = MissionState.COMPLETE
        self.runner.mission_complete()

    def set_current(self, seq: int) -> bool:
        """MISSION_SET_CURRENT / DO_SET_MISSION_CURRENT; False (refused) for a seq not in the list."""
        items = self.items()
        if not 0 <= seq <= len(items) or not items:
            return False
        if seq == 0 or self.state is MissionState.COMPLETE:
            self._jumps.clear()
        return self._set_current_index(max(seq, 1) - 1)

    def jump_to_tag(self, tag: int) -> bool:
        """DO_JUMP_TAG sent as a command: set_current to the first JUMP_TAG with `tag`; False
        (refused) when no item carries it."""
        index = tag_index(self.items(), tag)
        return index is not None and self.set_current(index + 1)

    def restart_current_nav(self) -> bool:
        """Start the current navigation item again (a new list arrived while it was flown)."""
        if not self.running or self.nav_index is None or self.nav_index >= len(self.items()):
            return False
        return self._set_current_index(self.nav_index)

    def starts_with_takeoff(self, restart: bool) -> bool:
        """Whether the mission flies a takeoff first (from the current item unless it restarts)."""
        items = self.items()
        index = 0 if restart or self.nav_index is None else self.nav_index
        for item in items[index:]:
            if is_nav(item.command):
                return is_takeoff(item.command)
        return False

    # ----- running -----------------------------------------------------------------------------
    def update(self) -> None:
        """One step of a running mission: verify the current items, move on when they are done."""
        if self.state is not MissionState.ACTIVE or not self.items():
            return
        if not self.nav_loaded or self.nav_index is None:
            if not self._advance_nav():
                self.complete()
                return
        elif self._verify(self.nav_index):
            self.nav_loaded = False
            if not self._advance_nav():
                self.complete()
                return
        if not self.do_loaded:
            self._advance_do()
        elif self.do_index is not None and self._verify(self.do_index):
            self.do_loaded = False

    def _verify(self, index: int) -> bool:
        items = self.items()
        if index >= len(items):
            return False
        if items[index].command in RUN_BY_MISSION:  # done when started; never reported reached
            return True
        done = self.runner.verify_command(index, items[index])
        if not done:
            return False
        if done != DONE_UNREPORTED:
            self._reached.append(index + 1)
        return True

    def _start(self, index: int, item) -> bool:
        self.notify(start_text(index, item))
        if item.command == CMD_DO_SET_RESUME_REPEAT_DIST:
            self.repeat_dist_m = as_uint16(item.p1)
        said = RUN_BY_MISSION_TEXTS.get(item.command)
        if said is not None and (text := said(item)) is not None:
            self.notify(text)
        return self.runner.start_command(index, item)

    def _set_current_index(self, index: int) -> bool:
        items = self.items()
        if index >= len(items):
            return False
        self._forget_history()  # as AP_Mission's set_current_cmd
        self.do_index, self.do_loaded, self.do_all_done = None, False, False
        self.nav_loaded = False
        if self.state is not MissionState.ACTIVE:
            # Not running: find the item a resume starts from, start nothing. Bounded as
            # _advance_nav is: "do" items and an unlimited DO_JUMP back to them, with no
            # navigation item, would otherwise be searched (and their jumps counted) for ever.
            for _ in range(MAX_ADVANCE):
                if self.nav_loaded:
                    break
                found = self._next_item(index, count_jumps=True)
                if found is None:
                    break
                if is_nav(items[found].command):
                    self.nav_index, self.nav_loaded = found, True
                elif not self.do_loaded:
                    self.do_index, self.do_loaded = found, True
                index = found + 1
            if not self.nav_loaded:
                self.nav_index = None
                return False
            self.do_all_done = not self.do_loaded
            self.state = MissionState.NOT_STARTED
            return True
        if not self._advance_nav(index):
            self.complete()
            return False
        return True

    def _advance_nav(self, from_index: int | None = None) -> bool:
        """Make the next navigation item current and start it (and the first "do" item on the
        way); False when the list is done."""
        if self.state is not MissionState.ACTIVE or self.nav_loaded:
            return False
        self.do_index, self.do_loaded, self.do_all_done = None, False, False
        if from_index is not None:
            index = from_index
        else:
            index = 0 if self.nav_index is None else self.nav_index + 1
        items = self.items()
        for _ in range(MAX_ADVANCE):
            found = self._next_item(index, count_jumps=True)
            if found is None:
                return False
            item = items[found]
            if is_nav(item.command):
                self.nav_index = found
                self.nav_loaded = self._start(found, item)
                if self.history.loaded(found, item, self.repeat_dist_m):
                    self.notify(RETURNED)
            elif not self.do_loaded:
                self.do_index, self.do_loaded = found, True
                self._start(found, item)
            index = found + 1
            if self.nav_loaded:
                self.do_all_done = not self.do_loaded
                return True
        return False

    def _advance_do(self) -> None:
        """Start the next "do" item before the next navigation item, if there is one."""
        if self.state is not MissionState.ACTIVE or self.do_all_done:
            return
        index = 0 if self.do_index is None else self.do_index + 1
        found = self._next_item(index, count_jumps=False)
        if found is None or is_nav(self.items()[found].command):
            self.do_all_done = True
            return
        self.do_index, self.do_loaded = found, True
        self._start(found, self.items()[found])

    def _next_item(self, index: int, count_jumps: bool) -> int | None:
        """The first item at or after `index` that is not a DO_JUMP, following the jumps still
        due (and counting them when the mission moves on, with AP_Mission's "Jump n/m" text)."""
        items = self.items()
        first_jump = None
        followed = 0
        while index < len(items):
            item = items[index]
            if item.command not in JUMPS:
                return index
            followed += 1
            target, repeat = jump_of(items, item) or (-1, 0)
            if followed > MAX_JUMPS_FOLLOWED or not 0 <= target < len(items):
                return None
            if not count_jumps and first_jump == index:
                return None  # a loop of jumps that can never finish
            first_jump = index if first_jump is None else first_jump
            done = self._jumps.get(index, 0)
            if repeat < 0 or done < repeat:
                if count_jumps:
                    self._jumps[index] = done + 1
                    limit = "unlimited" if repeat < 0 else str(repeat)
                    self.notify(f"Mission: {index + 1} Jump {done + 1}/{limit}")
                index = target
            else:
                if count_jumps:
                    self._jumps[index] = 0  # a loop run to its end counts again if flown again
                index += 1
        return None

    # ----- reached items -----------------------------------------------------------------------
    @property
    def has_reached(self) -> bool:
        """Whether an item was reached and not yet reported."""
        return bool(self._reached)

    @property
    def reached(self) -> list[int]:
        """Seqs reached and not yet reported, oldest first."""
        return list(self._reached)

    def report_reached(self, seq: int) -> None:
        """An item reached outside the mission (GUIDED's waypoint, which ArduCopter reports as 0)."""
        self._reached.append(seq)

    def drain_reached(self) -> list[int]:
        reached, self._reached = self._reached, []
        return reached
