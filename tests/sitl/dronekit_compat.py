"""DroneKit 2.9.2 (its last release, 2019) importable on Python 3.10 and later.

DroneKit's `Parameters` subclasses `collections.MutableMapping`, an alias of
`collections.abc.MutableMapping` that Python 3.10 removed, so `import dronekit` fails with
AttributeError. Putting that one alias back is the whole shim: DroneKit needs nothing else from
the language. Its other needs are packages, listed in the `test` extra: `monotonic` (declared by
DroneKit) and `future` (DroneKit imports `past.builtins` but does not declare it).

Import DroneKit's names from here, never from `dronekit` directly, so the alias is in place first.
"""
from __future__ import annotations

import collections
import collections.abc

if not hasattr(collections, "MutableMapping"):
    collections.MutableMapping = collections.abc.MutableMapping  # type: ignore[attr-defined]

from dronekit import Command, Vehicle, VehicleMode, connect  # noqa: E402 - needs the alias above

__all__ = ["Command", "Vehicle", "VehicleMode", "connect"]
