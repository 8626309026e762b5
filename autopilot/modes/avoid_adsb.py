"""AVOID_ADSB: the mode ArduCopter's ADS-B avoidance flies in, GUIDED underneath (ModeAvoidADSB
is a ModeGuided): entered by hand it holds where it can stop, as GUIDED does, takes GUIDED's
targets and takeoff (ArduCopter's in_guided_mode), and may not be armed in. Firefly has no ADS-B
traffic to avoid, so its avoidance sets it no target of its own."""
from __future__ import annotations

from .guided import Guided
from .numbers import ModeNumber


class AvoidAdsb(Guided):
    number = ModeNumber.AVOID_ADSB
    allows_arming = False
