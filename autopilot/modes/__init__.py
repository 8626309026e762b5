"""Flight modes: one class each, and the one table of ArduCopter mode numbers."""
from .acro import Acro
from .auto import Auto
from .auto_rtl import AutoRtl
from .autotune import AutoTune
from .avoid_adsb import AvoidAdsb
from .base import Mode, Setpoint
from .circle import Circle
from .drift import Drift
from .flip import Flip
from .flowhold import FlowHold
from .follow import Follow
from .guided import Guided
from .guided_nogps import GuidedNoGps
from .land import Land, Rtl
from .loiter import Brake, Loiter
from .manual import AltHold, Stabilize
from .numbers import ModeNumber
from .poshold import PosHold
from .smart_rtl import SmartRtl
from .systemid import SystemId
from .throw import Throw
from .turtle import Turtle
from .zigzag import ZigZag

MODE_CLASSES = (Stabilize, AltHold, Auto, Guided, Loiter, Rtl, Land, PosHold, Brake,
                Acro, Drift, Flip, AutoTune, Throw, FlowHold, Follow, SystemId, Turtle,
                Circle, AvoidAdsb, SmartRtl, ZigZag, AutoRtl, GuidedNoGps)
MODE_BY_NUMBER: dict[int, type[Mode]] = {cls.number: cls for cls in MODE_CLASSES}
MODE_BY_NAME: dict[str, type[Mode]] = {cls.name: cls for cls in MODE_CLASSES}
assert set(MODE_BY_NUMBER) == set(ModeNumber), "every number in the table has its mode class"

__all__ = ["ModeNumber", "Mode", "Setpoint", "MODE_CLASSES", "MODE_BY_NUMBER", "MODE_BY_NAME",
           "Stabilize", "AltHold", "Auto", "Guided", "Loiter", "Rtl", "Land", "PosHold", "Brake",
           "Acro", "Drift", "Flip", "AutoTune", "Throw", "FlowHold", "Follow", "SystemId", "Turtle",
           "Circle", "AvoidAdsb", "SmartRtl", "ZigZag", "AutoRtl", "GuidedNoGps"]
