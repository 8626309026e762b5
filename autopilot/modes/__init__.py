"""Flight modes: one class each, and the one table of ArduCopter mode numbers."""
from .acro import Acro
from .auto import Auto
from .autotune import AutoTune
from .base import Mode, Setpoint
from .drift import Drift
from .flip import Flip
from .flowhold import FlowHold
from .follow import Follow
from .guided import Guided
from .land import Land, Rtl
from .loiter import Brake, Loiter
from .manual import AltHold, Stabilize
from .numbers import ModeNumber
from .poshold import PosHold
from .systemid import SystemId
from .throw import Throw
from .turtle import Turtle

MODE_CLASSES = (Stabilize, AltHold, Auto, Guided, Loiter, Rtl, Land, PosHold, Brake,
                Acro, Drift, Flip, AutoTune, Throw, FlowHold, Follow, SystemId, Turtle)
MODE_BY_NUMBER: dict[int, type[Mode]] = {cls.number: cls for cls in MODE_CLASSES}
MODE_BY_NAME: dict[str, type[Mode]] = {cls.name: cls for cls in MODE_CLASSES}
assert set(MODE_BY_NUMBER) == set(ModeNumber), "every number in the table has its mode class"

__all__ = ["ModeNumber", "Mode", "Setpoint", "MODE_CLASSES", "MODE_BY_NUMBER", "MODE_BY_NAME",
           "Stabilize", "AltHold", "Auto", "Guided", "Loiter", "Rtl", "Land", "PosHold", "Brake",
           "Acro", "Drift", "Flip", "AutoTune", "Throw", "FlowHold", "Follow", "SystemId", "Turtle"]
