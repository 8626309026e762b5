"""ADS-B traffic as ArduCopter handles it: the receiver's list of aircraft (AP_ADSB, traffic_list.py),
the threats they pose and the COLLISION reports (AP_Avoidance, threats.py), and what the copter
does about one (ArduCopter's avoidance_adsb, escape.py)."""
