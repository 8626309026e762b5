"""AVOID_ADSB: the mode ArduCopter's ADS-B avoidance flies in, GUIDED underneath (ModeAvoidADSB
is a ModeGuided): entered by hand it holds where it can stop, as GUIDED does, takes GUIDED's
targets and takeoff (ArduCopter's in_guided_mode), and may not be armed in. ADS-B avoidance
(adsb/escape.py) enters it and gives it the velocity that flies away from a threat."""
from __future__ import annotations

from .guided import Guided
from .numbers import ModeNumber


class AvoidAdsb(Guided):
    number = ModeNumber.AVOID_ADSB
    allows_arming = False
