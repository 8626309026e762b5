"""ArduPilot dataflash (.BIN) logs, sans-IO: the message table, the binary encoding and the
recorder that decides what is logged when. The file itself (numbering, LASTLOG.TXT, rotation,
flushing) lives at the I/O edge (autopilot/io/dataflash_files.py)."""
