"""Safety: arming and the pre-arm checks, the land detector and auto-disarm, the failsafes and the
geofence, the EKF check, the thrust-loss check."""
