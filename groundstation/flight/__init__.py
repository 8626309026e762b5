"""Flying a real vehicle over MAVLink with MAVSDK: `groundstation explore` (the fire search),
`mission` (.plan / .waypoints files), `demo`, the vehicle link, and starting an autopilot process."""
