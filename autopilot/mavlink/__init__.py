"""MAVLink layer: turns decoded messages into calls on the vehicle and vehicle state into messages.

Everything here is sans-IO: the link (link.py) turns datagrams into messages and messages into
frames, sessions consume decoded messages with the current sim time and return messages to send;
times are handed in. Sockets live in autopilot/io/udp.py.
"""
