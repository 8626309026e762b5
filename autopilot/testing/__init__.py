"""Firefly for testing your own drone code: the pytest plugin (plugin.py) and what its fixtures
give a test. Import these names for type hints; the fixtures need no import."""
from .settings import FireflySettings, SettingsError
from .state import VehicleState
from .errors import FireflyError
from .vehicle import FireflyVehicle

__all__ = ["FireflySettings", "SettingsError", "VehicleState", "FireflyError", "FireflyVehicle"]
