"""Control layer library: PID, attitude and position controllers, thrust allocation. No I/O."""
