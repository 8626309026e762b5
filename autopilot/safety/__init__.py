"""Safety: failsafes and the geofence, the EKF check, the thrust-loss check."""
