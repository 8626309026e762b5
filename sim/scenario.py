"""Scenario files (TOML): the world a run takes place in — home, airframe, wind, sensor noise,
physics rate, seed, the recovery parachute's canopy, the fire world, the ground's hills ([[terrain]]), and the thermal camera
the vehicle carries, if any ([thermal_camera], ThermalCameraSpec's fields; the table present
fits one; its video_port key says where its video goes) — read the same way by the autopilot and the companion.

The tables that only the vehicle acts on ([script], [signing], [faults]) are kept as written in
`vehicle_tables`; the autopilot checks them (autopilot/cli/scenario.py). Every mistake is reported
as one ScenarioError line naming the file, the table and the key.
"""
from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path

from .airframe import Airframe
from .fire import FireWorld, world_from_tables
from .geo import GeoPoint
from .parachute import Canopy
from .sensors import NoiseConfig
from .thermal_camera import ThermalCameraSpec
from .terrain import Terrain, terrain_from_tables
from .traffic import tracks_from_tables
from .vehicle import SimConfig
from .wind import SteadyWind

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
    vehicle_tables: dict = dataclasses.field(default_factory=dict)  # VEHICLE_TABLES as written
    thermal_camera: ThermalCameraSpec | None = None  # [thermal_camera]: the camera fitted; None: none
    # [thermal_camera].video_port: the UDP port its live video goes to (+10 per instance); 0: no
    # video; None: the default (the autopilot's --video-port or 5600)
    video_port: int | None = None


def number(where: str, value, integer: bool = False):
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


def video_port(value, where: str) -> int:
    """A video port as a scenario or the command line gives it: 0 (no video) or 1..65535."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 65535:
        raise ScenarioError(f"{where}: expected a UDP port 1..65535 (0: no video), got {value!r}")
    return value


def _table_to(cls, table: dict, where: str):
    fields = {f.name: f for f in dataclasses.fields(cls)}
    values = {}
    for key, value in table.items():
        if key not in fields:
            raise ScenarioError(f"{where}: unknown key '{key}' (known: {', '.join(fields)})")
        values[key] = number(f"{where}.{key}", value, fields[key].type in ("int", int))
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


def read_toml(path: Path) -> dict:
    name = str(path)
    try:
        data = tomllib.loads(Path(path).read_text())
    except FileNotFoundError:
        raise ScenarioError(f"{name}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{name}: cannot read ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{name}: not valid TOML: {exc}") from None
    return data


def load_scenario(path: Path) -> Scenario:
    return scenario_from_dict(read_toml(path), str(path))


WORLD_TABLES = ("seed", "home", "airframe", "wind", "noise", "sim", "world", "fire", "traffic", "parachute",
                "thermal_camera", "terrain")
VEHICLE_TABLES = ("script", "signing", "faults", "startup", "params")  # what the vehicle acts on: checked by the autopilot
KNOWN_TABLES = WORLD_TABLES + VEHICLE_TABLES


def scenario_from_dict(data: dict, name: str = "scenario") -> Scenario:
    """The scenario `data` describes; the vehicle's own tables are kept, unread, in vehicle_tables."""
    if not isinstance(data, dict):
        raise ScenarioError(f"{name}: expected TOML tables")
    for key in data:
        if key not in KNOWN_TABLES:
            raise ScenarioError(f"{name}: unknown key '{key}' (known: {', '.join(KNOWN_TABLES)})")
    sc = Scenario()
    if "seed" in data:
        sc.seed = number(f"{name}: seed", data["seed"], integer=True)
    for key in ("home", "airframe", "wind", "noise", "sim", "parachute", "thermal_camera"):
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
        text = ",".join(str(number(f"{name}: [home].{k}", home[k])) for k in ("lat", "lon", "alt"))
        sc.home, _ = parse_home(text, f"{name}: [home]")
        sc.home_yaw_deg = number(f"{name}: [home].yaw", home.get("yaw", 0.0))
    airframe = _table_to(Airframe, data.get("airframe", {}), f"{name}: [airframe]")
    wind = _table_to(SteadyWind, data.get("wind", {}), f"{name}: [wind]")
    noise = _table_to(NoiseConfig, data.get("noise", {}), f"{name}: [noise]")
    canopy = _table_to(Canopy, data.get("parachute", {}), f"{name}: [parachute]")
    if "thermal_camera" in data:
        table = dict(data["thermal_camera"])
        if "video_port" in table:
            sc.video_port = video_port(table.pop("video_port"), f"{name}: [thermal_camera].video_port")
        sc.thermal_camera = _table_to(ThermalCameraSpec, table, f"{name}: [thermal_camera]")
    sim_table = data.get("sim", {})
    unknown = set(sim_table) - {"physics_rate_hz"}
    if unknown:
        raise ScenarioError(f"{name}: [sim] unknown key '{sorted(unknown)[0]}' (known: physics_rate_hz)")
    rate = number(f"{name}: [sim].physics_rate_hz", sim_table.get("physics_rate_hz", 400), integer=True)
    if rate not in (100, 200) and (rate < 400 or rate % 400):
        raise ScenarioError(f"{name}: [sim].physics_rate_hz must be 100, 200 or a multiple of 400, got {rate}")
    if "fire" in data and not isinstance(data["fire"], list):
        raise ScenarioError(f"{name}: fires are given as [[fire]] tables")
    try:
        sc.world = world_from_tables(data.get("world", {}), data.get("fire"), name)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    if sc.world.plume_rise_m_s > 0:
        if "wind_tilt" in data.get("world", {}) or "wind_to_deg" in data.get("world", {}):
            raise ScenarioError(f"{name}: [world].plume_rise_m_s leans the plume with [wind]; "
                                "give it or wind_tilt/wind_to_deg, not both")
        sc.world = dataclasses.replace(sc.world, wind_tilt=wind.speed_m_s / sc.world.plume_rise_m_s,
                                       wind_to_deg=(wind.from_direction_deg + 180.0) % 360.0)
    try:
        traffic = tracks_from_tables(data.get("traffic", []), name)
        terrain = terrain_from_tables(data.get("terrain", []), name)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    sc.sim = SimConfig(airframe=airframe, wind=wind, noise=noise, physics_rate_hz=rate, seed=sc.seed,
                       world=sc.world, traffic=traffic, canopy=canopy, terrain=terrain)
    sc.vehicle_tables = {key: data[key] for key in VEHICLE_TABLES if key in data}
    return sc
