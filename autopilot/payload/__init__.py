"""Payloads the autopilot drives itself: the camera (camera.py)."""
