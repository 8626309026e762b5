"""The example plans (examples/plans/), each a 1-3 minute flight from ArduPilot SITL's home:

  survey.plan        QGC survey of a 40 x 60 m field at 20 m, transects 15 m apart, a photo every 8 m
  corridor.plan      QGC corridor scan, 20 m wide, along 100 m with a right-angle bend, at 20 m
  structure.plan     QGC structure scan of a 20 x 20 m, 20 m tall building: 2 layers, 10 m off its walls
                     (ArduCopter 4.7 refuses its DO_SET_ROI_WPNEXT_OFFSET at upload)
  structure_roi.waypoints  the same scan pointing at the building's centre (DO_SET_ROI_LOCATION)
  splines.waypoints  Mission Planner: takeoff, spline waypoints round a loop, a landing sequence
                     after DO_LAND_START
"""
from __future__ import annotations

from pathlib import Path

from .corridor import Corridor
from .geo import LocalFrame
from .items import land, land_start, return_to_launch, spline_waypoint, takeoff, waypoint
from .qgc_plan import write_plan
from .structure import StructureScan
from .survey import Survey
from .waypoints_file import write_waypoints

HOME = (-35.363261, 149.165230, 584.0)  # ArduPilot SITL's CMAC field, Firefly's default home
AROUND_HOME = LocalFrame(HOME[0], HOME[1])


def at(north: float, east: float) -> tuple:
    """(lat, lon) `north` and `east` metres from home, rounded as a map click would be."""
    lat, lon = AROUND_HOME.to_latlon(north, east)
    return round(lat, 9), round(lon, 9)


SURVEY = Survey(polygon=(at(20, 10), at(60, 10), at(60, 70), at(20, 70)), altitude=20.0, side_m=15.0, trigger_m=8.0)
CORRIDOR = Corridor(polyline=(at(10, -10), at(70, -10), at(70, 30)), width_m=20.0, altitude=20.0, side_m=10.0,
                    trigger_m=8.0)
STRUCTURE = StructureScan(footprint=(at(30, -50), at(50, -50), at(50, -30), at(30, -30)), scan_distance_m=10.0,
                          layer_height_m=10.0, trigger_m=5.0, structure_height_m=20.0, layers=2,
                          entrance_alt_m=20.0)
SPLINE_ALT, APPROACH_ALT = 15.0, 10.0
SPLINES = [takeoff(SPLINE_ALT), waypoint(*at(20, 0), SPLINE_ALT),
           spline_waypoint(*at(40, 0), SPLINE_ALT), spline_waypoint(*at(55, 20), SPLINE_ALT + 5.0),
           spline_waypoint(*at(40, 40), SPLINE_ALT), spline_waypoint(*at(20, 40), SPLINE_ALT),
           waypoint(*at(10, 40), SPLINE_ALT),
           land_start(*at(10, 20)), waypoint(*at(10, 20), APPROACH_ALT), waypoint(*at(5, 5), APPROACH_ALT),
           land(*at(0, 0))]


def write_examples(out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, scan in (("survey", SURVEY), ("corridor", CORRIDOR), ("structure", STRUCTURE)):
        alt = getattr(scan, "altitude", None) or scan.entrance_alt_m
        path = out / f"{name}.plan"
        write_plan(path, HOME, [takeoff(alt), scan, return_to_launch()])
        written.append(path)
    for name, items in (("structure_roi", [takeoff(STRUCTURE.entrance_alt_m), *STRUCTURE.items_pointing_at_centre(),
                                           return_to_launch()]), ("splines", SPLINES)):
        path = out / f"{name}.waypoints"
        write_waypoints(path, HOME, items)
        written.append(path)
    return written
