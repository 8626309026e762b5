"""The scenario tables the vehicle acts on, on top of the world that sim/scenario.py reads:
[faults] (SIM_* parameters to start with), [params] (other parameters, saved before the first
boot as `autopilot --param` saves them), [script] (commands in sim time), [signing] (the
MAVLink 2 key) and [startup] (boot as ArduCopter does instead of armable at once). Every mistake is one ScenarioError line naming the file, the table and the key.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

from firefly.sim import scenario as world
from firefly.sim.scenario import DEFAULT_HOME, ScenarioError, parse_home  # noqa: F401 - the CLI's names

from ..faults.world import world_values
from ..params import SPEC_BY_NAME, ParamError, checked_value
from ..params_differences import OLD_NAMES
from ..startup import StartupTimeline

# the modelled faults, and ArduPilot 4.5's names of those 4.7 renamed
FAULT_NAMES = tuple(name for name in (*SPEC_BY_NAME, *OLD_NAMES) if name.startswith("SIM_"))
# SIM_* values the scenario's own tables give, and where a scenario sets them instead of [faults].
WORLD_SOURCES = {"SIM_WIND_SPD": "[wind].speed_m_s", "SIM_WIND_DIR": "[wind].from_direction_deg",
                 "SIM_BATT_VOLTAGE": "[airframe].battery_cells"}


@dataclasses.dataclass
class Scenario(world.Scenario):
    script: list = dataclasses.field(default_factory=list)  # (time_s, verb, args) steps
    signing_key: bytes | None = None  # MAVLink 2 signing key ([signing] or --signing-key)
    faults: dict = dataclasses.field(default_factory=dict)  # SIM_* parameter values from [faults]
    startup: StartupTimeline | None = None  # [startup] or --startup realistic; None = armable at once
    params: dict = dataclasses.field(default_factory=dict)  # [params]: saved before the first boot


def load_scenario(path: Path) -> Scenario:
    return scenario_from_dict(world.read_toml(path), str(path), Path(path).parent)


def scenario_from_dict(data: dict, name: str = "scenario", base_dir: Path = Path(".")) -> Scenario:
    """The scenario `data` describes; `base_dir` is where relative file names (key_file) start."""
    base = world.scenario_from_dict(data, name)
    sc = Scenario(**{f.name: getattr(base, f.name) for f in dataclasses.fields(world.Scenario)})
    for param, value in world_values(sc.sim).items():
        try:
            checked_value(param, value)
        except ParamError as exc:
            raise ScenarioError(f"{name}: {WORLD_SOURCES[param]}: {exc}") from None
    data = sc.vehicle_tables
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
    if "startup" in data:
        sc.startup = startup_from_table(data["startup"], f"{name}: [startup]")
    if "params" in data:
        sc.params = _params(data["params"], name)
    return sc


STARTUP_TIMES = tuple(f.name for f in dataclasses.fields(StartupTimeline))


def startup_from_table(table, where: str) -> StartupTimeline | None:
    """[startup]: realistic = true (the default when the table is there) boots as ArduCopter does,
    each stage at its measured time unless the table gives it (e.g. gps_in_use_s = 20)."""
    if not isinstance(table, dict):
        raise ScenarioError(f"{where} must be a table")
    times = {}
    for key, value in table.items():
        if key == "realistic":
            if not isinstance(value, bool):
                raise ScenarioError(f"{where}.realistic: expected true or false, got {value!r}")
            continue
        if key not in STARTUP_TIMES:
            raise ScenarioError(f"{where}.{key}: unknown key (known: realistic, {', '.join(STARTUP_TIMES)})")
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f"{where}.{key}: expected seconds, got {value!r}")
        times[key] = float(value)
    if not table.get("realistic", True):
        return None
    try:
        return StartupTimeline(**times)
    except ValueError as exc:
        raise ScenarioError(f"{where}: {exc}") from None


def _params(table, name: str) -> dict:
    """[params]: parameters by their names and values, as a ground station would set and save
    them before a reboot (e.g. EK3_DRAG_BCOEF_X for a wind estimate, CAM1_TYPE for a camera)."""
    def refused(key: str) -> str | None:
        return "the simulator's parameters go in [faults]" if key.startswith("SIM_") else None
    return _parameter_table(table, name, "params", refused)


def _faults(table, name: str) -> dict:
    """[faults]: SIM_* parameters by their names, set before the vehicle first moves."""
    def refused(key: str) -> str | None:
        if key not in FAULT_NAMES:
            return f"unknown fault (known: {', '.join(FAULT_NAMES)})"
        if key in WORLD_SOURCES:
            return f"the scenario sets this with {WORLD_SOURCES[key]}"
        return None
    return _parameter_table(table, name, "faults", refused)


def _parameter_table(table, name: str, section: str, refused) -> dict:
    """A table of parameter names and values, each checked against the parameter table; a key
    `refused(key)` has a reason against is refused with it."""
    if not isinstance(table, dict):
        raise ScenarioError(f"{name}: [{section}] must be a table")
    values = {}
    for key, value in table.items():
        where = f"{name}: [{section}].{key}"
        reason = refused(key)
        if reason:
            raise ScenarioError(f"{where}: {reason}")
        world.number(where, value)
        try:
            values[key] = checked_value(key, value)
        except ParamError as exc:
            raise ScenarioError(f"{where}: {str(exc).removeprefix(key + ': ')}") from None
    return values


def _signing_key(table, name: str, base_dir: Path) -> bytes:
    """[signing] holds exactly one of key (the text of a key file) or key_file (a path)."""
    from ..io.signing_keys import SigningKeyError, key_from_text, read_key_file
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
