"""The I/O edge: the UDP socket, the paced loop, the .tlog, atomic files, signing-key files, the exit report.

Where sockets are touched and the wall clock is read while the vehicles run: the runner hands wall
time to the link and the sessions, which never read a clock themselves."""
