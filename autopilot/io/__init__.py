"""The I/O edge: the UDP socket, the paced loop, the .tlog, atomic files, signing-key files, the exit report.

The only place that reads the wall clock or touches a socket or a file."""
