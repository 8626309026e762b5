"""Modes see the vehicle only through a ModeContext, and what a mode declares it does."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

from firefly.autopilot.modes import MODE_CLASSES, Guided, ModeNumber
from firefly.autopilot.modes.context import ModeContext
from firefly.autopilot.results import Result

from ._util import altitude, fly_until, ready_vehicle

MODES_DIR = Path(__file__).resolve().parents[2] / "autopilot" / "modes"
# Modes ArduCopter refuses armed on the ground (test_modes_manual.py tests the refusals); AUTO
# and AUTO RTL refuse without a mission (test_auto.py, test_nav_modes.py).
NOT_ENTERED_ARMED_ON_GROUND = (ModeNumber.AUTO, ModeNumber.FLIP, ModeNumber.AUTOTUNE, ModeNumber.THROW,
                               ModeNumber.FLOWHOLD, ModeNumber.FOLLOW, ModeNumber.SYSTEMID, ModeNumber.TURTLE,
                               ModeNumber.AUTO_RTL)
ENTERED_ARMED_ON_GROUND = [c for c in MODE_CLASSES if c.number not in NOT_ENTERED_ARMED_ON_GROUND]


def armed_on_the_ground_in(number):
    v = ready_vehicle()
    assert v.set_mode(ModeNumber.GUIDED) == Result.ACCEPTED and v.arm() == Result.ACCEPTED
    if number != ModeNumber.AUTO:  # AUTO refuses without a mission: tested in test_auto.py
        assert v.set_mode(number) == Result.ACCEPTED
    return v


@pytest.mark.parametrize("cls", ENTERED_ARMED_ON_GROUND, ids=lambda c: c.name)
def test_user_takeoff_is_declared_exactly_where_a_takeoff_flies(cls):
    v = armed_on_the_ground_in(cls.number)
    result = v.takeoff(5.0)
    assert (result == Result.ACCEPTED) == cls.has_user_takeoff
    if cls.has_user_takeoff and cls.number != ModeNumber.GUIDED_NOGPS:  # it accepts and ignores it, as ArduCopter's
        assert fly_until(v, lambda x: altitude(x) > 4.5, 15.0)


@pytest.mark.parametrize("cls", ENTERED_ARMED_ON_GROUND, ids=lambda c: c.name)
def test_ground_station_position_and_velocity_targets_are_taken_in_guided_only(cls):
    v = armed_on_the_ground_in(cls.number)
    guided = cls.in_guided_mode  # GUIDED, GUIDED_NOGPS (takes them, flies none) and AVOID_ADSB (GUIDED underneath)
    accepted = (Result.ACCEPTED,)
    assert (v.guided_goto(5.0, 0.0, -5.0) in accepted) == guided
    assert (v.guided_velocity(1.0, 0.0, 0.0) in accepted) == guided
    # CONDITION_YAW is accepted in every mode, as ArduCopter does; only GUIDED turns to it here.
    assert v.set_yaw(90.0, relative=False, direction=1) == Result.ACCEPTED


def test_the_context_reads_through_to_the_vehicle():
    v = ready_vehicle()
    ctx = ModeContext(v)
    assert not ctx.armed and ctx.landed and ctx.time_s == v.time_s
    v.set_mode(ModeNumber.GUIDED)
    v.arm()
    v.run_until(v.time_s + 0.1)
    assert ctx.armed and ctx.time_s == v.time_s and ctx.body == v.body
    assert ctx.mission_progress is v.mission_progress and ctx.params is v.params
    with pytest.raises(AttributeError):
        ctx.armed = False  # read only
    with pytest.raises(AttributeError):
        ctx.mission_state = "ACTIVE"  # nothing new can be written onto it


def test_no_mode_imports_the_vehicle_or_reaches_for_its_parts():
    for path in MODES_DIR.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                assert node.module not in ("vehicle", "autopilot.vehicle") and \
                    not (node.level == 2 and node.module == "vehicle"), f"{path.name} imports the vehicle"
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "ctx":
                assert node.attr in ModeContext.__slots__ or hasattr(ModeContext, node.attr), \
                    f"{path.name}: ctx.{node.attr} is not in the mode context"
