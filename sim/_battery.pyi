"""The compiled battery step (_battery.c over battery.h): the twin of battery.step_battery_at."""
from .battery import BatteryState

def step(state: BatteryState, omega: tuple[float, ...], constants: tuple[float, ...], /) -> BatteryState: ...
