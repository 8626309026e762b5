"""MAVLink layer: turns decoded messages into calls on the vehicle and vehicle state into messages.

Everything here is sans-IO: sessions consume decoded messages with the current sim time and
return messages to send. Sockets live in autopilot/udp.py.
"""
