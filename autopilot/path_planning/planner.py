"""ArduCopter's object-avoidance path planner (AP_OAPathPlanner with its Dijkstra and BendyRuler
planners), as the waypoint legs consult it: given where the vehicle is and the leg's destination
(and the next one), it answers whether avoidance is needed and, if so, the point to fly to now.

The planners are made at boot for the OA_TYPE then: 1 BendyRuler (bendy_ruler.py), 2 Dijkstra
(dijkstra.py), 3 both: BendyRuler round the obstacle database's proximity obstacles
(obstacle_database.py) while any are in the way, then Dijkstra round the fence, its path found
afresh from there (with no proximity sensor OA_TYPE 3 plans as 2). OA_TYPE set later is refused at arming ("Dijkstra OA requires reboot")
and plans nothing, while OA_TYPE 0 stops it at once. ArduCopter plans on a thread of its own about
once a second, for the request the legs last made; the legs act on an answer only when it was
planned for their present destination. Until then the answer is "processing" (the legs stop where
they can, unless OA_OPTIONS allows fast waypoints), and a planner silent for 3 s is an error. Here
the planner runs on sim time at every PLAN_EVERY_S a request finds due, so it answers 0-1 s after
a new destination, as ArduCopter's thread does.

BendyRuler answers at each plan a point to fly to (the legs hand it to the position controller,
not the waypoint navigator; with OA_BR_TYPE 2, vertical, a point with its height), or that no
avoidance is needed; it never says why, and
never stops the vehicle, and the way on to the next destination is never known clear (the legs
stop at each destination).

Each Dijkstra plan (AP_OADijkstra::update): no avoidance without a polygon fence enabled that holds an
inclusion or exclusion polygon or an exclusion circle. The fence's corners and what they see are
built once per fence with the OA_MARGIN_MAX of then (fence changes rebuild it; the margin alone
does not); the shortest path is found once per destination, from where the vehicle is then, and
its corners handed out one at a time: the next once the vehicle is within 2 m of the present one
or past the line square to its leg at it, told at the next plan. Past the last corner, or with a
straight path, avoidance is not needed. Failures are said as "Dijkstra: <reason>" (CRITICAL), each
reason again after 5 s at the soonest, and answered as errors (the legs stop).
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..results import Severity
from ..safety.fence_shapes import Shape
from ..safety.fence_switch import POLYGON, FenceSwitch
from .bendy_ruler import BendyRuler, FenceView, Settings
from .dijkstra import FenceGraph, PlanError
from .obstacle_database import ObstacleDatabase

if TYPE_CHECKING:
    from ..params import ParamStore

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]
NOT_REQUIRED, PROCESSING, ERROR, SUCCESS = "not required", "processing", "error", "success"  # OA_RetState
DISABLED, BENDY_RULER, DIJKSTRA, DIJKSTRA_BENDY_RULER = 0, 1, 2, 3  # OA_TYPE
PLANS_FENCES = (DIJKSTRA, DIJKSTRA_BENDY_RULER)
NEEDS = {BENDY_RULER: {BENDY_RULER}, DIJKSTRA: {DIJKSTRA}, DIJKSTRA_BENDY_RULER: {DIJKSTRA, BENDY_RULER}}
REBOOT_TEXTS = {BENDY_RULER: "BendyRuler OA requires reboot", DIJKSTRA: "Dijkstra OA requires reboot",
                DIJKSTRA_BENDY_RULER: "OA requires reboot"}
VERTICAL = 2  # OA_BR_TYPE (1 horizontal, and anything else)
FAST_WAYPOINTS = 1 << 2  # OA_OPTIONS: fly on while planning, and through the corners
# OA_UPDATE_MS is 1 s, but the thread wakes every 20 ms to look: measured, plans 1.00 to 1.04 s
# apart, 1.02 s on average (so a reason said again "after 5 s" is said every 5.1 s)
PLAN_EVERY_S = 1.02
ANSWER_TIMEOUT_S = 3.0  # OA_TIMEOUT_MS: an older answer is an error
REQUEST_GAP_S = 0.2  # requests further apart start afresh (no timeout at first)
REPORT_EVERY_S = 5.0  # OA_DIJKSTRA_ERROR_REPORTING_INTERVAL_MS
NEAR_CORNER_M = 2.0  # within this of a corner, the next one is handed out
SAME_PLACE_M = 0.01  # ArduCopter's Locations are equal within 1e-7 degree


@dataclass(frozen=True)
class Answer:
    """A plan for a request: its state and, when SUCCESS, the leg to fly (origin, destination and
    the point after it, the request's destination past the last corner); dest_to_next_clear: the
    way from the request's destination to its next one crosses no fence; bendy: BendyRuler's
    answer (a point for the position controller, not a leg)."""
    state: str
    origin: Vec2 | None = None
    destination: Vec2 | None = None
    next_destination: Vec2 | None = None
    dest_to_next_clear: bool = True
    bendy: bool = False
    height: float | None = None  # vertical BendyRuler's point's height (local frame, up)


@dataclass(frozen=True)
class _Request:
    here: Vec2
    destination: Vec2
    next_destination: Vec2 | None
    velocity: Vec2 = (0.0, 0.0)  # the ground velocity (north, east) [m/s]
    heading_deg: float = 0.0
    home: Vec3 = (0.0, 0.0, 0.0)  # north, east, up
    here_up: float = 0.0


def _same(a: Vec2 | None, b: Vec2 | None) -> bool:
    if a is None or b is None:
        return a is b
    return math.hypot(a[0] - b[0], a[1] - b[1]) < SAME_PLACE_M


def past_finish_line(point: Vec2, start: Vec2, finish: Vec2) -> bool:
    """Whether `point` is at or past the line through `finish` square to start-finish
    (Location::past_interval_finish_line; start and finish together: past)."""
    dn, de = finish[0] - start[0], finish[1] - start[1]
    span = dn * dn + de * de
    if span < 0.001:
        return True
    return ((point[0] - start[0]) * dn + (point[1] - start[1]) * de) / span >= 1.0


class Dijkstra:
    """AP_OADijkstra's state: the fence's graph, the path to the destination and the corner it is at."""

    def __init__(self, notify: Callable[[str, int], None]):
        self._notify = notify
        self._graph: FenceGraph | None = None
        self._shapes: tuple[Shape, ...] | None = None
        self._graph_error: str | None = None
        self._path: list[Vec2] | None = None
        self._index = 1
        self._planned_for: tuple[Vec2, Vec2 | None] | None = None
        self._dest_to_next_clear = True
        self._reported: tuple[str, float] | None = None  # the last reason said, and when

    def plan(self, now_s: float, request: _Request, shapes: Sequence[Shape], margin: float) -> Answer:
        here, destination, following = request.here, request.destination, request.next_destination
        if _same(here, destination):
            self._dest_to_next_clear = False
            return Answer(NOT_REQUIRED, dest_to_next_clear=False)
        if self._shapes is None or tuple(shapes) != self._shapes:
            self._shapes, self._path = tuple(shapes), None
            try:
                self._graph, self._graph_error = FenceGraph(self._shapes, margin), None
            except PlanError as error:
                self._graph, self._graph_error = None, str(error)
        if self._graph is None:
            return self._failed(now_s, self._graph_error or "")
        if self._planned_for is None or not (_same(destination, self._planned_for[0])
                                             and _same(following, self._planned_for[1])):
            self._planned_for, self._path = (destination, following), None
        if self._path is None:
            try:
                self._path = self._graph.shortest_path(here, destination)
            except PlanError as error:
                return self._failed(now_s, str(error))
            self._index = 1
            self._dest_to_next_clear = following is not None and not self._graph.crosses(destination, following)
        path, index = self._path, self._index
        if index >= len(path) - 1:  # past the last corner (or a straight path): nothing in the way
            return Answer(NOT_REQUIRED, dest_to_next_clear=self._dest_to_next_clear)
        origin, corner = path[index - 1], path[index]
        after = path[index + 1] if index + 1 < len(path) - 1 else destination
        if math.dist(here, corner) <= NEAR_CORNER_M or past_finish_line(here, origin, corner):
            self._index += 1  # the next corner, from the next plan on
        return Answer(SUCCESS, origin, corner, after, self._dest_to_next_clear)

    def recalculate(self) -> None:
        """The path afresh from where the vehicle is at the next plan (BendyRuler took it aside)."""
        self._path = None

    def _failed(self, now_s: float, reason: str) -> Answer:
        self._path = None
        self._dest_to_next_clear = False
        last = self._reported
        if last is None or last[0] != reason or now_s - last[1] > REPORT_EVERY_S:
            self._notify(f"Dijkstra: {reason}", Severity.CRITICAL)
            self._reported = (reason, now_s)
        return Answer(ERROR, dest_to_next_clear=False)


class PathPlanner:
    """AP_OAPathPlanner: the planner OA_TYPE made at boot, asked by the waypoint legs."""

    def __init__(self, params: ParamStore, fence_shapes: Callable[[], Sequence[Shape]], fence: FenceSwitch,
                 notify: Callable[[str, int], None]):
        """`fence_shapes()`: the stored fence's shapes; `fence`: which fences are on."""
        self._params = params
        self._fence_shapes = fence_shapes
        self._fence = fence
        self.kind_at_boot = int(params["OA_TYPE"])
        self._made = NEEDS.get(self.kind_at_boot, set())  # the planners made at boot
        self._dijkstra = Dijkstra(notify)
        self._bendy = BendyRuler()
        # The obstacle database, made with the planner thread (OA_TYPE 1-3 at boot)
        self.database = ObstacleDatabase(params) if self._made else None
        if self.database is not None and self.database.init_failure is not None:
            notify(self.database.init_failure, Severity.INFO)
        self._proximity_only = True  # OA_TYPE 3: BendyRuler looks at the database alone
        self._answer: tuple[_Request, Answer] | None = None  # the last plan, for the request it was made for
        self._answer_s = -math.inf
        self._tick = -1  # the planning period of the last request
        self._asked_s = -math.inf
        self._activated_s = 0.0

    def prearm_failure(self) -> str | None:
        """ArduCopter's "Check Object Avoidance": OA_TYPE names a planner not made at boot."""
        kind = int(self._params["OA_TYPE"])
        return REBOOT_TEXTS[kind] if not NEEDS.get(kind, set()) <= self._made else None

    @property
    def options(self) -> int:
        return int(self._params["OA_OPTIONS"])

    def avoid(self, now_s: float, here: Vec2, destination: Vec2, next_destination: Vec2 | None,
              velocity: Vec2 = (0.0, 0.0), heading_deg: float = 0.0, home: Vec3 = (0.0, 0.0, 0.0),
              here_up: float = 0.0) -> Answer:
        """The plan for flying from `here` (`here_up` high) to `destination` (then on to
        `next_destination`), the vehicle moving at `velocity` (north, east) facing `heading_deg`,
        home at `home` (north, east, up): AP_OAPathPlanner::mission_avoidance."""
        kind = int(self._params["OA_TYPE"])
        if kind == DISABLED or not self._made:  # (no planner thread was made)
            return Answer(NOT_REQUIRED)
        since_asked = now_s - self._asked_s
        if since_asked > REQUEST_GAP_S:
            self._activated_s = now_s
        self._asked_s = now_s
        request = _Request(here, destination, next_destination, velocity, heading_deg, home, here_up)
        # A plan every PLAN_EVERY_S, for the request made just before it (one made after a long
        # silence waits for the next, as a request the thread did not see yet)
        tick = math.floor(now_s / PLAN_EVERY_S)
        if tick != self._tick and since_asked <= PLAN_EVERY_S:
            self._plan(now_s, kind, request)
        self._tick = tick
        answer = self._answer
        timed_out = now_s - self._answer_s > ANSWER_TIMEOUT_S and now_s - self._activated_s > ANSWER_TIMEOUT_S
        if (answer is not None and _same(answer[0].destination, destination)
                and _same(answer[0].next_destination, next_destination) and not timed_out):
            return answer[1]
        return Answer(ERROR) if timed_out else Answer(PROCESSING)

    def _plan(self, now_s: float, kind: int, request: _Request) -> None:
        if not NEEDS.get(kind, {DISABLED}) <= self._made:
            return  # a planner not made at boot: no answer (a timeout, as ArduCopter's)
        shapes = self._fence_shapes()
        if self.database is not None:
            self.database.expire(now_s)
        if kind == BENDY_RULER:
            self._answer, self._answer_s = (request, self._bendy_plan(request, shapes, False)), now_s
            return
        if kind == DIJKSTRA_BENDY_RULER:
            # BendyRuler round what the proximity sensor saw until clear of it, then Dijkstra's
            # path afresh from where that left the vehicle
            answer = self._bendy_plan(request, shapes, self._proximity_only)
            if answer.state == SUCCESS:
                self._proximity_only = False
                self._answer, self._answer_s = (request, answer), now_s
                return
            if not self._proximity_only:
                self._dijkstra.recalculate()
            self._proximity_only = True
        fenced = any(s.kind == "poly" or not s.inclusion for s in shapes)
        if not fenced or not self._fence.enabled_fences & POLYGON:
            answer = Answer(NOT_REQUIRED)
        else:
            answer = self._dijkstra.plan(now_s, request, shapes, float(self._params["OA_MARGIN_MAX"]))
        self._answer, self._answer_s = (request, answer), now_s

    def _bendy_plan(self, request: _Request, shapes: Sequence[Shape], proximity_only: bool) -> Answer:
        p = self._params
        home = request.home
        db = self.database
        fence = FenceView(tuple(shapes), self._fence.enabled_fences, float(p["FENCE_RADIUS"]),
                          float(p["FENCE_MARGIN"]), (home[0], home[1]), float(p["FENCE_ALT_MAX"]), home[2],
                          db.obstacles if db is not None and db.healthy else None, request.here_up, proximity_only)
        settings = Settings(float(p["OA_BR_LOOKAHEAD"]), float(p["OA_BR_CONT_RATIO"]), float(p["OA_BR_CONT_ANGLE"]),
                            float(p["OA_MARGIN_MAX"]))
        height = None
        if int(p["OA_BR_TYPE"]) == VERTICAL:
            here = (*request.here, request.here_up)
            active, (n, e, height) = self._bendy.update_vertical(here, request.destination, fence, settings)
            point = (n, e)
        else:
            active, point = self._bendy.update(request.here, request.destination, request.velocity,
                                               request.heading_deg, fence, settings)
        if not active:
            return Answer(NOT_REQUIRED, dest_to_next_clear=False)
        return Answer(SUCCESS, request.here, point, None, dest_to_next_clear=False, bendy=True, height=height)
