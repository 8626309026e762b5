"""`autopilot --param NAME=VALUE`: a parameter set and saved before the first boot, refused in one
line naming the option when the name or value is bad."""
from __future__ import annotations

import argparse

import pytest

from firefly.autopilot.cli.main import param_setting


def test_a_known_parameter_is_taken_with_its_value_checked():
    assert param_setting("CAM1_TYPE=1") == ("CAM1_TYPE", 1.0)
    assert param_setting("WPNAV_SPEED=750") == ("WPNAV_SPEED", 750.0)


@pytest.mark.parametrize("text, says", [("CAM1_TYPEX=1", "unknown parameter CAM1_TYPEX"),
                                        ("CAM1_TYPE=9", "out of range"), ("CAM1_TYPE", "not a number"),
                                        ("CAM1_TYPE=nan", "finite")])
def test_a_bad_setting_names_what_is_wrong(text, says):
    with pytest.raises(argparse.ArgumentTypeError, match=says):
        param_setting(text)
