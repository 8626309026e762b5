"""The static type check, and what it takes on trust.

mypy checks sim/ and autopilot/ with Optional checking (pyproject.toml [tool.mypy]): a None that
can reach an index or an attribute (home before it is set, a leg before it is begun) is an error
before it is a crash. The readers of the vehicle are typed with read-only views (autopilot/views.py),
and a second test shows mypy refusing the two reads the views exist to stop.

What mypy cannot see is the path inside a read-through property, `x: ReadThrough[float] =
property(attrgetter("a.b"))`: the annotation is a claim. The third test reads every such
property of a flown vehicle and of its mode context and checks the value against its annotation.
"""
from __future__ import annotations

import subprocess
import sys
import types
import typing
from pathlib import Path

from firefly.autopilot import views

from ._util import hovering_vehicle

ROOT = Path(__file__).resolve().parents[2]


def test_mypy_finds_nothing():
    """`python -m mypy` from the repository root, with its configuration (pyproject.toml)."""
    done = subprocess.run([sys.executable, "-m", "mypy"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"mypy (exit {done.returncode}):\n{done.stdout}{done.stderr}"


UNCHECKED_READS = '''
from firefly.autopilot.modes.context import ModeContext
from firefly.autopilot.views import FailsafeView


def height_above_home(ctx: ModeContext) -> float:
    return ctx.home_ned[2] - ctx.body.d_m  # home may not be set: line 7


def height_above_required_home(ctx: ModeContext) -> float:
    return ctx.require_home()[2] - ctx.body.d_m


def volts(v: FailsafeView) -> float:
    return v.estimate.battery.voltage_v  # into the vehicle's parts: line 15
'''


def test_mypy_refuses_an_unchecked_home_and_a_reach_into_the_vehicle(tmp_path):
    """The kind of read that once killed the process, and a reader reaching past its view."""
    path = tmp_path / "readers.py"
    path.write_text(UNCHECKED_READS)
    done = subprocess.run([sys.executable, "-m", "mypy", str(path)], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    errors = [line.split(":", 2)[1:] for line in done.stdout.splitlines() if ": error:" in line]
    assert done.returncode == 1 and [line for line, _ in errors] == ["7", "15"], done.stdout + done.stderr
    assert "not indexable" in errors[0][1] and '"FailsafeView" has no attribute "estimate"' in errors[1][1]


def _names_for_annotations() -> dict:
    """What the annotations name, though their modules import it for the type checker only."""
    from firefly.sim.battery import BatteryState
    from firefly.sim.rigid_body import BodyState
    from firefly.sim.sensors import GpsReading, RcReceiver
    from firefly.autopilot.optical_flow import FlowReading
    from firefly.autopilot.pilot import PilotInput
    return {"ReadThrough": views.ReadThrough, "Vector3": views.Vector3, "BatteryState": BatteryState,
            "BodyState": BodyState, "GpsReading": GpsReading, "PilotInput": PilotInput, "RcReceiver": RcReceiver,
            "FlowReading": FlowReading}


def conforms(value, hint) -> bool:
    """Whether `value` is of the type `hint` (the forms the read-through annotations use)."""
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        return any(conforms(value, arm) for arm in args)
    if hint is None or hint is type(None):
        return value is None
    if origin is tuple:
        if not isinstance(value, tuple):
            return False
        if len(args) == 2 and args[1] is Ellipsis:
            return all(conforms(x, args[0]) for x in value)
        return len(value) == len(args) and all(conforms(x, a) for x, a in zip(value, args))
    if origin is list:
        return isinstance(value, list) and all(conforms(x, args[0]) for x in value)
    if hint is float:
        return isinstance(value, (float, int)) and not isinstance(value, bool)
    return isinstance(value, hint)


def read_through_properties(cls) -> dict:
    """{name: T} of each `name: ReadThrough[T]` in the class body."""
    names = {**vars(sys.modules[cls.__module__]), **_names_for_annotations()}
    found = {}
    for name, text in cls.__annotations__.items():
        if isinstance(text, str) and text.startswith("ReadThrough["):
            found[name] = typing.get_args(eval(text, names))[0]  # noqa: S307 - our own annotations
    return found


def test_the_read_through_properties_give_what_their_annotations_say():
    v = hovering_vehicle(5.0)
    v.run_until(v.time_s + 0.5)  # a sample of everything (temperature, GPS) taken in flight
    checked = []
    for obj in (v, v.ctx):
        properties = read_through_properties(type(obj))
        assert properties, f"no read-through property found on {type(obj).__name__}"
        for name, hint in properties.items():
            assert isinstance(type(obj).__dict__[name], property), name
            value = getattr(obj, name)
            assert conforms(value, hint), f"{type(obj).__name__}.{name} = {value!r}, annotated {hint}"
            checked.append(name)
    assert {"home_ned", "battery", "gps_glitching", "mode_number", "body"} <= set(checked)


def test_the_conformance_check_can_fail():
    assert not conforms(None, views.Vector3) and conforms(None, views.Vector3 | None)
    assert not conforms((1.0, 2.0), views.Vector3) and conforms((1.0, 2.0, 3), views.Vector3)
    assert not conforms(True, float) and not conforms("1", int)
