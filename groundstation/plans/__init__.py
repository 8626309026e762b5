"""Mission plans made by the ground stations' own rules: QGroundControl's survey, corridor scan
and structure scan (complex items in a `.plan`), and a Mission Planner `.waypoints` with spline
waypoints and a landing sequence. The items each rule produces are the ones the ground station
would upload; the files are the ones it would save. `python -m groundstation.plans OUT_DIR`
writes the example plans (examples/plans/)."""
