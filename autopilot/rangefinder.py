"""The rangefinder RNGFND1, as ArduPilot's AP_RangeFinder runs its first instance.

RNGFND1_TYPE is read at boot, as ArduPilot makes its driver once: 100 reads the simulator's beam
(sim/rangefinder.py, ArduPilot SITL's own type), 10 takes the DISTANCE_SENSOR a companion sends
(those whose orientation is RNGFND1_ORIENT; none for 500 ms is no data); 0, or a type that names
hardware SITL does not have, makes none. Set to 0 while running, the driver stops until a reboot.
ArduCopter reads it at 20 Hz (update()).

Each reading has a status: no data (nothing yet, a beam that misses the ground, a companion gone
quiet), out of range low or high (below RNGFND1_MIN, above RNGFND1_MAX, both in metres and
inclusive), or good. Out of range is still data: DISTANCE_SENSOR goes on reporting it and the
sensor stays healthy; only good readings count towards the three in a row that make its height
trusted (valid_count). A companion's own min and max, when it sends any, narrow the parameters'.
Ranges and limits are float32s, as ArduPilot's (measured: a companion's 20 cm comes back as 19).
"""
from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

from .c_casts import float32
from .params import ParamStore

NONE, MAVLINK, SIM = 0, 10, 100  # RNGFND1_TYPE
DOWN = 25  # RNGFND1_ORIENT: ROTATION_PITCH_270
UPDATE_S = 0.05  # ArduCopter's read_rangefinder, 20 Hz
MAVLINK_TIMEOUT_S = 0.5  # a companion's rangefinder with nothing newer is no data
TERRAIN_HEIGHT_VALID_S = 5.0  # EKF3: a terrain height this long after its last range fused
VALID_COUNT_MAX = 10
CM_TO_M = float32(0.01)  # ArduPilot's 0.01, a float32: 20 cm reads 0.19999999 m, sent back as 19 cm
MAV_DISTANCE_SENSOR_UNKNOWN = 4  # the SITL driver's type in DISTANCE_SENSOR


class RangeStatus(IntEnum):
    NOT_CONNECTED = 0
    NO_DATA = 1
    OUT_OF_RANGE_LOW = 2
    OUT_OF_RANGE_HIGH = 3
    GOOD = 4


class RangeReading(NamedTuple):
    """What the messages and the checks read of the rangefinder (mavlink/rangefinder_messages.py)."""
    status: RangeStatus
    distance_m: float      # the last range, not corrected for tilt; after no data the one before
    min_m: float           # the limits the status was judged by
    max_m: float
    orientation: int
    sensor_type: int       # MAV_DISTANCE_SENSOR: the SITL driver's 4, a companion's own
    signal_quality: int    # -1 unknown, else 0-100
    valid_count: int       # good readings in a row, at most VALID_COUNT_MAX

    @property
    def has_data(self) -> bool:
        return self.status not in (RangeStatus.NOT_CONNECTED, RangeStatus.NO_DATA)


class Rangefinder:
    def __init__(self, params: ParamStore):
        self._params = params
        kind = int(params["RNGFND1_TYPE"])
        self.kind = kind if kind in (MAVLINK, SIM) else NONE  # the driver made at boot
        self._stopped = False  # RNGFND1_TYPE set to 0 since boot
        self._status = RangeStatus.NOT_CONNECTED
        self._distance_m = 0.0
        self._valid_count = 0
        self._quality = -1
        self._sensor_type = MAV_DISTANCE_SENSOR_UNKNOWN
        # the companion's last accepted DISTANCE_SENSOR: when, range [m], its own min and max [m]
        self._heard_s: float | None = None
        self._heard_m = 0.0
        self._heard_limits = (0.0, 0.0)
        self._heard_quality = -1
        self.last_good_s = -math.inf  # the last good reading facing down: the EKF's terrain height
        # ArduCopter's rangefinder_state.enabled: set at boot with a downward rangefinder, then by
        # the RANGEFINDER aux switch (switched()); SYS_STATUS's laser bit is enabled and healthy by it
        self.enabled = self.down

    def switched(self, high: bool) -> None:
        """The RANGEFINDER aux function: on in its high position if a rangefinder faces down, else off."""
        self.enabled = high and self.down

    @property
    def exists(self) -> bool:
        """A driver runs: made at boot and not stopped since."""
        return self.kind != NONE and not self._stopped

    @property
    def down(self) -> bool:
        """A driver runs facing down (ArduCopter's has_orientation(PITCH_270))."""
        return self.exists and int(self._params["RNGFND1_ORIENT"]) == DOWN

    def limits_m(self) -> tuple[float, float]:
        """(min, max) the readings are judged by: the parameters', narrowed by a companion's own."""
        low, high = float32(self._params["RNGFND1_MIN"]), float32(self._params["RNGFND1_MAX"])
        if self.kind == MAVLINK and self._heard_limits != (0.0, 0.0):
            return max(low, self._heard_limits[0]), min(high, self._heard_limits[1])
        return low, high

    def reading(self) -> RangeReading:
        low, high = self.limits_m()
        status = self._status if self.exists else RangeStatus.NOT_CONNECTED
        return RangeReading(status, self._distance_m, low, high, int(self._params["RNGFND1_ORIENT"]),
                            self._sensor_type, self._quality, self._valid_count if self.exists else 0)

    def update(self, now_s: float, beam_m: float) -> None:
        """ArduCopter's 20 Hz read: the simulator's beam `beam_m` (SIM) or the companion's last
        message (MAVLINK) becomes the reading."""
        if self.kind == NONE:
            return
        if int(self._params["RNGFND1_TYPE"]) == NONE:
            self._stopped = True
            self._set(RangeStatus.NOT_CONNECTED)
            return
        if self._stopped:
            return
        if self.kind == SIM:
            if not math.isfinite(beam_m):
                self._status = RangeStatus.NO_DATA  # as SITL's driver: the range and the count stay
                return
            self._distance_m = float32(max(0.0, beam_m))
        else:
            if self._heard_s is None or now_s - self._heard_s > MAVLINK_TIMEOUT_S:
                self._distance_m, self._quality = 0.0, -1
                self._set(RangeStatus.NO_DATA)
                return
            self._distance_m, self._quality = self._heard_m, self._heard_quality
        low, high = self.limits_m()
        if self._distance_m > high:
            self._set(RangeStatus.OUT_OF_RANGE_HIGH)
        elif self._distance_m < low:
            self._set(RangeStatus.OUT_OF_RANGE_LOW)
        else:
            self._set(RangeStatus.GOOD)
            if self.down:
                self.last_good_s = now_s

    def _set(self, status: RangeStatus) -> None:
        self._status = status
        self._valid_count = min(self._valid_count + 1, VALID_COUNT_MAX) if status == RangeStatus.GOOD else 0

    def heard(self, now_s: float, orientation: int, distance_cm: int, min_cm: int, max_cm: int,
              sensor_type: int, signal_quality: int) -> None:
        """A DISTANCE_SENSOR from a companion: taken by the MAVLink driver when it faces the way
        RNGFND1_ORIENT says; its id, time and covariance are not read, as ArduPilot's are not."""
        if self.kind != MAVLINK or orientation != int(self._params["RNGFND1_ORIENT"]):
            return
        self._heard_s = now_s
        self._heard_m = float32(distance_cm * CM_TO_M)
        self._heard_limits = (float32(min_cm * CM_TO_M), float32(max_cm * CM_TO_M))
        self._sensor_type = sensor_type
        # MAVLink's 0 is unknown and 1 the worst, ArduPilot's -1 and 0; kept in an int8, as ArduPilot
        # keeps it (255 reads -1, unknown)
        quality = signal_quality - 256 if signal_quality >= 128 else signal_quality
        self._heard_quality = -1 if quality == 0 else (0 if quality == 1 else quality)

    def prearm_failure(self) -> str | None:
        """The pre-arm check's complaint, None when the rangefinder may fly (out of range may)."""
        if int(self._params["RNGFND1_TYPE"]) == NONE:
            return None
        if self.kind == NONE:  # set since boot, or hardware SITL does not have
            return "Rangefinder 1: Not Detected"
        if not self.reading().has_data:
            return "Rangefinder 1: No Data"
        return None
