"""Flight modes: one class each, and the one table of ArduCopter mode numbers."""
from .auto import Auto
from .base import Mode, Setpoint
from .guided import Guided
from .guided_nogps import GuidedNoGps
from .land import Land, Rtl
from .loiter import Brake, Loiter
from .manual import AltHold, Stabilize
from .numbers import ModeNumber
from .poshold import PosHold

MODE_CLASSES = (Stabilize, AltHold, Auto, Guided, Loiter, Rtl, Land, PosHold, Brake,
                GuidedNoGps)
MODE_BY_NUMBER: dict[int, type[Mode]] = {cls.number: cls for cls in MODE_CLASSES}
MODE_BY_NAME: dict[str, type[Mode]] = {cls.name: cls for cls in MODE_CLASSES}
assert set(MODE_BY_NUMBER) == set(ModeNumber), "every number in the table has its mode class"

__all__ = ["ModeNumber", "Mode", "Setpoint", "MODE_CLASSES", "MODE_BY_NUMBER", "MODE_BY_NAME",
           "Stabilize", "AltHold", "Auto", "Guided", "Loiter", "Rtl", "Land", "PosHold", "Brake",
           "GuidedNoGps"]
