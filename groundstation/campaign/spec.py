"""A campaign file (TOML): what to run, checked in full before anything runs.

    [campaign]
    scenario = "../scenarios/default.toml"   # relative to this file
    policies = ["gig", "lawnmower"]
    episodes = 50        # decision-level episodes per cell (condition x policy)
    flown = 5            # of those, the first ones also flown through a real autopilot
    speedup = 20         # of the flown episodes' autopilots
    seed = 2             # default: the scenario's

    [sweep.world]        # [world] keys of the scenario, each a list of values
    noise_k = [1.0, 3.0]
    [sweep.search]       # the search's settings (and how episodes are drawn)
    start = ["corner"]
    [sweep.wind]         # the scenario's [wind]: what the vehicle flies in (the search estimates it)
    speed_m_s = [0.0, 4.0]
    [sweep.team]         # several vehicles searching together (strategy/team.py): the policies are
    vehicles = [1, 3]    # then team policies (joint, independent, strips); start: corner or spread

The conditions are every combination of the swept values; a cell is a condition and a policy; a
task is one episode of a cell, decision-level or flown. Every mistake is one line naming the table
and key.
"""
from __future__ import annotations

import copy
import dataclasses
import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from pathlib import Path

from firefly.sim.fire import WORLD_KEYS
from firefly.sim.scenario import ScenarioError, read_toml, scenario_from_dict

from ..evaluation.episodes import EpisodeConfig, episode_world
from ..strategy.policies import POLICIES
from ..strategy.team import TEAM_POLICIES

CAMPAIGN_KEYS = ("name", "scenario", "policies", "episodes", "flown", "speedup", "seed")
# The search settings a campaign may sweep: EpisodeConfig's scalar fields, less the wind it is told
# and the wind that blows (those follow [sweep.wind]) and the ranges episodes are drawn from.
SEARCH_KEYS = tuple(f.name for f in dataclasses.fields(EpisodeConfig)
                    if f.name not in ("wind_ne_m_s", "air_ne_m_s", "strength_k", "ambient_c"))
WIND_KEYS = ("speed_m_s", "from_direction_deg")
TEAM_KEYS = ("vehicles", "start")
MAX_VEHICLES = 8
SWEEP_TABLES = {"world": tuple(sorted(WORLD_KEYS)), "search": SEARCH_KEYS, "wind": WIND_KEYS, "team": TEAM_KEYS}


class CampaignError(ValueError):
    """A campaign file that cannot be run, in one line naming the table and key."""


@dataclass(frozen=True)
class Condition:
    """One combination of swept values: {"world.noise_k": 3.0, "search.start": "corner", ...}."""
    values: tuple  # ((dotted key, value), ...) in the sweep's order

    @property
    def key(self) -> str:
        return json.dumps(dict(self.values), sort_keys=True)

    @property
    def label(self) -> str:
        return ", ".join(f"{k.split('.', 1)[1]}={v}" for k, v in self.values) or "as the scenario"

    @property
    def team(self) -> tuple[int, str] | None:
        """(vehicles, start) when the condition sweeps a team, else None."""
        values = dict(self.values)
        if "team.vehicles" not in values and "team.start" not in values:
            return None
        return int(values.get("team.vehicles", 1)), str(values.get("team.start", "corner"))


@dataclass(frozen=True)
class Task:
    """One episode of one cell: what a worker needs to run it, and its identity in the results."""
    condition: Condition
    policy: str
    episode: int
    flown: bool

    @property
    def id(self) -> str:
        return f"{self.condition.key}|{self.policy}|{self.episode}|{'flown' if self.flown else 'decided'}"


@dataclass(frozen=True)
class Campaign:
    path: Path
    name: str
    scenario_path: Path
    scenario_tables: dict
    policies: tuple
    episodes: int
    flown: int
    speedup: float
    seed: int
    sweep: tuple  # ((dotted key, (values...)), ...)
    fingerprint: str  # what a results file must carry to be resumed with this campaign

    def conditions(self) -> list[Condition]:
        keys = [k for k, _ in self.sweep]
        return [Condition(tuple(zip(keys, combo))) for combo in itertools.product(*(v for _, v in self.sweep))]

    def tasks(self) -> list[Task]:
        """Every task, decision-level first (they are quick and fill the table early), then flown."""
        cells = [(c, p) for c in self.conditions() for p in self.policies]
        decided = [Task(c, p, k, False) for c, p in cells for k in range(self.episodes)]
        flown = [Task(c, p, k, True) for c, p in cells for k in range(self.flown)]
        return decided + flown

    def setup(self, condition: Condition):
        """(scenario tables, world, EpisodeConfig) of a condition."""
        return condition_setup(self.scenario_tables, condition, self.name)


def condition_setup(scenario_tables: dict, condition: Condition, where: str):
    tables = copy.deepcopy(scenario_tables)
    search = {}
    for dotted, value in condition.values:
        table, key = dotted.split(".", 1)
        if table == "world":
            tables.setdefault("world", {})[key] = value
        elif table == "wind":
            tables.setdefault("wind", {})[key] = value
        elif table == "search":
            search[key] = value  # team.* keys choose how the episode is run (tasks.py), not the world
    scenario = scenario_from_dict(tables, f"{where}: {condition.label}")
    if "fires" in search and "max_fires" not in search:
        search["max_fires"] = None  # a sweep over fire counts: not told how many, as evaluate is
    search["air_ne_m_s"] = tuple(scenario.sim.wind.velocity_ned()[:2])
    config = EpisodeConfig(**search)
    return tables, scenario.world, config


def _fail(where: str, text: str):
    raise CampaignError(f"{where}: {text}")


def _whole(where: str, value, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        _fail(where, f"expected a whole number >= {low}, got {value!r}")
    return value


def load_campaign(path: Path) -> Campaign:
    path = Path(path)
    name = str(path)
    try:
        data = read_toml(path)
    except ScenarioError as exc:  # no such file, unreadable, not TOML: the scenario reader's own lines
        raise CampaignError(str(exc)) from None
    for key in data:
        if key not in ("campaign", "sweep"):
            _fail(name, f"unknown table [{key}] (known: [campaign], [sweep.world], [sweep.search], [sweep.wind], [sweep.team])")
    head = data.get("campaign")
    if not isinstance(head, dict):
        _fail(name, "a [campaign] table is required (scenario, policies, episodes)")
    where = f"{name}: [campaign]"
    for key in head:
        if key not in CAMPAIGN_KEYS:
            _fail(where, f"unknown key '{key}' (known: {', '.join(CAMPAIGN_KEYS)})")
    for key in ("scenario", "policies", "episodes"):
        if key not in head:
            _fail(where, f"'{key}' is required")
    if not isinstance(head["scenario"], str):
        _fail(f"{where} scenario", f"expected a path, got {head['scenario']!r}")
    scenario_path = (path.parent / head["scenario"]).resolve()
    try:
        scenario_tables = read_toml(scenario_path)
        scenario = scenario_from_dict(scenario_tables, str(scenario_path))
    except ScenarioError as exc:
        _fail(f"{where} scenario", str(exc))
    policies = head["policies"]
    if not isinstance(policies, list) or not policies:
        _fail(f"{where} policies", f"expected a non-empty list of policy names, got {policies!r}")
    team = "team" in data.get("sweep", {}) if isinstance(data.get("sweep"), dict) else False
    known = TEAM_POLICIES if team else POLICIES
    for p in policies:
        if p not in known:
            _fail(f"{where} policies", f"unknown {'team ' if team else ''}policy {p!r} (known: {', '.join(known)}"
                                       + ("; [sweep.team] runs team policies" if team else "") + ")")
    if len(set(policies)) != len(policies):
        _fail(f"{where} policies", "a policy is listed twice")
    episodes = _whole(f"{where} episodes", head["episodes"], 1)
    flown = _whole(f"{where} flown", head.get("flown", 0), 0)
    if flown > episodes:
        _fail(f"{where} flown", f"at most episodes ({episodes}) can be flown, got {flown}")
    speedup = head.get("speedup", 20.0)
    if isinstance(speedup, bool) or not isinstance(speedup, (int, float)) or not (speedup > 0):
        _fail(f"{where} speedup", f"expected a positive number (inf allowed), got {speedup!r}")
    seed = _whole(f"{where} seed", head.get("seed", scenario.seed), 0)
    campaign_name = head.get("name", path.stem)
    if not isinstance(campaign_name, str) or not campaign_name:
        _fail(f"{where} name", f"expected a non-empty string, got {campaign_name!r}")
    sweep = _sweep(data.get("sweep", {}), name)
    campaign = Campaign(path, campaign_name, scenario_path, scenario_tables, tuple(policies), episodes, flown,
                        float(speedup), seed, sweep, "")
    _check_conditions(campaign, name)
    return dataclasses.replace(campaign, fingerprint=fingerprint(campaign))


def _sweep(sweep, name: str) -> tuple:
    if not isinstance(sweep, dict):
        _fail(name, "[sweep] must hold tables: [sweep.world], [sweep.search], [sweep.wind], [sweep.team]")
    out = []
    for table, values in sweep.items():
        where = f"{name}: [sweep.{table}]"
        if table not in SWEEP_TABLES:
            _fail(f"{name}: [sweep]", f"unknown table '{table}' (known: {', '.join(SWEEP_TABLES)})")
        if not isinstance(values, dict):
            _fail(where, "must be a table of lists")
        if table == "team" and not values:  # it would turn the policies into team policies for no team
            _fail(where, "sweeps nothing: give vehicles = [...] (and start = [...]), or leave the table out")
        for key, options in values.items():
            if key not in SWEEP_TABLES[table]:
                _fail(where, f"unknown key '{key}' (known: {', '.join(SWEEP_TABLES[table])})")
            if not isinstance(options, list):
                _fail(f"{where} {key}", f"expected a list of values, got {options!r}")
            if not options:
                _fail(f"{where} {key}", "an empty list sweeps nothing: give at least one value")
            if len({json.dumps(o) for o in options}) != len(options):
                _fail(f"{where} {key}", "a value is listed twice")
            for o in options:
                if not isinstance(o, (str, int, float)) or isinstance(o, float) and not math.isfinite(o):
                    _fail(f"{where} {key}", f"values must be strings or finite numbers, got {o!r}")
            out.append((f"{table}.{key}", tuple(options)))
    return tuple(out)


def _check_conditions(campaign: Campaign, name: str) -> None:
    """Build every condition's world and settings once, so a bad value fails now, in one line."""
    for condition in campaign.conditions():
        try:
            _, world, config = campaign.setup(condition)
            episode_world(world, campaign.seed, 0, config)
        except (ValueError, TypeError) as exc:
            text = str(exc).removeprefix(f"{campaign.name}: {condition.label}: ")  # said once, below
            _fail(f"{name}: [sweep] {condition.label}", text)
        if condition.team is not None:
            values = dict(condition.values)
            vehicles, start = values.get("team.vehicles", 1), values.get("team.start", "corner")
            if isinstance(vehicles, bool) or not isinstance(vehicles, int) or not 1 <= vehicles <= MAX_VEHICLES:
                _fail(f"{name}: [sweep.team] vehicles", f"expected whole numbers 1..{MAX_VEHICLES}, got {vehicles!r}")
            if start not in ("corner", "spread"):
                _fail(f"{name}: [sweep.team] start", f"expected 'corner' or 'spread', got {start!r}")
            if campaign.flown:
                _fail(f"{name}: [campaign] flown", "team episodes are decided only for now: set flown = 0")
            if config.max_fires != 1:
                _fail(f"{name}: [sweep.search] max_fires", "a team searches for one fire")
            if "search.start" in values:
                _fail(f"{name}: [sweep.search] start", "a team's starts are [sweep.team] start (corner or spread)")
        if campaign.flown and config.start != "corner":
            _fail(f"{name}: [sweep.search] start", "flown episodes start at home, the area's corner: "
                                                   "with flown > 0 sweep only start = [\"corner\"]")


def fingerprint(campaign: Campaign) -> str:
    """What identifies a campaign's results: everything that decides an episode's outcome."""
    identity = {"scenario": campaign.scenario_tables, "policies": campaign.policies, "episodes": campaign.episodes,
                "flown": campaign.flown, "speedup": campaign.speedup, "seed": campaign.seed,
                "sweep": [[k, list(v)] for k, v in campaign.sweep],
                # since issue 30 the search estimates the wind it was told before: results from
                # before are not this campaign's
                "wind": "estimated by one vehicle, told to a team"}
    return hashlib.sha256(json.dumps(identity, sort_keys=True, default=str).encode()).hexdigest()[:16]
