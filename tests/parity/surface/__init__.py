"""ArduCopter's user-reachable surface, enumerated from its sources at the reference commit."""
