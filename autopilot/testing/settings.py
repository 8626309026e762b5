"""What a test asks of its vehicle: `@pytest.mark.firefly(...)` over the run's command-line defaults.

Every key is checked here, before any process starts, so that a mistake fails that test at setup
with one line naming the marker and the key.
"""
from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

MAX_COUNT = 1000  # vehicles one test may ask for (past 255, the autopilot runs a process per 255)
MAX_AIRBORNE_M = 500.0


class SettingsError(ValueError):
    """A marker key or a command-line option that cannot be used, said in one line."""


@dataclass(frozen=True)
class FireflySettings:
    speedup: float = 10.0
    scenario: Path | None = None
    home: str | None = None  # "LAT,LON,ALT[,YAW]", as autopilot --home takes it
    seed: int = 0
    params: dict = field(default_factory=dict)  # set over MAVLink before the test, in this order
    faults: dict = field(default_factory=dict)  # SIM_* parameters, set like params, after them
    count: int = 1
    airborne: float | None = None  # metres: armed and hovering at this height in GUIDED before the test
    startup: str = "instant"  # or "realistic": boot as ArduCopter does

    @property
    def speedup_text(self) -> str:
        return "inf" if math.isinf(self.speedup) else f"{self.speedup:g}"


KEYS = tuple(FireflySettings.__dataclass_fields__)


def seed_for(test_identity: str) -> int:
    """A seed from the test's identity: the same test always flies the same noise, two tests differ."""
    return zlib.crc32(test_identity.encode()) & 0x7FFF_FFFF


def parse_speedup(value, where: str) -> float:
    if isinstance(value, str) and value.strip().lower() == "inf":
        return math.inf
    try:
        if isinstance(value, bool):  # float(True) is 1.0: a flag is not a speed
            raise TypeError
        speedup = float(value)
    except (TypeError, ValueError):
        raise SettingsError(f"{where}: expected a positive number or 'inf', got {value!r}") from None
    if not speedup > 0:
        raise SettingsError(f"{where}: expected a positive number or 'inf', got {value!r}")
    return speedup


def _number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SettingsError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def _params(value, where: str, sim_only: bool) -> dict:
    if not isinstance(value, dict):
        raise SettingsError(f"{where}: expected a dict of parameter names to numbers, got {value!r}")
    checked = {}
    for name, v in value.items():
        if not isinstance(name, str) or not name or len(name) > 16:
            raise SettingsError(f"{where}: {name!r} is not a parameter name (1 to 16 characters)")
        if sim_only and not name.startswith("SIM_"):
            raise SettingsError(f"{where}: {name} is not a SIM_* parameter (faults are SIM_*; use params=)")
        checked[name] = _number(v, f"{where}[{name!r}]")
    return checked


def _home(value, where: str) -> str:
    parts = value.split(",") if isinstance(value, str) else value
    try:
        numbers = [float(x) for x in parts]
    except (TypeError, ValueError):
        raise SettingsError(f"{where}: expected (lat, lon, alt[, yaw]), got {value!r}") from None
    if len(numbers) not in (3, 4) or not all(math.isfinite(x) for x in numbers):
        raise SettingsError(f"{where}: expected (lat, lon, alt[, yaw]), got {value!r}")
    if not (-90 <= numbers[0] <= 90 and -180 <= numbers[1] <= 180):
        raise SettingsError(f"{where}: latitude must be in -90..90 and longitude in -180..180, got {value!r}")
    return ",".join(repr(x) for x in numbers)


def settings(marker_kwargs: dict, defaults: FireflySettings, test_dir: Path, marker_args: tuple = ()) -> FireflySettings:
    """The settings of one test: `defaults` (the command line's) with the marker's keys applied."""
    where = "@pytest.mark.firefly"
    if marker_args:
        raise SettingsError(f"{where}: takes keywords only ({', '.join(KEYS)}), got {marker_args!r}")
    unknown = sorted(set(marker_kwargs) - set(KEYS))
    if unknown:
        raise SettingsError(f"{where}: unknown key {unknown[0]!r} (known: {', '.join(KEYS)})")
    changes: dict[str, Any] = {}  # FireflySettings fields, each of its own type
    for key, value in marker_kwargs.items():
        at = f"{where}({key}=...)"
        if key == "speedup":
            changes[key] = parse_speedup(value, at)
        elif key == "scenario":
            path = Path(value) if isinstance(value, (str, Path)) else None
            if path is None:
                raise SettingsError(f"{at}: expected a path to a scenario TOML file, got {value!r}")
            path = path if path.is_absolute() else test_dir / path
            if not path.is_file():
                raise SettingsError(f"{at}: no scenario file {path}")
            changes[key] = path
        elif key == "home":
            changes[key] = _home(value, at)
        elif key == "seed":
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2 ** 31:
                raise SettingsError(f"{at}: expected an integer in 0..2**31-1, got {value!r}")
            changes[key] = value
        elif key in ("params", "faults"):
            changes[key] = _params(value, at, sim_only=key == "faults")
        elif key == "count":
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_COUNT:
                raise SettingsError(f"{at}: expected an integer in 1..{MAX_COUNT}, got {value!r}")
            changes[key] = value
        elif key == "airborne":
            height = _number(value, at) if value is not None else None
            if height is not None and not 1.0 <= height <= MAX_AIRBORNE_M:
                raise SettingsError(f"{at}: expected a height in 1..{MAX_AIRBORNE_M:g} m, got {value!r}")
            changes[key] = height
        elif key == "startup":
            if value not in ("instant", "realistic"):
                raise SettingsError(f"{at}: expected 'instant' or 'realistic', got {value!r}")
            changes[key] = value
    return replace(defaults, **changes)
