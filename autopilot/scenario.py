"""Scenario files (TOML): home, airframe, wind, sensor noise, seed, faults to start with.

Every mistake is reported as one ScenarioError line naming the file, the table and the key.
"""
from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path

from sim.airframe import Airframe
from sim.fire import FireWorld, world_from_tables
from sim.sensors import NoiseConfig
from sim.vehicle import SimConfig
from sim.wind import SteadyWind

from .faults import world_values
from .geo import GeoPoint
from .params import SPEC_BY_NAME, ParamError, checked_value

DEFAULT_HOME = (-35.363261, 149.165230, 584.0, 0.0)  # ArduPilot SITL's CMAC field, Canberra


class ScenarioError(ValueError):
    pass


@dataclasses.dataclass
class Scenario:
    home: GeoPoint = dataclasses.field(default_factory=lambda: GeoPoint(*DEFAULT_HOME[:3]))
    home_yaw_deg: float = DEFAULT_HOME[3]
    seed: int = 0
    sim: SimConfig = dataclasses.field(default_factory=SimConfig)
    world: FireWorld = dataclasses.field(default_factory=FireWorld)
    script: list = dataclasses.field(default_factory=list)  # (time_s, verb, args) steps
    signing_key: bytes | None = None  # MAVLink 2 signing key ([signing] or --signing-key)
    faults: dict = dataclasses.field(default_factory=dict)  # SIM_* parameter values from [faults]


def _number(where: str, value, integer: bool = False):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            (integer and not isinstance(value, int)):
        raise ScenarioError(f"{where}: expected {'an integer' if integer else 'a number'}, got {value!r}")
    try:
        finite = math.isfinite(value)
    except OverflowError:
        finite = False
    if not finite:
        raise ScenarioError(f"{where}: must be finite and of sensible size")
    return value


def _table_to(cls, table: dict, where: str):
    fields = {f.name: f for f in dataclasses.fields(cls)}
    values = {}
    for key, value in table.items():
        if key not in fields:
            raise ScenarioError(f"{where}: unknown key '{key}' (known: {', '.join(fields)})")
        values[key] = _number(f"{where}.{key}", value, fields[key].type in ("int", int))
    try:
        obj = cls(**values)
        if hasattr(obj, "validate"):
            obj.validate()
    except ValueError as exc:
        raise ScenarioError(f"{where}: {exc}") from None
    return obj


def parse_home(text: str, where: str = "--home") -> tuple[GeoPoint, float]:
    parts = text.split(",")
    if len(parts) not in (3, 4):
        raise ScenarioError(f"{where}: expected LAT,LON,ALT[,YAW], got {text!r}")
    try:
        values = [float(p) for p in parts] + ([0.0] if len(parts) == 3 else [])
    except ValueError:
        raise ScenarioError(f"{where}: expected numbers in LAT,LON,ALT[,YAW], got {text!r}") from None
    home = GeoPoint(*values[:3])
    try:
        home.validate()
    except ValueError as exc:
        raise ScenarioError(f"{where}: {exc}") from None
    if not math.isfinite(values[3]):
        raise ScenarioError(f"{where}: yaw must be finite")
    return home, values[3]


def load_scenario(path: Path) -> Scenario:
    name = str(path)
    try:
        data = tomllib.loads(Path(path).read_text())
    except FileNotFoundError:
        raise ScenarioError(f"{name}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{name}: cannot read ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{name}: not valid TOML: {exc}") from None
    return scenario_from_dict(data, name, Path(path).parent)


KNOWN_TABLES = ("seed", "home", "airframe", "wind", "noise", "sim", "world", "fire", "script", "signing",
                "faults")
FAULT_NAMES = tuple(name for name in SPEC_BY_NAME if name.startswith("SIM_"))
# SIM_* values the scenario's own tables give, and where a scenario sets them instead of [faults].
WORLD_SOURCES = {"SIM_WIND_SPD": "[wind].speed_m_s", "SIM_WIND_DIR": "[wind].from_direction_deg",
                 "SIM_BATT_VOLTAGE": "[airframe].battery_cells"}


def scenario_from_dict(data: dict, name: str = "scenario", base_dir: Path = Path(".")) -> Scenario:
    """The scenario `data` describes; `base_dir` is where relative file names (key_file) start."""
    for key in data:
        if key not in KNOWN_TABLES:
            raise ScenarioError(f"{name}: unknown key '{key}' (known: {', '.join(KNOWN_TABLES)})")
    sc = Scenario()
    if "seed" in data:
        sc.seed = _number(f"{name}: seed", data["seed"], integer=True)
    for key in ("home", "airframe", "wind", "noise", "sim"):
        if key in data and not isinstance(data[key], dict):
            raise ScenarioError(f"{name}: [{key}] must be a table")
    home = data.get("home", {})
    if home:
        unknown = set(home) - {"lat", "lon", "alt", "yaw"}
        if unknown:
            raise ScenarioError(f"{name}: [home] unknown key '{sorted(unknown)[0]}' (known: lat, lon, alt, yaw)")
        missing = {"lat", "lon", "alt"} - set(home)
        if missing:
            raise ScenarioError(f"{name}: [home] missing '{sorted(missing)[0]}'")
        text = ",".join(str(_number(f"{name}: [home].{k}", home[k])) for k in ("lat", "lon", "alt"))
        sc.home, _ = parse_home(text, f"{name}: [home]")
        sc.home_yaw_deg = _number(f"{name}: [home].yaw", home.get("yaw", 0.0))
    airframe = _table_to(Airframe, data.get("airframe", {}), f"{name}: [airframe]")
    wind = _table_to(SteadyWind, data.get("wind", {}), f"{name}: [wind]")
    noise = _table_to(NoiseConfig, data.get("noise", {}), f"{name}: [noise]")
    sim_table = data.get("sim", {})
    unknown = set(sim_table) - {"physics_rate_hz"}
    if unknown:
        raise ScenarioError(f"{name}: [sim] unknown key '{sorted(unknown)[0]}' (known: physics_rate_hz)")
    rate = _number(f"{name}: [sim].physics_rate_hz", sim_table.get("physics_rate_hz", 400), integer=True)
    if rate not in (100, 200) and (rate < 400 or rate % 400):
        raise ScenarioError(f"{name}: [sim].physics_rate_hz must be 100, 200 or a multiple of 400, got {rate}")
    if "fire" in data and not isinstance(data["fire"], list):
        raise ScenarioError(f"{name}: fires are given as [[fire]] tables")
    try:
        sc.world = world_from_tables(data.get("world", {}), data.get("fire"), name)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    sc.sim = SimConfig(airframe=airframe, wind=wind, noise=noise, physics_rate_hz=rate, seed=sc.seed,
                       world=sc.world)
    for param, value in world_values(sc.sim).items():
        try:
            checked_value(param, value)
        except ParamError as exc:
            raise ScenarioError(f"{name}: {WORLD_SOURCES[param]}: {exc}") from None
    if "faults" in data:
        sc.faults = _faults(data["faults"], name)
    if "script" in data:
        from .script import ScriptError, parse_steps
        table = data["script"]
        if not isinstance(table, dict) or set(table) != {"steps"}:
            raise ScenarioError(f"{name}: [script] must hold exactly one key, steps")
        try:
            sc.script = parse_steps(table["steps"], name)
        except ScriptError as exc:
            raise ScenarioError(str(exc)) from None
    if "signing" in data:
        sc.signing_key = _signing_key(data["signing"], name, base_dir)
    return sc


def _faults(table, name: str) -> dict:
    """[faults]: SIM_* parameters by their names, set before the vehicle first moves."""
    if not isinstance(table, dict):
        raise ScenarioError(f"{name}: [faults] must be a table")
    faults = {}
    for key, value in table.items():
        where = f"{name}: [faults].{key}"
        if key not in FAULT_NAMES:
            raise ScenarioError(f"{where}: unknown fault (known: {', '.join(FAULT_NAMES)})")
        if key in WORLD_SOURCES:
            raise ScenarioError(f"{where}: the scenario sets this with {WORLD_SOURCES[key]}")
        _number(where, value)
        try:
            faults[key] = checked_value(key, value)
        except ParamError as exc:
            raise ScenarioError(f"{where}: {str(exc).removeprefix(key + ': ')}") from None
    return faults


def _signing_key(table, name: str, base_dir: Path) -> bytes:
    """[signing] holds exactly one of key (the text of a key file) or key_file (a path)."""
    from .signing_keys import SigningKeyError, key_from_text, read_key_file
    if not isinstance(table, dict) or len(table) != 1 or not set(table) <= {"key", "key_file"}:
        raise ScenarioError(f"{name}: [signing] must hold exactly one key: key or key_file")
    (field, value), = table.items()
    if not isinstance(value, str):
        raise ScenarioError(f"{name}: [signing].{field}: expected a string, got {value!r}")
    try:
        return key_from_text(value) if field == "key" else read_key_file(base_dir / value)
    except SigningKeyError as exc:
        shown = f" {value}" if field == "key_file" else ""  # never echo a secret
        raise ScenarioError(f"{name}: [signing].{field}{shown}: {exc}") from None
