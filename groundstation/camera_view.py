"""A thermal camera's frame as the search takes it: the camera's geometry (sim/thermal_camera.py)
joined to the strategy's frame (strategy/frame.py), which knows rectangles on the ground but not
cameras. The decision-level episodes and the flown search both go through here, so one frame is
read one way whether it was rendered in the episode or downloaded from the vehicle."""
from __future__ import annotations

import numpy as np

from firefly.sim.thermal_camera import CameraPose, ThermalCameraSpec, footprint, footprint_corners, pose_from_attitude

from .strategy.frame import FrameObservation, reduce_footprint


def nadir_footprint_m(spec: ThermalCameraSpec, alt_m: float) -> tuple[float, float]:
    """The ground rectangle (north, east) [m] a frame straight down from alt_m covers, level at yaw 0:
    what the planner scores a candidate's frame by."""
    corners = footprint_corners(spec, pose_from_attitude(0.0, 0.0, alt_m))
    return float(np.ptp(corners[:, 0])), float(np.ptp(corners[:, 1]))


def frame_from_image(image: np.ndarray, spec: ThermalCameraSpec, pose: CameraPose) -> FrameObservation:
    """A frame taken from `pose` (deg C per pixel) as the strategy's FrameObservation, judged on the
    axis-aligned part of its footprint (strategy/frame.py)."""
    north, east = footprint(spec, pose)
    return reduce_footprint(image, north, east, footprint_corners(spec, pose), spec.emission_height_m)
