"""Where a jump item sends the mission: DO_JUMP to an item's seq, DO_JUMP_TAG to the first
JUMP_TAG carrying its tag. AP_Mission turns a DO_JUMP_TAG into a DO_JUMP when it meets one, so
both count their repeats the same way (by the jump item's own index)."""
from __future__ import annotations

from ..c_casts import as_int16, as_uint16
from .commands import CMD_DO_JUMP, CMD_DO_JUMP_TAG, CMD_JUMP_TAG

JUMPS = frozenset({CMD_DO_JUMP, CMD_DO_JUMP_TAG})


def tag_index(items, tag: int) -> int | None:
    """The index of the first JUMP_TAG with this tag (AP_Mission's get_index_of_jump_tag), or None."""
    for index, item in enumerate(items):
        if item.command == CMD_JUMP_TAG and as_uint16(item.p1) == tag:
            return index
    return None


def jump_of(items, item) -> tuple[int, int] | None:
    """(target index, repeat count; negative: for ever) of a jump item; target -1 when it points
    nowhere (an unknown tag, a seq outside the list: AP_Mission ends its search there)."""
    if item.command == CMD_DO_JUMP:
        return as_uint16(item.p1) - 1, as_int16(item.p2)  # seq -> index
    if item.command == CMD_DO_JUMP_TAG:
        target = tag_index(items, as_uint16(item.p1))
        return -1 if target is None else target, as_int16(item.p2)
    return None
