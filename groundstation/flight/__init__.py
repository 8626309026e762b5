"""Flying a real vehicle over MAVLink with MAVSDK: `groundstation explore` (the fire search; survey.py
pairs its readings with positions and feeds the search controller), `mission` (.plan / .waypoints
files), `demo`, the vehicle link, reference_flight.py (the flight the bench and the SITL tests
time), and starting an autopilot process."""
