"""What AP_Mission says as it starts an item: "Mission: 3 WP", and for the items it runs itself
(RUN_BY_MISSION) the line their action adds ("Gripper Released")."""
from __future__ import annotations

from typing import Callable

from ..c_casts import as_uint16
from .commands import CMD_JUMP_TAG, command_name

GRIPPER_RELEASE, GRIPPER_GRAB = 0, 1  # DO_GRIPPER's param 2 (GRIPPER_ACTIONS)


def start_text(index: int, item) -> str:
    """AP_Mission's "Mission: <seq> <name>". A JUMP_TAG adds its Mission_Command's p1, which
    AP_Mission never fills for tags (the tag goes to the jump's target): always " 0"."""
    text = f"Mission: {index + 1} {command_name(item.command)}"
    return f"{text} 0" if item.command == CMD_JUMP_TAG else text


def _gripper(item) -> str | None:
    # said whether or not a gripper is fitted (GRIP_ENABLE 0): AP_Mission does not ask
    action = as_uint16(item.p2)
    return {GRIPPER_RELEASE: "Gripper Released", GRIPPER_GRAB: "Gripper Grabbed"}.get(action)


def _repeat_dist(item) -> str:
    return f"Resume repeat dist set to {as_uint16(item.p1)} m"


# MAV_CMD -> the text its start adds (None: nothing)
RUN_BY_MISSION_TEXTS: dict[int, Callable[[object], str | None]] = {
    211: _gripper,  # DO_GRIPPER
    215: _repeat_dist,  # DO_SET_RESUME_REPEAT_DIST
}
