"""Stored mission, fence and rally lists, saved atomically.

A list is replaced whole (`replace`), or item by item as an upload arrives (`truncate`, `put`,
then `changed` when the transfer ends), as ArduPilot writes mission and rally items to storage.

Items keep MAVLink's MISSION_ITEM_INT field meanings (command and frame numbers, x/y in 1e-7
degrees) because that is the language of mission files and ground stations; the store itself
knows nothing of the wire. For the mission list, index 0 is home, as in ArduPilot: what is stored
starts at seq 1 and the home item is made up when the list is read.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from ..io.persist import JsonFile, read_json

MISSION, FENCE, RALLY = 0, 1, 2


@dataclass(frozen=True)
class MissionItem:
    command: int
    frame: int
    p1: float = 0.0
    p2: float = 0.0
    p3: float = 0.0
    p4: float = 0.0
    x: int = 0  # latitude * 1e7 (or local x) as in MISSION_ITEM_INT
    y: int = 0  # longitude * 1e7
    z: float = 0.0
    autocontinue: int = 1


class MissionStore:
    def __init__(self, path: Path | None = None):
        self.path = path
        self._lists: dict[int, list[MissionItem]] = {MISSION: [], FENCE: [], RALLY: []}
        self.version = 0  # bumped on every change, so AUTO can notice a new mission
        self.file = JsonFile(path)  # a refused save: counted, the lists still hold the change
        if path is not None and path.exists():
            self._load(path)

    def _load(self, path: Path) -> None:
        try:
            lists = {int(k): [MissionItem(**item) for item in v] for k, v in read_json(path).items()}
        except (AttributeError, ValueError, TypeError):
            return  # unreadable: start empty; the next save writes a good file
        for kind in (MISSION, FENCE, RALLY):
            self._lists[kind] = lists.get(kind, [])

    def items(self, kind: int) -> list[MissionItem]:
        """Stored items. For MISSION these are seq 1..n (seq 0 is home)."""
        return list(self._lists[kind])

    def replace(self, kind: int, items: list[MissionItem]) -> bool:
        """Replace a whole list; whether it was saved."""
        self._lists[kind] = list(items)
        self.version += 1
        return self._save()

    def clear(self, kind: int) -> bool:
        return self.replace(kind, [])

    def truncate(self, kind: int, length: int) -> None:
        """Keep at most `length` items; a change AUTO sees at once, saved at `changed`."""
        if len(self._lists[kind]) > length:
            del self._lists[kind][length:]
            self.version += 1

    def put(self, kind: int, index: int, item: MissionItem) -> None:
        """Write `item` at `index`, over the item there or at the end; a change AUTO sees at
        once (as AP_Mission's change time moves with every write), saved at `changed`."""
        items = self._lists[kind]
        if index == len(items):
            items.append(item)
        else:
            items[index] = item
        self.version += 1

    def changed(self) -> bool:
        """After truncate and put, when the transfer ends: save (a process stopped mid-upload
        keeps the list it had); whether it was saved."""
        self.version += 1
        return self._save()

    def _save(self) -> bool:
        return self.file.save(lambda: {str(k): [asdict(i) for i in v] for k, v in self._lists.items()})
