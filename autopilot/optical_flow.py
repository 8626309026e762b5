"""The optical flow sensor, as ArduPilot's AP_OpticalFlow runs it with its SITL driver.

FLOW_TYPE is read at boot, as ArduPilot makes its driver once: 10 reads the simulator's camera
(sim/optical_flow.py, which makes a sample at SIM_FLOW_RATE while SIM_FLOW_ENABLE is on); any
other type names hardware SITL does not have and makes none. The sensor is enabled while FLOW_TYPE
is not 0 (read live: set while running, SYS_STATUS shows it present and enabled, but with no driver
it is never healthy), and healthy while its last sample is under half a second old. ArduCopter
updates it at 200 Hz; Firefly at its mode rate, which the 10 Hz samples do not notice.

The driver scales each flow axis by 1 + FLOW_FXSCALER/1000 (FLOW_FYSCALER) and turns the flow by
FLOW_ORIENT_YAW (centidegrees), as ArduPilot's backends do; the body rates are the gyro's, as they are.
"""
from __future__ import annotations

import math
from typing import NamedTuple

from firefly.sim.optical_flow import FlowSample

from .params import ParamStore

NONE, SITL = 0, 10  # FLOW_TYPE
HEALTHY_S = 0.5  # data older than this is unhealthy (AP_OpticalFlow::update)


class FlowReading(NamedTuple):
    """What FLOWHOLD and the messages read of the sensor."""
    flow_x: float  # flow rates [rad/s] about the body axes, the body's rotation included
    flow_y: float
    body_x: float  # the body rates that came with them [rad/s]
    body_y: float
    quality: int   # 0-255
    updated_s: float  # when the last sample came (sim seconds)


NO_READING = FlowReading(0.0, 0.0, 0.0, 0.0, 0, -math.inf)


class OpticalFlow:
    def __init__(self, params: ParamStore):
        self._params = params
        self.kind = SITL if int(params["FLOW_TYPE"]) == SITL else NONE  # the driver made at boot
        self.reading = NO_READING

    @property
    def enabled(self) -> bool:
        """FLOW_TYPE is not 0, now (AP_OpticalFlow::enabled)."""
        return int(self._params["FLOW_TYPE"]) != NONE

    def healthy(self, now_s: float) -> bool:
        return self.enabled and now_s - self.reading.updated_s < HEALTHY_S

    def update(self, now_s: float, sample: FlowSample | None) -> None:
        """A new sample from the simulator's camera (None: none due), taken by the SITL driver."""
        if sample is None or self.kind != SITL or not self.enabled:
            return
        p = self._params
        fx = sample.flow_x * (1.0 + 0.001 * p["FLOW_FXSCALER"])
        fy = sample.flow_y * (1.0 + 0.001 * p["FLOW_FYSCALER"])
        yaw = math.radians(p["FLOW_ORIENT_YAW"] / 100.0)
        if yaw:
            c, s = math.cos(yaw), math.sin(yaw)
            fx, fy = fx * c - fy * s, fx * s + fy * c
        self.reading = FlowReading(fx, fy, sample.body_x, sample.body_y, sample.quality, now_s)
