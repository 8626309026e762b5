"""Mission progress: which item of the stored mission is current, whether the mission runs, and
which items were reached — the part of ArduPilot's AP_Mission that is not storage.

AUTO drives it (modes/auto.py), MISSION_SET_CURRENT and MISSION_START reach it through the
vehicle, and the MAVLink layer reports it (MISSION_CURRENT, MISSION_ITEM_REACHED). The index is
into the stored items, so item seq = index + 1 (seq 0 is home, as in ArduPilot).

AP_Mission's verbs and what they do here:
- stop():   nothing is flown until the mission is resumed (AP_Mission MISSION_STOPPED; reported
            as NOT_STARTED);
- resume(): run from the current item;
- start():  run from the first item;
- reset():  back to the first item, not running;
- pause():  a running mission was left (AUTO exited); MAVLink's PAUSED;
- complete(): the last item is done.
"""
from __future__ import annotations

from enum import Enum

from .store import MISSION


class MissionState(Enum):
    """MAVLink's MISSION_STATE names (NO_MISSION is reported for an empty list)."""
    NOT_STARTED = "NOT_STARTED"
    ACTIVE = "ACTIVE"
    PAUSED = "PAUSED"
    COMPLETE = "COMPLETE"


class MissionProgress:
    def __init__(self, store):
        self.store = store
        self.state = MissionState.NOT_STARTED
        self._index = 0
        self._reached: list[int] = []  # seqs reached since the MAVLink layer last asked

    # ----- the list and the current item -------------------------------------------------------
    def items(self) -> list:
        """The stored mission items (seq 1..n)."""
        return self.store.items(MISSION)

    @property
    def version(self) -> int:
        """Changes whenever a new list is stored, so AUTO can notice an upload."""
        return self.store.version

    @property
    def index(self) -> int:
        """Index into the stored items of the current item, within the list."""
        return min(self._index, max(len(self.store.items(MISSION)) - 1, 0))

    def current_seq(self) -> int:
        """The current item as MISSION_CURRENT numbers it; 0 without a mission."""
        return self.index + 1 if self.store.items(MISSION) else 0

    def set_index(self, index: int) -> None:
        self._index = index

    def set_current(self, seq: int) -> bool:
        """MISSION_SET_CURRENT: make item `seq` current; False (nothing changes) if there is none."""
        if not 1 <= seq <= len(self.store.items(MISSION)):
            return False
        self._index = seq - 1
        return True

    # ----- running -----------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        return self.state is MissionState.ACTIVE

    def stop(self) -> None:
        self.state = MissionState.NOT_STARTED

    def resume(self) -> None:
        self.state = MissionState.ACTIVE

    def start(self) -> None:
        self._index = 0
        self.state = MissionState.ACTIVE

    def reset(self) -> None:
        self._index = 0
        self.state = MissionState.NOT_STARTED

    def pause(self) -> None:
        if self.state is MissionState.ACTIVE:
            self.state = MissionState.PAUSED

    def complete(self) -> bool:
        """Mark the mission done; True if it was not already (so it is announced once)."""
        if self.state is MissionState.COMPLETE:
            return False
        self.state = MissionState.COMPLETE
        return True

    def prepare_start(self) -> None:
        """MISSION_START: a completed mission starts over from its first item; one that is not
        running waits to resume from its current item once AUTO may fly it."""
        if self.state is MissionState.COMPLETE:
            self.reset()
        elif self.state is not MissionState.ACTIVE:
            self.stop()

    # ----- reached items -----------------------------------------------------------------------
    def item_reached(self, index: int) -> None:
        self._reached.append(index + 1)

    @property
    def reached(self) -> list[int]:
        """Seqs reached and not yet reported, oldest first."""
        return list(self._reached)

    def drain_reached(self) -> list[int]:
        reached, self._reached = self._reached, []
        return reached
