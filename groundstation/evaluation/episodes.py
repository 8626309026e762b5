"""Decision-level episodes: the strategy against the sim's fire world without flying the vehicle.

The vehicle starts at the area's corner (0, 0) or its centre, flies straight lines between the
policy's waypoints at a constant speed (5 m/s) at the survey altitude, and takes a reading from
sim.fire.TemperatureSensor every sample interval (1 s: one reading per 5 m) and on arriving at a
waypoint. The real sensor publishes at >= 5 Hz, i.e. a reading per metre or less at 5 m/s; one per
5 m is the conservative choice (fewer readings, and the belief's updates stay cheap). After every
reading the belief is updated and the stopping rule checked; the policy is asked for a new waypoint
on arrival and, if it asks for it, while flying (gig: every 4 readings, i.e. 20 m).

Declaring: the stopping rule of stopping.py, here with a 3 x 3 mass threshold of 0.99 (the rule's
own default is STRATEGY's 0.95) and confirmation by flying over the cell (confirm_m = 10 m; None turns
it off): once the belief is confident, the vehicle flies to the most likely cell's centre and declares
there if the belief is still confident. A calibrated belief declared at mass t is wrong about 1 - t of
the time, in practice a little more, as the declaration is taken at the first reading that crosses
the threshold. Measured with gig on validation episodes (seed 1, episodes 100-299, not the ones
reported): 0.95 alone was wrong in 3-4 % (R), 0.95 with confirmation in 0.5 % (R and G), 0.99 with
confirmation never, for about 3 m more mean path than 0.95 with confirmation.
Policies that ignore the belief (zigzag) end when their route ends.

Episodes are generated from (scenario world, seed, episode index): one fire uniform in the area at
least one cell from its edge, strength uniform 20-80 K, ambient uniform 15-35 C; the scenario's other
world settings (kernel, noise, plume sigma, outliers, wind tilt) are kept. fixed_fire=True keeps the
scenario's own fires and ambient. Everything is deterministic given the seed, except the measured
decision times.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from sim.fire import Fire, FireWorld, TemperatureSensor

from ..strategy.belief import Belief, Geometry
from ..strategy.policies import Policy
from ..strategy.stopping import Declaration, StoppingRule

STARTS = ("corner", "centre")


@dataclass(frozen=True)
class EpisodeConfig:
    speed_m_s: float = 5.0
    sample_s: float = 1.0
    start: str = "corner"
    threshold: float = 0.99
    budget_m: float = 6000.0
    fixed_fire: bool = False
    strength_k: tuple = (20.0, 80.0)
    ambient_c: tuple = (15.0, 35.0)
    prior_strength_mean_k: float = 50.0
    prior_strength_sd_k: float = 25.0
    subcells: int = 3
    confirm_m: float | None = 10.0

    def __post_init__(self):
        if self.start not in STARTS:
            raise ValueError(f"start must be one of {', '.join(STARTS)}, got {self.start!r}")
        if not (self.speed_m_s > 0 and self.sample_s > 0):
            raise ValueError("speed and sample interval must be positive")


@dataclass
class EpisodeResult:
    policy: str
    episode: int
    seed: int
    kernel: str
    start: str
    fires: list            # [(n, e, strength_k)]
    ambient_c: float
    path_m: float
    declared: tuple        # (n, e) local metres
    declared_cell: tuple   # (i_north, j_east)
    error_m: float         # declared cell centre to the nearest fire
    success: bool          # declared cell within one cell (Chebyshev) of a fire's cell
    declared_by: str       # "confident", "budget" or "end" (the policy had nothing more to do)
    forced: bool           # declared without the belief being confident
    false_declaration: bool  # a confident declaration that is wrong
    mass: float            # belief mass in the 3x3 block around the declared cell
    readings: int
    decisions: int
    ms_mean: float
    ms_max: float

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _mix(seed: int, index: int, stream: int) -> list[int]:
    return [seed & 0xFFFFFFFF, index & 0xFFFFFFFF, stream]


def episode_world(world: FireWorld, seed: int, index: int, config: EpisodeConfig = EpisodeConfig()) -> FireWorld:
    """The world of episode `index`: a random fire, strength and ambient unless config.fixed_fire."""
    if config.fixed_fire:
        return world
    rng = np.random.default_rng(_mix(seed, index, 1))
    lo, hi = world.cell_m, world.area_m - world.cell_m
    if hi <= lo:
        lo = hi = world.area_m / 2
    n, e = rng.uniform(lo, hi, size=2)
    strength = rng.uniform(*config.strength_k)
    ambient = rng.uniform(*config.ambient_c)
    return dataclasses.replace(world, fires=(Fire(float(n), float(e), float(strength)),), ambient_c=float(ambient))


def judge(world: FireWorld, n: float, e: float) -> tuple[float, bool]:
    """Distance from a declared point to the nearest fire, and success: the declared cell within
    one cell (Chebyshev) of a fire's cell."""
    geometry = Geometry.from_world(world)
    declared = geometry.cell_of(n, e)
    errors = [math.hypot(n - f.n_m, e - f.e_m) for f in world.fires]
    within = any(max(abs(declared[0] - i), abs(declared[1] - j)) <= 1
                 for i, j in (geometry.cell_of(f.n_m, f.e_m) for f in world.fires))
    return (min(errors) if errors else math.nan), within


def start_position(geometry: Geometry, start: str) -> tuple[float, float]:
    return (0.0, 0.0) if start == "corner" else (geometry.area_m / 2, geometry.area_m / 2)


def run_episode(world: FireWorld, seed: int, index: int, policy: Policy,
                config: EpisodeConfig = EpisodeConfig(), trace: list | None = None) -> EpisodeResult:
    """One episode; `trace`, if given, receives (n, e, reading) for every reading."""
    ep_world = episode_world(world, seed, index, config)
    geometry = Geometry.from_world(ep_world)
    sensor = TemperatureSensor(ep_world, seed=(seed * 1_000_003 + index) & 0xFFFFFFFF)
    belief = Belief(geometry, config.prior_strength_mean_k, config.prior_strength_sd_k,
                    subcells=config.subcells)
    rule = StoppingRule(config.threshold, 1, config.budget_m, config.confirm_m)
    alt = geometry.survey_alt_m
    pos = start_position(geometry, config.start)
    policy.reset(geometry, pos, np.random.default_rng(_mix(seed, index, 2)))

    t = 0.0
    path = 0.0
    readings = 0
    step = config.speed_m_s * config.sample_s
    max_readings = int(4 * config.budget_m / step) + 100  # guards against a policy that never moves
    times: list[float] = []

    def read():
        nonlocal readings
        z = sensor.read(pos[0], pos[1], alt, t)
        belief.update(pos[0], pos[1], z, alt)
        policy.observe(pos[0], pos[1], z)
        readings += 1
        if trace is not None:
            trace.append((pos[0], pos[1], z))

    def decide():
        t0 = time.perf_counter()
        wp = policy.next_waypoint(belief, pos)
        times.append(time.perf_counter() - t0)
        if wp is not None:
            wp = (float(wp[0]), float(wp[1]))
            a = geometry.area_m
            if not (0 <= wp[0] <= a and 0 <= wp[1] <= a and math.isfinite(wp[0]) and math.isfinite(wp[1])):
                raise RuntimeError(f"policy {policy.name} chose a waypoint outside the area: {wp}")
        return wp

    read()
    need_decision, target, since = True, None, 0
    declaration: Declaration | None = None
    declared_by = ""
    confirming = False
    while True:
        if policy.uses_stopping_rule:
            declaration = rule.confident(belief)
            if declaration is not None:
                declared_by = "confident"
                break
        if path >= config.budget_m or readings >= max_readings:
            declaration, declared_by = rule.force(belief, "budget"), "budget"
            break
        if policy.uses_stopping_rule and config.confirm_m is not None:
            check = rule.to_confirm(belief)
            if check is not None:  # confident but not yet flown over: go and look
                target, confirming, need_decision = check, True, False
            elif confirming:  # the readings on the way overturned it: back to the policy
                confirming, need_decision = False, True
        if need_decision:
            target, since, need_decision = decide(), 0, False
            if target is None:
                declaration, declared_by = rule.force(belief, "end"), "end"
                break
        dn, de = target[0] - pos[0], target[1] - pos[1]
        d = math.hypot(dn, de)
        if d <= step:
            pos = target
            path += d
            t += d / config.speed_m_s if d > 0 else config.sample_s
            need_decision = True
        else:
            pos = (pos[0] + dn * step / d, pos[1] + de * step / d)
            path += step
            t += config.sample_s
        read()
        since += 1
        if not need_decision and policy.wants_replan(since):
            need_decision = True

    declared = declaration.position
    own = policy.declaration(belief)
    if own is not None:
        declared = (float(own[0]), float(own[1]))
    index_decl = geometry.cell_of(*declared)
    declared = geometry.centre_of(index_decl)
    error, success = judge(ep_world, *declared)
    forced = declared_by == "budget" or (declared_by != "confident" and policy.uses_stopping_rule)
    ms = [1000.0 * x for x in times]
    return EpisodeResult(
        policy=policy.name, episode=index, seed=seed, kernel=ep_world.kernel, start=config.start,
        fires=[(f.n_m, f.e_m, f.strength_k) for f in ep_world.fires], ambient_c=ep_world.ambient_c,
        path_m=path, declared=declared, declared_cell=index_decl, error_m=error,
        success=bool(success), declared_by=declared_by, forced=bool(forced),
        false_declaration=bool(declared_by == "confident" and not success),
        mass=belief.mass_around(index_decl, 1), readings=readings, decisions=len(times),
        ms_mean=float(np.mean(ms)) if ms else 0.0, ms_max=float(np.max(ms)) if ms else 0.0)
