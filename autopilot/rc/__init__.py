"""The pilot's radio, as ArduCopter's RC_Channels reads it.

- `channels.py`: one channel's calibration (RCn_MIN/TRIM/MAX/DZ/REVERSED) and what a PWM means:
  a stick (-1..1), a throttle (0..1), a 3- or 6-position switch;
- `overrides.py`: channel values a ground station sends (RC_CHANNELS_OVERRIDE, MANUAL_CONTROL),
  each lasting RC_OVERRIDE_TIME;
- `switches.py`: ArduPilot's switch debounce (a position counts once it has held 200 ms);
- `aux.py`: the RCn_OPTION functions, one table, also run by MAV_CMD_DO_AUX_FUNCTION;
- `radio.py`: the receiver and the overrides read together at the flight-mode rate: the channels
  in microseconds, the sticks through RCMAP_*, the flight-mode switch (FLTMODE_CH, FLTMODE1..6)
  and the aux switches.
What MAVLink says is turned into overrides in autopilot/mavlink/rc_input.py (sans-IO).
"""
from .radio import RadioInput

__all__ = ["RadioInput"]
