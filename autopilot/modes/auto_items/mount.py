"""The gimbal's mission items, as ArduCopter's AUTO and AP_Mission run them: done as they start.

DO_MOUNT_CONTROL: params 1-3 pitch, roll, yaw [deg] (body-frame yaw), whatever the mode in z;
where the gimbal cannot pan the vehicle turns by the yaw instead (ModeAuto::do_mount_control).
DO_GIMBAL_MANAGER_PITCHYAW: params 1 / 2 pitch and yaw [deg], used when within 90 and 360, else
3 / 4 their rates [deg/s] when neither is NaN, x the flags (retract, neutral, yaw lock), z the
gimbal (0 the first); neither: passed over (AP_Mission's start_command_do_gimbal_manager_pitchyaw).
With no gimbal (or naming another) both still run, and nothing moves. The ROI items are roi.py's.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ...c_casts import as_uint8
from ...payload.mount import F_NEUTRAL, F_RETRACT, F_YAW_LOCK, NEUTRAL, RETRACT
from ..guided_yaw import FIXED, SLEW_YAW_DEFAULT_CDEG_S
from . import AutoItem

if TYPE_CHECKING:
    from ...mission.store import MissionItem
    from ..auto import Auto
    from ..context import ModeContext

DO_MOUNT_CONTROL = 205


class MountItem(AutoItem):
    def start(self, auto: Auto, ctx: ModeContext, index: int, item: MissionItem) -> bool:
        mount = ctx.mount
        if item.command == DO_MOUNT_CONTROL:
            if mount.fitted and not mount.has_pan_control() and math.isfinite(item.p3):
                _turn_by(auto, ctx, item.p3)
            if mount.fitted:
                mount.set_angle_target(item.p2, item.p1, item.p3, False)
            return True
        gimbal = as_uint8(item.z)
        # another gimbal: none there (ArduPilot's null backend), and the item still runs
        target = mount if mount.fitted and gimbal <= 1 else None
        flags = int(item.x) & 0xFFFFFFFF
        lock = bool(flags & F_YAW_LOCK)
        if flags & (F_RETRACT | F_NEUTRAL):
            if target is not None:
                target.set_mode(RETRACT if flags & F_RETRACT else NEUTRAL)
        elif abs(item.p1) <= 90 and abs(item.p2) <= 360:  # NaN fails both
            if target is not None:
                target.set_angle_target(0.0, item.p1, item.p2, lock)
        elif not math.isnan(item.p3) and not math.isnan(item.p4):
            if target is not None:
                target.set_rate_target(0.0, item.p3, item.p4, lock)
        else:
            return False
        return True


def _turn_by(auto: Auto, ctx: ModeContext, offset_deg: float) -> None:
    """AutoYaw::set_yaw_angle_offset_deg: the heading AUTO steers to, turned by this much for the
    leg (the turn slewed at ATC_SLEW_YAW, as CONDITION_YAW's)."""
    heading = auto.heading
    heading.angle = auto.heading_target(ctx)
    heading.kind = FIXED
    slew_max = math.radians(ctx.params.get("ATC_SLEW_YAW", SLEW_YAW_DEFAULT_CDEG_S) / 100.0)
    heading.set_fixed(heading.angle, math.radians(abs(offset_deg)), 0.0, 1 if offset_deg >= 0 else -1, True, slew_max)
