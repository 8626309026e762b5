"""The documentation reader of the recorder: full names through @Group/@Path, Copter's own tagged
fields, vector parameters, and ranges only where the documentation gives two numbers."""
from __future__ import annotations

from .param_docs import documented_params

VEHICLE = """\
    // @Param: RTL_ALT
    // @Range: 30 300000
    // @Range{Plane}: 0 1
    GSCALAR(rtl_altitude, "RTL_ALT", 1500),

    // @Param{Plane}: PLANE_ONLY
    // @Range: 0 1

    // @Group: BATT
    // @Path: ../libraries/AP_Batt/AP_Batt.cpp
    GOBJECT(battery, "BATT", AP_Batt),

    // @Group:
    // @Path: Parameters.cpp
    GOBJECT(g2, "", ParametersG2),
"""
LIBRARY = """\
    // @Param: _LOW_VOLT
    // @Units: V
    AP_GROUPINFO("_LOW_VOLT", 1, AP_Batt, low, 10.5),

    // @Param: _CAPACITY
    // @Range{Copter}: 0 50000
    // @Range: 0 1
    // @Param: _OFFS
    // @Vector3Parameter: 1
    // @Range: -5 +5

    // @Group: 2_
    // @Path: AP_Batt_Params.cpp
"""
PARAMS = """\
    // @Param: MONITOR
    // @Values: 0:Disabled,4:Analog
    // @Range: fast slow
"""


def test_names_ranges_and_tags(tmp_path):
    (tmp_path / "ArduCopter").mkdir()
    (tmp_path / "ArduCopter" / "Parameters.cpp").write_text(VEHICLE)
    (tmp_path / "libraries" / "AP_Batt").mkdir(parents=True)
    (tmp_path / "libraries" / "AP_Batt" / "AP_Batt.cpp").write_text(LIBRARY)
    (tmp_path / "libraries" / "AP_Batt" / "AP_Batt_Params.cpp").write_text(PARAMS)
    docs = documented_params(tmp_path / "ArduCopter")
    assert set(docs) == {"RTL_ALT", "BATT_LOW_VOLT", "BATT_CAPACITY", "BATT_OFFS_X", "BATT_OFFS_Y",
                         "BATT_OFFS_Z", "BATT2_MONITOR"}
    assert docs["RTL_ALT"].range() == (30, 300000)  # the untagged range; Plane's is not Copter's
    assert docs["BATT_CAPACITY"].range() == (0, 50000)  # Copter's own wins, whatever the order
    assert docs["BATT_OFFS_Y"].range() == (-5, 5)
    assert docs["BATT_LOW_VOLT"].range() is None
    assert docs["BATT2_MONITOR"].range() is None  # not two numbers
    assert docs["BATT2_MONITOR"].fields["Values"] == "0:Disabled,4:Analog"
