"""What a flight mode sees of the vehicle, and all it may do to it.

Modes get this context, never the vehicle: what they read and the few things they may change
are listed here and nowhere else. It reads through to the vehicle's parts, so it is always
current, also when a mode is entered between two ticks (a command from a ground station).
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from operator import attrgetter
from typing import TYPE_CHECKING

from ..views import FollowTargetView, ModeHost, Notify, ReadThrough, Vector3

if TYPE_CHECKING:
    from firefly.sim.geo import GeoPoint
    from firefly.sim.rigid_body import BodyState

    from ..mission.progress import MissionProgress
    from ..optical_flow import FlowReading
    from ..precland import Steer
    from ..params import ParamStore
    from ..payload.camera import Camera
    from ..payload.mount import Mount
    from ..payload.gripper import Gripper
    from ..payload.parachute import Parachute
    from ..payload.sprayer import Sprayer
    from ..payload.winch import Winch
    from ..pilot import PilotInput
    from .return_path import ReturnPath
    from ..path_planning.planner import PathPlanner
    from ..results import Result


class ModeContext:
    """State (read only):
        body          the state estimate: n_m, e_m, d_m, vn_m_s, ve_m_s, vd_m_s, quaternion, rates
        attitude      (roll, pitch, yaw) in radians
        params        the parameter store (ArduCopter names and units)
        pilot         the pilot's sticks (PilotInput), centred when none arrive
        armed, landed, time_s (sim seconds), home_ned (None until home is set)
        enabled_fences the fences on (FENCE_TYPE bits: 1 ceiling, 2 circle, 4 polygon, 8 floor)
        height_ref_d  the down coordinate heights are measured from (home, or the boot ground)
        nav_speed_m_s the horizontal speed AUTO and GUIDED fly (WPNAV_SPEED, DO_CHANGE_SPEED)
        has_position() whether the horizontal position is known (3D GPS fix)
        auto_armed    AUTO may start its mission from the ground
        interlock_at_s when the arming delay ends and the motors may spin (sim seconds)
        origin_alt_m  altitude of the local frame's origin above sea level
        ned_of(lat, lon, alt_amsl) -> (n, e, d) in the local frame
        position_global() where the vehicle is (GeoPoint: degrees, metres above sea level)
        armed_at_s    when the vehicle last armed (sim seconds)
        optical_flow  the flow sensor's last sample (optical_flow.FlowReading); optical_flow_healthy()
        accel_body    what the accelerometer reads (FRD, m/s^2): 1 g up at rest, 0 in free fall
        mode_number   the vehicle's mode: while a mode's enter() runs, the one it would take over from
        hover_thrust_share the airframe's weight over its full thrust
        unix_time_us() the UTC clock (sim time from a fixed epoch: NAV_DELAY's time of day)
    Actions:
        notify(text, severity)   a STATUSTEXT
        disarm(reason)           a Result: FAILED while flying
        mission_progress         mission/progress.py: AP_Mission's rules; AUTO binds itself as its
                                 runner and drives it (start_or_resume, update, stop)
        return_path              modes/return_path.py: the way back SMART_RTL takes (pop, peek)
        path_planner             path_planning/planner.py: OA_TYPE's planner round the fence, asked by
                                 the waypoint legs of a mode that plans_paths (avoid, options)
        follow_target            follow_target.py: the lead FOLLOW flies after (views.FollowTargetView):
                                 update(now, own position), the point to fly to, the lead's heading
        camera                   payload/camera.py: CAM1, as the mission's camera items drive it
        mount                    payload/mount.py: MNT1, as the mission's mount and ROI items drive it
        parachute, sprayer, gripper, winch payload/parachute.py, sprayer.py, gripper.py, winch.py:
                                 as the mission's DO_PARACHUTE, DO_SPRAYER, DO_GRIPPER and DO_WINCH
                                 drive them
        set_speed(m_s)           as DO_CHANGE_SPEED
        set_home(ned or None)    as DO_SET_HOME (None = here)
        fence_enable_item(action) as the mission's DO_FENCE_ENABLE (0 off, 1 on, 2 the floor off)
        set_servo(channel, pwm), repeat_servo(channel, pwm, count, cycle_s), set_relay(relay,
        state), repeat_relay(relay, count, cycle_s)
                                 as DO_SET_SERVO / DO_REPEAT_SERVO / DO_SET_RELAY /
                                 DO_REPEAT_RELAY (servo_relay.py)
        set_mode(number)         hand over to another mode, with that mode's entry rules (a
                                 Result); a mode that hands over stops filling the setpoint
        restart_position_control() the position loop starts from the present velocity (a mode
                                 that flew attitudes hands back to it, as on a mode change)
        use_gains(gains or None) the controllers fly these ATC_* gains in place of the parameters'
                                 (AUTOTUNE's trial sets); None: the parameters' own again
        precland_landing(land_speed_m_s) what precision landing makes of a landing (precland.py's
                                 Steer: a point, a descent rate, a retry's height), None without it
        avoid_velocity(vel_neu, accel, dt) a wanted velocity (north, east, up) as simple avoidance
                                 lets it be flown, accel the mode's horizontal limit (m/s/s)
        avoid_climb(climb, dt)   a pilot's climb rate as the altitude fences let it be flown
        avoid_lean(lean)         ALT_HOLD's (roll, pitch) pushed away from what the proximity sensor sees
        destination_within_fence(n, e, d) a GUIDED destination (local NED) inside every enabled fence
        terrain_offset_m()       the terrain's height above the origin under the vehicle [m], from
                                 the terrain source, None while it has none there
        terrain_source()         AC_WPNav's terrain source: "rangefinder", "database" or None
        terrain_offset_at(n, e)  the terrain database's height above the origin at a local point
        terrain_failsafe()       terrain missing where a mode needs it: the failsafe's action
        terrain_status(found)    a terrain leg's step found its terrain offset or not (the failsafe's timer)
    """
    __slots__ = ("_v", "_estimate", "_arming", "_land", "_sim", "params", "mission_progress", "return_path", "path_planner",
                 "follow_target", "camera", "mount", "parachute", "sprayer", "gripper", "winch", "notify", "disarm", "set_speed",
                 "set_home", "fence_enable_item",
                 "set_servo", "repeat_servo", "set_relay", "repeat_relay", "ned_of", "position_global", "set_mode",
                 "hover_thrust_share", "restart_position_control", "use_gains", "precland_landing",
                 "avoid_velocity", "avoid_climb", "avoid_lean", "destination_within_fence",
                 "terrain_offset_m", "terrain_source", "terrain_offset_at", "terrain_failsafe", "terrain_status")
    params: ParamStore
    mission_progress: MissionProgress
    return_path: ReturnPath
    path_planner: PathPlanner
    follow_target: FollowTargetView
    camera: Camera
    mount: Mount
    parachute: Parachute
    sprayer: Sprayer
    gripper: Gripper
    winch: Winch
    notify: Notify
    disarm: Callable[[str], Result]
    set_speed: Callable[[float], Result]
    set_home: Callable[[Vector3 | None], Result]
    fence_enable_item: Callable[[int], None]
    set_servo: Callable[[int, int], Result]
    repeat_servo: Callable[[int, int, int, float], Result]
    set_relay: Callable[[int, int], Result]
    repeat_relay: Callable[[int, int, float], Result]
    ned_of: Callable[[float, float, float], Vector3]
    position_global: Callable[[], GeoPoint]
    set_mode: Callable[[int], Result]
    restart_position_control: Callable[[], None]
    use_gains: Callable[[Mapping[str, float] | None], None]
    precland_landing: Callable[[float], Steer | None]
    avoid_velocity: Callable[[Vector3, float, float], Vector3]
    avoid_climb: Callable[[float, float], float]
    avoid_lean: Callable[[tuple[float, float]], tuple[float, float]]
    destination_within_fence: Callable[[float, float, float], bool]
    terrain_offset_m: Callable[[], float | None]
    terrain_source: Callable[[], str | None]
    terrain_offset_at: Callable[[float, float], float | None]
    terrain_failsafe: Callable[[], None]
    terrain_status: Callable[[bool], None]

    def __init__(self, vehicle: ModeHost):
        self._v = vehicle
        self._estimate = vehicle.estimate
        self._arming = vehicle.arming
        self._land = vehicle.land_detector
        self._sim = vehicle.sim
        self.params = vehicle.params
        self.mission_progress = vehicle.mission_progress
        self.return_path = vehicle.return_path
        self.path_planner = vehicle.path_planner
        self.follow_target = vehicle.follow_target
        self.camera = vehicle.camera
        self.mount = vehicle.mount
        self.parachute = vehicle.parachute
        self.sprayer = vehicle.sprayer
        self.gripper = vehicle.gripper
        self.winch = vehicle.winch
        self.notify = vehicle.notify
        self.disarm = vehicle.disarm
        self.set_speed = vehicle.set_speed
        self.set_home = vehicle.set_home
        self.fence_enable_item = vehicle.fence_enable_item
        self.set_servo = vehicle.set_servo
        self.repeat_servo = vehicle.repeat_servo
        self.set_relay = vehicle.set_relay
        self.repeat_relay = vehicle.repeat_relay
        self.ned_of = vehicle.ned_of
        self.position_global = vehicle.position_global
        self.set_mode = vehicle.set_mode
        self.restart_position_control = vehicle.restart_position_control
        self.use_gains = vehicle.use_gains
        self.precland_landing = vehicle.precland_landing
        self.avoid_velocity = vehicle.avoid_velocity
        self.avoid_climb = vehicle.avoid_climb
        self.avoid_lean = vehicle.avoid_lean
        self.destination_within_fence = vehicle.destination_within_fence
        self.terrain_offset_m = vehicle.terrain_offset_m
        self.terrain_source = vehicle.terrain_source
        self.terrain_offset_at = vehicle.terrain_offset_at
        self.terrain_failsafe = vehicle.terrain_failsafe
        self.terrain_status = vehicle.terrain_status
        airframe = vehicle.sim.airframe
        self.hover_thrust_share = airframe.weight_n / (4.0 * airframe.max_rotor_thrust_n)

    # Read-through properties as C-level attribute getters: modes read them at 100 Hz per vehicle.
    body: ReadThrough[BodyState] = property(attrgetter("_estimate.body"))
    attitude: ReadThrough[Vector3] = property(attrgetter("_estimate.attitude"))
    pilot: ReadThrough[PilotInput] = property(attrgetter("_v.rc.pilot"))
    armed: ReadThrough[bool] = property(attrgetter("_arming.armed"))
    landed: ReadThrough[bool] = property(attrgetter("_land.landed"))
    terrain_failsafe_on: ReadThrough[bool] = property(attrgetter("_v.terrain_failsafe_on"))
    landed_at_s: ReadThrough[float] = property(attrgetter("_land.landed_at_s"))
    time_s: ReadThrough[float] = property(attrgetter("_sim.time_s"))
    home_ned: ReadThrough[Vector3 | None] = property(attrgetter("_v.home_ned"))
    height_ref_d: ReadThrough[float] = property(attrgetter("_v.height_ref_d"))
    nav_speed_m_s: ReadThrough[float] = property(attrgetter("_v.nav_speed_m_s"))
    auto_armed: ReadThrough[bool] = property(attrgetter("_arming.auto_armed"))
    armed_yaw: ReadThrough[float] = property(attrgetter("_arming.armed_yaw"))  # heading at arming [rad]
    interlock_at_s: ReadThrough[float] = property(attrgetter("_arming.interlock_at_s"))  # the arming delay's end
    origin_alt_m: ReadThrough[float] = property(attrgetter("_v.origin.alt_m"))
    accel_body: ReadThrough[Vector3] = property(attrgetter("_estimate.accel_body"))
    mode_number: ReadThrough[int] = property(attrgetter("_v.mode_number"))
    armed_at_s: ReadThrough[float] = property(attrgetter("_arming.armed_at_s"))  # when last armed
    optical_flow: ReadThrough[FlowReading] = property(attrgetter("_v.optical_flow.reading"))  # its last sample
    precland_kind: ReadThrough[int] = property(attrgetter("_v.precland.kind"))  # PLND_TYPE's sensor, 0 none
    enabled_fences: ReadThrough[int] = property(attrgetter("_v.fence.enabled_fences"))  # AC_FENCE_TYPE_* bits on

    def unix_time_us(self) -> int:
        return self._v.unix_time_us()

    def optical_flow_healthy(self) -> bool:
        return self._v.optical_flow.healthy(self._sim.time_s)

    def has_position(self) -> bool:
        return self._estimate.has_position()

    def require_home(self) -> Vector3:
        """Home (local NED), for a mode that declares requires_home: the vehicle runs such a
        mode only once home is set, so a None here is a bug, raised as one (an internal error)."""
        home = self._v.home_ned
        if home is None:
            raise MissingRequirement("home read by a mode that does not declare requires_home")
        return home


class MissingRequirement(RuntimeError):
    """A mode read what the vehicle does not have and the mode did not declare it needs."""
