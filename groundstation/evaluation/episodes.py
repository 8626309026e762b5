"""Decision-level episodes: the search controller (strategy/controller.py) against the sim's fire
world, without flying the vehicle.

The vehicle starts at the area's corner (0, 0) or its centre, flies straight lines between the
controller's targets at the survey speed (5 m/s) at the survey altitude, and takes a reading from
sim.fire.TemperatureSensor every sample interval (1 s: one reading per 5 m) and on arriving at a
target. The real sensor publishes at >= 5 Hz, i.e. a reading per metre or less at 5 m/s; one per
5 m is the conservative choice (fewer readings, and the belief's updates stay cheap), and the flight
averages its readings to the same density. Every reading goes to the controller, which is then
asked where to fly: the episode is the controller's driver, as the flight is.

The wind: the world's plume leans with the scenario's wind (air_ne_m_s). The search is told a wind
only when config.wind_ne_m_s says so (as a vehicle fusing drag reports it in WIND); by default it
estimates the wind from how the vehicle leans (strategy/wind_estimate.py), and the episode gives it
what the flight's steady samples are: one per reading, lean = c (v - w) + noise, with c the sim
airframe's drag over its weight (the steady state of sim/rigid_body.py's forces), v the leg's velocity
(zero while hovering at the start) and LEAN_NOISE the spread measured in flight.

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

from firefly.sim.airframe import Airframe
from firefly.sim.fire import Fire, FireWorld, TemperatureSensor
from firefly.sim.thermal_camera import ThermalCameraSpec, pose_from_attitude, render

from ..strategy.belief import Geometry
from ..strategy.controller import SearchConfig, SearchController
from ..camera_view import frame_from_image, nadir_footprint_m
from ..strategy.policies import Policy
from ..strategy.stopping import Declaration
from ..truth import fires_found, judge_all

STARTS = ("corner", "centre")
SENSORS = ("point", "camera")
HOVER_SAMPLES = 5  # steady samples hovering at the start, before the first leg (the flight hovers there too)
# Vertical speeds of a climb or descent to a target at another height (ArduCopter's WPNAV_SPEED_UP
# and WPNAV_SPEED_DN defaults, m/s)
CLIMB_M_S = 2.5
DESCENT_M_S = 1.5
LEAN_NOISE = 0.003  # spread of one steady lean sample (tan of the tilt) about c (v - w), measured in flight


@dataclass(frozen=True)
class EpisodeConfig(SearchConfig):
    """The search's settings, and how the episode's world and start are drawn."""
    start: str = "corner"
    fixed_fire: bool = False
    strength_k: tuple = (20.0, 80.0)
    ambient_c: tuple = (15.0, 35.0)
    wind_ne_m_s: tuple | None = None  # the wind the search is told (as (n, e) m/s); None: it estimates it
    air_ne_m_s: tuple = (0.0, 0.0)    # the wind that blows (the scenario's): the vehicle leans in it
    lean_noise: float = LEAN_NOISE
    fires: int = 1                   # fires drawn per episode (each uniform, strength uniform)
    fire_spacing_m: float | None = None  # set: the second fire this far from the first, as strong
    sensor: str = "point"            # "camera": a thermal frame (nadir, level) besides every reading

    def __post_init__(self):
        super().__post_init__()
        if self.start not in STARTS:
            raise ValueError(f"start must be one of {', '.join(STARTS)}, got {self.start!r}")
        if self.sensor not in SENSORS:
            raise ValueError(f"sensor must be one of {', '.join(SENSORS)}, got {self.sensor!r}")
        if int(self.fires) != self.fires or self.fires < 1:
            raise ValueError(f"fires must be a positive whole number, got {self.fires!r}")
        if self.fire_spacing_m is not None and not (self.fire_spacing_m > 0 and self.fires == 2):
            raise ValueError("fire_spacing_m needs two fires and a positive distance")


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
    error_m: float         # the declared cell centre farthest from every fire: to its nearest fire
    success: bool          # a declaration, and every declared cell within one cell (Chebyshev) of a fire's
    fires_found: int       # fires with a declared cell within one cell of theirs
    declared_by: str       # "confident", "budget", "end" (the policy had nothing more to do) or
                           # "clear" (several fires: confident there is no further fire)
    forced: bool           # declared without the belief being confident
    false_declaration: bool  # a confident declaration that is wrong
    mass: float            # belief mass in the 3x3 block around the declared cell
    readings: int
    decisions: int
    ms_mean: float
    ms_max: float
    declarations: list = dataclasses.field(default_factory=list)  # every declared (n, e): several fires
    first_find_m: float | None = None  # path flown when the first fire was found (None: none was)
    time_s: float = 0.0                # flight time to the declaration (survey speed, climbs)
    sensor: str = "point"
    frames: int = 0                    # thermal frames taken (sensor "camera")
    frame_ms_mean: float = 0.0         # ... and the time one costs the search: its pixels' ground points,
    frame_ms_max: float = 0.0          # its reduction and its likelihood (not the render, the world's part)

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
    fires = [Fire(float(n), float(e), float(strength))]
    if config.fire_spacing_m is not None:  # a twin at that distance, on a bearing that keeps it inside
        for _ in range(1000):
            bearing = rng.uniform(0.0, 2.0 * math.pi)
            n2, e2 = n + config.fire_spacing_m * math.cos(bearing), e + config.fire_spacing_m * math.sin(bearing)
            if lo <= n2 <= hi and lo <= e2 <= hi:
                break
        else:
            raise ValueError(f"no room for two fires {config.fire_spacing_m:g} m apart in a {world.area_m:g} m area")
        fires.append(Fire(float(n2), float(e2), float(strength)))
    for _ in range(config.fires - len(fires)):  # drawn after the first fire's, so one-fire episodes are unchanged
        n, e = rng.uniform(lo, hi, size=2)
        fires.append(Fire(float(n), float(e), float(rng.uniform(*config.strength_k))))
    return dataclasses.replace(world, fires=tuple(fires), ambient_c=float(ambient))


def start_position(geometry: Geometry, start: str) -> tuple[float, float]:
    return (0.0, 0.0) if start == "corner" else (geometry.area_m / 2, geometry.area_m / 2)


def policy_rng(seed: int, index: int) -> np.random.Generator:
    """The random stream the policy of episode `index` draws from."""
    return np.random.default_rng(_mix(seed, index, 2))


def steady_lean(config: EpisodeConfig, rng: np.random.Generator):
    """lean(velocity): a steady lean sample at that velocity in the episode's wind."""
    af = Airframe()
    c = af.linear_drag_n_per_m_s / af.weight_n
    wn, we = float(config.air_ne_m_s[0]), float(config.air_ne_m_s[1])

    def lean(velocity):
        noise = rng.normal(0.0, config.lean_noise, 2) if config.lean_noise > 0 else (0.0, 0.0)
        return c * (velocity[0] - wn) + noise[0], c * (velocity[1] - we) + noise[1]
    return lean


def run_episode(world: FireWorld, seed: int, index: int, policy: Policy,
                config: EpisodeConfig = EpisodeConfig(), trace: list | None = None,
                steps: list | None = None) -> EpisodeResult:
    """One episode; `trace`, if given, receives (n, e, reading) for every reading, and `steps` the
    controller's answer (Goto or Declaration) after every reading."""
    ep_world = episode_world(world, seed, index, config)
    geometry = Geometry.from_world(ep_world)
    sensor = TemperatureSensor(ep_world, seed=(seed * 1_000_003 + index) & 0xFFFFFFFF)
    alt = geometry.survey_alt_m
    pos = start_position(geometry, config.start)
    camera = Camera(ep_world, seed, index) if config.sensor == "camera" else None
    if camera is not None:  # before the controller resets the policy
        policy.footprint_m = camera.footprint_m(geometry.survey_alt_m)
    controller = SearchController(geometry, policy, config, pos, policy_rng(seed, index), time.perf_counter,
                                  wind_ne_m_s=config.wind_ne_m_s)
    lean = steady_lean(config, np.random.default_rng(_mix(seed, index, 3)))
    for _ in range(HOVER_SAMPLES):
        controller.observe_lean((0.0, 0.0), lean((0.0, 0.0)))
    step_m = config.observation_spacing_m
    t = path = 0.0
    readings = 0
    arrived = False
    velocity = (0.0, 0.0)
    while True:
        if readings:
            controller.observe_lean(velocity, lean(velocity))
        z = sensor.read(pos[0], pos[1], alt, t)
        controller.observe(pos[0], pos[1], z, alt)
        if camera is not None:
            camera.look(controller, pos, alt, t)
        readings += 1
        if trace is not None:
            trace.append((pos[0], pos[1], z))
        move = controller.step(pos, path, arrived)
        if steps is not None:
            steps.append(move)
        if isinstance(move, Declaration):
            break
        to_alt = geometry.survey_alt_m if move.height_m is None else move.height_m
        dn, de = move.target[0] - pos[0], move.target[1] - pos[1]
        d = math.hypot(dn, de)
        velocity = (dn * config.speed_m_s / d, de * config.speed_m_s / d) if d > 0 else (0.0, 0.0)
        if to_alt != alt:  # a climb or a descent: the slower axis sets the time, along a straight line
            dz = to_alt - alt
            need_s = max(d / config.speed_m_s, abs(dz) / (CLIMB_M_S if dz > 0 else DESCENT_M_S))
            share = min(1.0, config.sample_s / need_s)
            arrived = share == 1.0
            pos, alt = (pos[0] + dn * share, pos[1] + de * share), alt + dz * share
            if arrived:
                pos, alt = move.target, to_alt
            path += share * math.hypot(d, dz)
            t += share * need_s
            velocity = (dn / need_s, de / need_s)
            continue
        arrived = d <= step_m
        if arrived:
            pos = move.target
            path += d
            t += d / config.speed_m_s if d > 0 else config.sample_s
        else:
            pos = (pos[0] + dn * step_m / d, pos[1] + de * step_m / d)
            path += step_m
            t += config.sample_s

    declared = [d.position for d in controller.declarations]
    error, success, on_fire = judge_all(ep_world, declared)
    wrong = any(d.reason == "confident" and not ok for d, ok in zip(controller.declarations, on_fire))
    ms = [1000.0 * x for x in controller.decision_s]
    return EpisodeResult(
        policy=policy.name, episode=index, seed=seed, kernel=ep_world.kernel, start=config.start,
        fires=[(f.n_m, f.e_m, f.strength_k) for f in ep_world.fires], ambient_c=ep_world.ambient_c,
        path_m=path, declared=move.position, declared_cell=move.index, error_m=error,
        success=bool(success), fires_found=fires_found(ep_world, declared), declared_by=controller.finished_by,
        forced=move.forced, false_declaration=bool(wrong),
        mass=move.mass, readings=readings, decisions=controller.decisions,
        ms_mean=float(np.mean(ms)) if ms else 0.0, ms_max=float(np.max(ms)) if ms else 0.0,
        declarations=[tuple(p) for p in declared], first_find_m=controller.first_find_path_m,
        time_s=t, sensor=config.sensor, frames=len(camera.ms) if camera else 0,
        frame_ms_mean=float(np.mean(camera.ms)) if camera and camera.ms else 0.0,
        frame_ms_max=float(np.max(camera.ms)) if camera and camera.ms else 0.0)


class Camera:
    """The thermal camera of an episode (sim/thermal_camera.py): a frame straight down, the vehicle
    level at yaw 0, rendered from the episode's world with its own seeded noise, reduced and given to
    the controller. `ms`: what each frame cost the search (the reduction and the likelihood)."""

    def __init__(self, world: FireWorld, seed: int, index: int):
        self.world = world
        self.spec = ThermalCameraSpec()
        self.rng = np.random.default_rng(_mix(seed, index, 4))
        self.ms: list[float] = []

    def footprint_m(self, alt_m: float) -> tuple[float, float]:
        """The ground rectangle (north, east) [m] a frame from alt_m covers."""
        return nadir_footprint_m(self.spec, alt_m)

    def look(self, controller: SearchController, pos, alt: float, t: float) -> None:
        pose = pose_from_attitude(pos[0], pos[1], alt)
        image = render(self.world, self.spec, pose, self.rng, t)
        t0 = time.perf_counter()
        frame = frame_from_image(image, self.spec, pose)  # as the flown search reads a downloaded still
        controller.observe_frame(frame)
        self.ms.append(1000.0 * (time.perf_counter() - t0))
