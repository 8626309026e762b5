"""What AP_Mission says as it starts an item: "Mission: 3 WP", and for the items it runs itself
(RUN_BY_MISSION) the line their action adds ("Resume repeat dist set to 5 m"; DO_GRIPPER's, after
the gripper's own, is said by AUTO's item: modes/auto_items/payload.py)."""
from __future__ import annotations

from typing import Callable

from ..c_casts import as_uint16
from .commands import CMD_JUMP_TAG, command_name


def start_text(index: int, item) -> str:
    """AP_Mission's "Mission: <seq> <name>". A JUMP_TAG adds its Mission_Command's p1, which
    AP_Mission never fills for tags (the tag goes to the jump's target): always " 0"."""
    text = f"Mission: {index + 1} {command_name(item.command)}"
    return f"{text} 0" if item.command == CMD_JUMP_TAG else text


def _repeat_dist(item) -> str:
    return f"Resume repeat dist set to {as_uint16(item.p1)} m"


# MAV_CMD -> the text its start adds (None: nothing)
RUN_BY_MISSION_TEXTS: dict[int, Callable[[object], str | None]] = {
    215: _repeat_dist,  # DO_SET_RESUME_REPEAT_DIST
}
