"""Which fences are on: AC_Fence's enabled-fences mask. FENCE_ENABLE switches the configured ones
(FENCE_TYPE, less the floor) on or off when it changes; DO_FENCE_ENABLE, as a command or a mission
item, switches them at run time without touching the parameter (ArduCopter saves nothing either:
after a reboot FENCE_ENABLE rules again)."""
from __future__ import annotations

ALT_MAX, CIRCLE, POLYGON, ALT_MIN = 1, 2, 4, 8  # FENCE_TYPE bits (AC_FENCE_TYPE_*)
ALL_FENCES = ALT_MAX | CIRCLE | POLYGON | ALT_MIN
DISABLE, ENABLE, DISABLE_FLOOR = 0, 1, 2  # DO_FENCE_ENABLE's param 1 (AC_Fence::MavlinkFenceActions)
NAMES = ("Max Alt", "Circle", "Polygon", "Min Alt")  # by bit, as AC_Fence names them


def fence_names(fences: int) -> str:
    """AC_Fence's get_fence_names: "Max Alt, Circle and Polygon fences"."""
    names = [name for bit, name in enumerate(NAMES) if fences >> bit & 1]
    if not names:
        return ""
    listed = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return f"{listed} fence{'s' if len(names) > 1 else ''}"


class FenceSwitch:
    __slots__ = ("enabled_fences", "_enable_param")

    def __init__(self, params) -> None:
        self.enabled_fences = 0
        self._enable_param: float | None = None
        self.follow_param(params)

    @property
    def enabled(self) -> bool:
        return self.enabled_fences != 0

    def follow_param(self, params) -> None:
        """FENCE_ENABLE was (maybe) set: a change switches the configured fences (AC_Fence::update)."""
        value = params["FENCE_ENABLE"]
        if value != self._enable_param:
            self._enable_param = value
            self.enabled_fences = int(params["FENCE_TYPE"]) & ~ALT_MIN & ALL_FENCES if value else 0

    def enable(self, on: bool, fences: int, configured: int) -> int:
        """Switch `fences` (those of them configured) on or off; the ones that changed."""
        fences &= configured
        wanted = self.enabled_fences | fences if on else self.enabled_fences & ~fences
        changed = self.enabled_fences ^ wanted
        self.enabled_fences = wanted
        return changed

    # ----- DO_FENCE_ENABLE -----------------------------------------------------------------------
    def command(self, action: int, fences: int, configured: int, has_polygon: bool) -> bool:
        """The command (GCS_MAVLINK::handle_command_do_fence_enable): action 0 off, 1 on (refused
        when none of `fences` is present), 2 the floor off; `fences` 0 means all. False: FAILED."""
        fences = fences or ALL_FENCES
        if action == DISABLE:
            self.enable(False, fences, configured)
        elif action == ENABLE:
            present = configured & (ALT_MAX | CIRCLE | ALT_MIN | (POLYGON if has_polygon else 0))
            if not present & fences:
                return False
            self.enable(True, fences, configured)
        elif action == DISABLE_FLOOR:
            self.enable(False, ALT_MIN, configured)
        else:
            return False
        return True

    def mission_item(self, action: int, configured: int) -> str | None:
        """The mission item (AP_Mission::start_command_fence): every configured fence on or off,
        or the floor off; what AP_Mission says of it (None: nothing)."""
        if action == DISABLE:
            changed, verb = self.enable(False, configured, configured), "disabled"
        elif action == ENABLE:
            changed, verb = self.enable(True, configured, configured), "enabled"
        elif action == DISABLE_FLOOR:
            self.enable(False, ALT_MIN, configured)
            changed, verb = ALT_MIN, "disabled"  # said whether or not the floor was on
        else:
            return None
        return f"{fence_names(changed)} {verb}" if changed else None
