"""Decision layer: MAVSDK-based companion processes that fly the autopilot over MAVLink."""
