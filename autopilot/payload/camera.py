"""The autopilot's own camera driver, as ArduPilot's AP_Camera runs CAM1 (CAM1_TYPE 1: a servo
output, 2: a relay, 6: a MAVLink camera v2) for the commands and mission items that reach it.

CAM1_TYPE 6 (AP_Camera_MAVLinkCamV2) drives the thermal camera, a component of the vehicle's own
system (mavlink/camera_component.py), when one is fitted: each picture is an IMAGE_START_CAPTURE
for one still sent to it (with the next image number as its sequence), and the picture is counted,
reported and logged here as any other. ArduPilot looks for the camera's heartbeat for 60 s after
boot and asks it for CAMERA_INFORMATION until it answers; the camera of this process is there from
boot, so it is found at once. Without it, no picture is taken (a command asking for one FAILS).

A picture (take_picture) is refused while CAM1_INTRVAL_MIN has not passed since the last one (it
is then taken as soon as it has: pending) and while the shutter is still held from the last one.
Taken, it moves the shutter: the outputs whose SERVOn_FUNCTION is the camera trigger (10) go to
CAM1_SERVO_ON, or the relays whose RELAYn_FUNCTION is the camera (4) to CAM1_RELAY_ON, for
CAM1_DURATION; it counts the image and stores its feedback (where and how the vehicle was, with
the GPS time), which the MAVLink layer sends as CAMERA_FEEDBACK to every link.

update() runs at AP_Camera's 50 Hz, only while something is to do (busy): the shutter or the ISO
output held, a continuous zoom or focus, a picture pending, an interval capture
(IMAGE_START_CAPTURE) or distance triggering on (a CAM1_TRIGG_DIST above 0, also set by
DO_SET_CAM_TRIGG_DIST). An interval capture takes a picture each time the interval has passed
since the last one and, while it runs, distance triggering waits. Distance triggering takes one
each time the vehicle is CAM1_TRIGG_DIST from where the last one was taken (the first position it
sees is the start), in AUTO only if CAM_AUTO_ONLY says so, and not while rolled beyond
CAM_MAX_ROLL (0: any roll).

A servo camera also drives a lens: the outputs whose SERVOn_FUNCTION is the camera's zoom (180) or
focus (92) each hold a position of 0..1000 over SERVOn_MIN..MAX, put in the middle at boot. A zoom
or focus asked as a percentage sets it (held to 0..100 %); asked as a rate (SET_CAMERA_ZOOM's and
_FOCUS's continuous type: -1 out, 0 hold, 1 in) moves it by that much at each 50 Hz update until
held, within its range (measured: 40 us/s on a 1100-1900 output). It has no autofocus, and a relay
camera neither zoom nor focus; nor has the thermal camera CAM1_TYPE 6 drives (ArduPilot passes a
zoom or focus to a MAVLink camera only if its CAMERA_INFORMATION says it has one: FAILED for a
focus, refused for a zoom). CAMERA_SETTINGS reports neither (NaN), as ArduCopter's does. Its
ISO output (SERVOn_FUNCTION 90) sits at CAM1_SERVO_OFF and is pulsed like the shutter by a
DO_DIGICAM_CONFIGURE asking for an ISO; its aperture (91) and shutter-speed (93) outputs are put
at the PWM one asks for (configure()).

CAM1_TYPE is read at boot, as ArduPilot builds its camera backend once: a change takes effect
after a reboot. Left 0 with an output set to the camera trigger, it becomes 1 at boot (ArduPilot
converts a CAM1_TYPE it has not stored from the older settings so). With no camera every command
still answers as ArduCopter's does, and nothing runs.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

from ..c_casts import as_uint16, float32
from ..params import ParamStore
from ..results import Result
from ..views import CameraView
from .outputs import Constrain, outputs_of, range_pwm

NONE, SERVO, RELAY, MAVLINK_CAMV2 = 0, 1, 2, 6  # CAM1_TYPE
TRIGGER_FUNCTION = 10  # SERVOn_FUNCTION: camera trigger (SRV_Channel k_cam_trigger)
RELAY_CAMERA_FUNCTION = 4  # RELAYn_FUNCTION: camera
UPDATE_S = 0.02  # AP_Camera::update's rate, 50 Hz
UPDATES_PER_S = 50  # how AP_Camera counts CAM1_DURATION down: updates at 50 Hz
CAPTURE_FOREVER = -1
CHANNELS, RELAYS = 16, 6
AUTO = 3  # mode number
YAW_FULL_TURN_F32 = 359.99998  # from here up a float32 rounds to 360
ZOOM_FUNCTION, FOCUS_FUNCTION = 180, 92  # SERVOn_FUNCTION: camera zoom (k_cam_zoom), camera focus (k_cam_focus)
# SERVOn_FUNCTION: the camera's ISO, aperture and shutter speed (k_cam_iso, _aperture, _shutter_speed)
ISO_FUNCTION, APERTURE_FUNCTION, SHUTTER_SPEED_FUNCTION = 90, 91, 93
LENS_FULL = 1000.0  # a lens output's range (SRV_Channel's set_range(1000)): SERVOn_MIN at 0, _MAX at 1000
LENS_START = 500.0  # where a servo camera puts its zoom and focus at boot
# How a zoom or focus is asked (AP_Camera's ZoomType and FocusType)
RATE, PERCENT, AUTOFOCUS = "rate", "percent", "auto"
# MAVLink's ZOOM_TYPE and SET_FOCUS_TYPE as AP_Camera takes them, for a command or a mission item:
# a zoom continuous (1) or to a percentage (2); a focus continuous (1), to a percentage (2) or auto
# (4, 5, 6). A zoom of another type is refused; a focus of another (a step, metres) is DENIED.
ZOOM_TYPES = {1: RATE, 2: PERCENT}
FOCUS_TYPES = {1: RATE, 2: PERCENT, 4: AUTOFOCUS, 5: AUTOFOCUS, 6: AUTOFOCUS}


class Feedback(NamedTuple):
    """One picture as CAMERA_FEEDBACK reports it."""
    time_usec: int  # GPS time the picture was taken
    image_index: int  # pictures taken since boot, this one included
    lat_e7: int
    lon_e7: int
    alt_msl_m: float  # to the centimetre, as ArduPilot's Location holds it
    alt_rel_m: float
    roll_deg: float
    pitch_deg: float
    yaw_deg: float  # 0..360


class CameraStatus(NamedTuple):
    """What the camera's messages report (mavlink/camera_messages.py)."""
    present: bool
    image_index: int
    interval_s: float  # an interval capture's, 0 if none
    capturing: bool  # an interval capture with pictures still to take
    feedback: Feedback | None
    mavlink_camera: Any = None  # CAM1_TYPE 6: the camera found (its CAMERA_INFORMATION is sent for it)
    kind: int = NONE  # CAM1_TYPE as read at boot


class LensOutput:
    """A servo camera's zoom or focus: a position of 0..LENS_FULL (float32, as AP_Camera_Servo keeps
    it), set to a percentage or moved by `rate` at each update; put out on the outputs of its
    SERVOn_FUNCTION."""

    def __init__(self, function: int, constrain: Constrain):
        self.function = function
        self._constrain = constrain
        self.position = LENS_START
        self.rate = 0.0

    def set_percent(self, percent: float) -> None:
        self.position = self._constrain(float32(float32(percent) * 10.0), 0.0, LENS_FULL)

    def step(self) -> None:
        self.position = self._constrain(float32(self.position + self.rate), 0.0, LENS_FULL)

    def put_out(self, params: ParamStore, servo_pwm: list[int]) -> None:
        for output in outputs_of(params, self.function):
            servo_pwm[output - 1] = range_pwm(params, output, self.position / LENS_FULL)


class Camera:
    def __init__(self, view: CameraView, params: ParamStore, servo_pwm: list[int], relays: list[bool],
                 on_nan: Callable[[], None] = lambda: None):
        self._v = view  # the vehicle, read-only
        self.params = params
        if params["CAM1_TYPE"] == NONE and any(params.get(f"SERVO{i}_FUNCTION", 0) == TRIGGER_FUNCTION
                                               for i in range(1, CHANNELS + 1)):
            # AP_Camera::convert_params: a CAM1_TYPE never set (the default, which is not
            # stored) becomes a servo camera when an output is the camera trigger, and is saved
            params.set("CAM1_TYPE", SERVO)
        self.kind = int(params["CAM1_TYPE"])
        self.present = self.kind in (SERVO, RELAY, MAVLINK_CAMV2)
        # CAM1_TYPE 6: the MAVLink camera it drives (a CameraComponent, set when the thermal camera
        # is fitted), or None: no camera found
        self.mavlink_camera = None
        self._servo_pwm, self._relays = servo_pwm, relays  # the outputs it drives (servo_relay.py's)
        self.image_index = 0
        self.feedback: Feedback | None = None  # the last picture's
        self.feedback_due = False  # a picture not yet reported on the links
        # Who else hears of each picture (the dataflash log's CAM records): set by the I/O edge
        self.picture_listener: Callable[[Feedback], None] | None = None
        self.busy = False
        self.interval_s = 0.0  # an interval capture: seconds between pictures
        self.remaining = 0  # ... pictures still to take (CAPTURE_FOREVER: no end)
        self.trigg_dist_m = params["CAM1_TRIGG_DIST"]
        self._pending = False
        self._hold = 0  # updates the shutter stays open
        self._last_picture_s = 0.0
        self._last_ne: tuple[float, float] | None = None  # where distance triggering measures from
        self._next_update_s = 0.0
        self._shutter_open = False
        self._trigger_outputs: tuple[int, ...] = ()  # 0-based outputs or relays the shutter moves
        self._iso_hold = 0  # updates until the ISO output goes off (DO_DIGICAM_CONFIGURE); 0: off
        # A servo camera's lens (its zoom and focus outputs); `on_nan`: the vehicle's constraining_nan
        constrain = Constrain(on_nan)
        self.lens = (LensOutput(ZOOM_FUNCTION, constrain), LensOutput(FOCUS_FUNCTION, constrain))
        if self.present:
            params.on_change(self._param_changed)
            self._find_outputs()
            self._shutter(False)
            self._put_out_lens()
            if self.kind == SERVO:
                self._put(ISO_FUNCTION, int(params["CAM1_SERVO_OFF"]))  # AP_Camera_Servo's update, from boot

    def status(self) -> CameraStatus:
        return CameraStatus(self.present, self.image_index, self.interval_s, self.remaining > 0, self.feedback,
                            self.mavlink_camera, self.kind)

    # ----- what commands and mission items ask ---------------------------------------------------
    def take_picture(self) -> bool:
        """One picture now; False if refused (too soon after the last: taken once it may be)."""
        if not self.present:
            return False
        v = self._v
        now = v.time_s
        if now - self._last_picture_s < self.params["CAM1_INTRVAL_MIN"] - 1e-9:
            self._pending = self.busy = True
            return False
        self._pending = False
        if self._hold > 0:  # the shutter is still held from the last picture
            return False
        if self.kind == MAVLINK_CAMV2:  # the camera takes it: no shutter output to hold
            if self.mavlink_camera is None or not self.mavlink_camera.trigger(self.image_index + 1):
                return False
        else:
            self._shutter(True)
            self._hold = self._hold_updates()
        self.image_index = (self.image_index + 1) & 0xFFFF  # ArduPilot's count is a uint16
        self._last_picture_s = now
        b = v.body
        self._last_ne = (b.n_m, b.e_m)
        self.feedback = self._feedback(v, self.image_index)
        self.feedback_due = self.busy = True
        if self.picture_listener is not None:
            self.picture_listener(self.feedback)
        return True

    def control(self, shoot: float) -> None:
        """DO_DIGICAM_CONTROL: its shooting command 1 takes a picture (nothing else is modelled)."""
        if self.present and shoot == 1:
            self.take_picture()

    def configure(self, shutter_speed: float, aperture: float, iso: float) -> None:
        """DO_DIGICAM_CONFIGURE, as a servo camera takes it (made for a Blackmagic Micro Cinema
        Camera): an ISO above 0 pulses the ISO outputs to CAM1_SERVO_ON for CAM1_DURATION, an
        aperture or a shutter speed above 0 puts those outputs at that many microseconds (measured:
        1234 and 125 us stay). Its shooting mode would put the focus outputs at that PWM until the
        next update puts the focus back (20 ms): not modelled. Any other camera: nothing shows."""
        if self.kind != SERVO:
            return
        if iso > 0:
            self._iso_hold = self._hold_updates() + 1  # on, then off at the update after the count
            self._put(ISO_FUNCTION, int(self.params["CAM1_SERVO_ON"]))
            self._check_busy()
        for function, pwm in ((APERTURE_FUNCTION, aperture), (SHUTTER_SPEED_FUNCTION, shutter_speed)):
            if pwm > 0:
                self._put(function, as_uint16(pwm))

    def set_zoom(self, how: str, value: float) -> bool:
        """SET_CAMERA_ZOOM (`how` RATE or PERCENT): True if taken, which only a servo camera does."""
        if self.kind != SERVO or how not in (RATE, PERCENT):
            return False
        self._move_lens(self.lens[0], how, value)
        return True

    def set_focus(self, how: str, value: float) -> Result:
        """SET_CAMERA_FOCUS (`how` RATE, PERCENT or AUTOFOCUS), answered as AP_Camera answers: FAILED
        with no camera (or a MAVLink camera without focus), UNSUPPORTED for what it cannot do."""
        if not self.present or self.kind == MAVLINK_CAMV2:
            return Result.FAILED
        if self.kind != SERVO or how not in (RATE, PERCENT):
            return Result.UNSUPPORTED
        self._move_lens(self.lens[1], how, value)
        return Result.ACCEPTED

    def _move_lens(self, lens: LensOutput, how: str, value: float) -> None:
        if how == PERCENT:
            lens.set_percent(value)
            self._put_out_lens()
        else:
            lens.rate = float32(value)
            self._check_busy()

    def set_trigger_distance(self, distance_m: float) -> None:
        """DO_SET_CAM_TRIGG_DIST: CAM1_TRIGG_DIST for now (not saved, as AP_Param::set)."""
        if not self.present:
            return
        self.trigg_dist_m = distance_m
        self.params.report("CAM1_TRIGG_DIST", distance_m)
        self._check_busy()

    def take_pictures(self, interval_s: float, count: int) -> bool:
        """IMAGE_START_CAPTURE with an interval: `count` pictures (CAPTURE_FOREVER: until stopped),
        the first at the next update; False with no camera."""
        if not self.present:
            return False
        self.interval_s, self.remaining = interval_s, count
        self._check_busy()
        return True

    def stop_capture(self) -> None:
        self.interval_s, self.remaining = 0.0, 0
        self._check_busy()

    def is_instance(self, index: int | None) -> bool:
        """Whether camera `index` (0-based; None: every camera) is there: CAM1 only."""
        return self.present and (index is None or index == 0)

    def start_capture(self, index: int | None, interval_s: float, count: int) -> bool:
        """IMAGE_START_CAPTURE as AP_Camera reads it, for a command or a mission item: one picture
        when `count` is 1 or both are 0; else pictures every `interval_s` (whole milliseconds,
        not 0), `count` of them or, for 0, until stopped. False: no such camera, no picture
        (too soon) or no interval."""
        if not self.is_instance(index):
            return False
        if count == 1 or (interval_s == 0 and count == 0):
            return self.take_picture()
        interval_ms = int(interval_s * 1000) & 0xFFFFFFFF if math.isfinite(interval_s) and interval_s > 0 else 0
        if interval_ms == 0:
            return False
        return self.take_pictures(interval_ms / 1000.0, CAPTURE_FOREVER if count == 0 else count)

    def trigger_distance(self, distance_m: float, shoot_now: bool) -> None:
        """DO_SET_CAM_TRIGG_DIST, command or mission item: the distance, and a picture now if asked."""
        self.set_trigger_distance(distance_m)
        if shoot_now:
            self.take_picture()

    # ----- the 50 Hz update ----------------------------------------------------------------------
    def update(self) -> None:
        """AP_Camera's update, at 50 Hz of sim time; the vehicle calls it while busy. Busy again
        after a rest, the camera runs at the vehicle's next step and every 0.02 s from there, as
        ArduPilot's scheduler runs it at its next 50 Hz step (a rest is no update: never two in
        one period)."""
        v = self._v
        now = v.time_s
        if now < self._next_update_s - 1e-9:
            return
        if now - self._next_update_s >= UPDATE_S - 1e-9:  # idle until now: the 50 Hz steps start here
            self._next_update_s = now
        self._next_update_s += UPDATE_S
        if self._hold > 0:
            self._hold -= 1
        elif self._shutter_open:
            self._shutter(False)
        if self._iso_hold > 0:
            self._iso_hold -= 1
            if self._iso_hold == 0:
                self._put(ISO_FUNCTION, int(self.params["CAM1_SERVO_OFF"]))
        if any(lens.rate != 0 for lens in self.lens):  # a continuous zoom or focus (NaN too)
            for lens in self.lens:
                lens.step()
            self._put_out_lens()
        if self._pending:
            self.take_picture()
        if self.remaining != 0:
            if now - self._last_picture_s >= self.interval_s - 1e-9 and self.take_picture() and self.remaining > 0:
                self.remaining -= 1
        else:
            self._by_distance()
        self._check_busy()

    def _by_distance(self) -> None:
        if not self.trigg_dist_m > 0:
            self._last_ne = None
            return
        params = self.params
        v = self._v
        if params["CAM_AUTO_ONLY"] != 0 and v.mode_number != AUTO:
            return
        max_roll = params["CAM_MAX_ROLL"]
        if max_roll > 0 and abs(math.degrees(v.attitude[0])) > max_roll:
            return
        b = v.body
        here = (b.n_m, b.e_m)
        last = self._last_ne
        if last is None:
            self._last_ne = here
            return
        if math.hypot(here[0] - last[0], here[1] - last[1]) >= self.trigg_dist_m:
            self.take_picture()

    def _check_busy(self) -> None:
        self.busy = self.present and (self._hold > 0 or self._pending or self.remaining != 0
                                      or self.trigg_dist_m > 0 or self._shutter_open or self._iso_hold > 0
                                      or any(lens.rate != 0 for lens in self.lens))

    # ----- the outputs ---------------------------------------------------------------------------
    def _find_outputs(self) -> None:
        """The outputs the shutter moves: read at boot and when an output's function changes."""
        get = self.params.get
        if self.kind == SERVO:
            self._trigger_outputs = tuple(i for i in range(CHANNELS)
                                          if get(f"SERVO{i + 1}_FUNCTION", 0) == TRIGGER_FUNCTION)
        elif self.kind == RELAY:
            self._trigger_outputs = tuple(i for i in range(RELAYS)
                                          if get(f"RELAY{i + 1}_FUNCTION", 0) == RELAY_CAMERA_FUNCTION)

    def _shutter(self, open_: bool) -> None:
        """The trigger outputs to CAM1_SERVO_ON / _OFF, or the camera relays to CAM1_RELAY_ON or not."""
        self._shutter_open = open_
        params = self.params
        if self.kind == SERVO:
            pwm = int(params["CAM1_SERVO_ON" if open_ else "CAM1_SERVO_OFF"])
            for i in self._trigger_outputs:
                self._servo_pwm[i] = pwm
        elif self.kind == RELAY:
            on = params["CAM1_RELAY_ON"] != 0
            for i in self._trigger_outputs:
                self._relays[i] = on if open_ else not on

    def _hold_updates(self) -> int:
        """CAM1_DURATION in 50 Hz updates, as AP_Camera counts it (a uint16)."""
        return min(int(self.params["CAM1_DURATION"] * UPDATES_PER_S), 65535)

    def _put(self, function: int, pwm: int) -> None:
        """A servo camera's outputs of `function` to `pwm`."""
        for output in outputs_of(self.params, function):
            self._servo_pwm[output - 1] = pwm

    def _put_out_lens(self) -> None:
        if self.kind == SERVO:
            for lens in self.lens:
                lens.put_out(self.params, self._servo_pwm)

    def _param_changed(self, name: str, value: float) -> None:
        if name == "CAM1_TRIGG_DIST":
            self.trigg_dist_m = value
            self._check_busy()
        elif name.endswith("_FUNCTION") and name.startswith(("SERVO", "RELAY")):
            self._find_outputs()
            self._shutter(self._shutter_open)
            self._put_out_lens()
            if self.kind == SERVO and self._iso_hold == 0:
                self._put(ISO_FUNCTION, int(self.params["CAM1_SERVO_OFF"]))
        elif name.startswith("SERVO") and name.endswith(("_MIN", "_MAX", "_REVERSED")):
            self._put_out_lens()  # SRV_Channels scales the lens outputs afresh at every loop

    @staticmethod
    def _feedback(v: CameraView, image_index: int) -> Feedback:
        pos = v.position_global()
        home = v.home
        alt_cm = round(pos.alt_m * 100)
        home_cm = round((home or v.origin).alt_m * 100)
        roll, pitch, yaw = v.attitude
        yaw_deg = math.degrees(yaw) % 360.0  # AHRS's yaw in degrees: 0..360
        if yaw_deg >= YAW_FULL_TURN_F32:  # a hair under north: the message's float32 would read 360
            yaw_deg = 0.0
        return Feedback(v.unix_time_us(), image_index, round(pos.lat_deg * 1e7), round(pos.lon_deg * 1e7),
                        alt_cm / 100.0, (alt_cm - home_cm) / 100.0, math.degrees(roll), math.degrees(pitch),
                        yaw_deg)
