"""Payloads the autopilot drives itself: the camera (camera.py), the parachute (parachute.py), the
sprayer (sprayer.py) and the gripper (gripper.py), on the outputs their functions name
(outputs.py); and ArduPilot SITL's simulated parachute and gripper (sitl_parachute.py,
sitl_gripper.py), which turn those outputs into the sim's canopy and load."""
