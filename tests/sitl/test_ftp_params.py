"""Parameters downloaded by MAVLink FTP (`@PARAM/param.pck`) from the real autopilot process, with
pymavlink's MAVFTP and with MAVProxy's `param ftp`: every parameter arrives with its value."""
from __future__ import annotations

import re

import pytest
from pymavlink.mavftp import MAVFTP

from firefly.autopilot.params import SERVED

from .conftest import free_udp_port
from .pymav import Gcs, set_param
from .test_mavproxy import MavProxy

pytestmark = pytest.mark.sitl
CHANGED = {"WPNAV_SPEED": 1234.5, "FENCE_TYPE": 3.0}  # set over MAVLink before the download
DEFAULTS = {spec.name: spec.default for spec in SERVED}
# The process's --speedup (the autopilot fixture's), as SITL reports it; the mission's length with
# home (MIS_TOTAL is counted, as AP_Mission's, not a default)
REPORTED = {"SIM_SPEEDUP": 10.0, "MIS_TOTAL": 1.0}


def _expected() -> dict:
    return {**DEFAULTS, **REPORTED, **CHANGED}


def _read_parm(path) -> dict:
    """NAME,value or NAME value lines, as MAVFTP and MAVProxy save them."""
    values = {}
    for line in path.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, value = re.split(r"[,\s]+", line.strip())[:2]
            values[name] = float(value)
    return values


def _same(got: dict, expected: dict) -> None:
    assert sorted(got) == sorted(expected)
    wrong = {n: (got[n], v) for n, v in expected.items() if got[n] != pytest.approx(v, rel=1e-6, abs=1e-6)}
    assert not wrong, wrong


@pytest.fixture
def gcs(autopilot):
    g = Gcs(autopilot.pymavlink_url)
    for name, value in CHANGED.items():
        set_param(g, name, value)
    yield g
    g.close()


@pytest.mark.parametrize("burst_read_size", [80, 239])
def test_mavftp_getparams_downloads_every_value_and_default(gcs, tmp_path, burst_read_size):
    ftp = MAVFTP(gcs.conn, gcs.conn.target_system, gcs.conn.target_component)
    ftp.ftp_settings.burst_read_size = burst_read_size
    values_path, defaults_path = tmp_path / "values.parm", tmp_path / "defaults.parm"
    assert ftp.cmd_getparams([str(values_path), str(defaults_path)]).error_code == 0
    result = ftp.process_ftp_reply("getparams", timeout=30)
    assert result.error_code == 0, result.display_message()
    _same(_read_parm(values_path), _expected())
    _same(_read_parm(defaults_path), DEFAULTS)


def test_mavproxy_param_ftp_downloads_every_value(autopilot_factory, tmp_path):
    observer_port = free_udp_port()
    ap = autopilot_factory(extra=("--out", f"udp:127.0.0.1:{observer_port}"))
    setter = Gcs(f"udpin:127.0.0.1:{observer_port}")
    try:
        for name, value in CHANGED.items():
            set_param(setter, name, value)
    finally:
        setter.close()
    mavproxy = MavProxy(ap.port, tmp_path / "mavproxy")
    try:
        # MAVProxy fetches by FTP on its own when it connects; `param ftp` asks again after the
        # changes, and its count line says the file decoded.
        mavproxy.wait_output(r"Received \d+ parameters \(ftp\)", 60)
        start = mavproxy.mark()
        mavproxy.send("param ftp")
        found = mavproxy.wait_output(r"Received (\d+) parameters \(ftp\)", 60, start)
        assert int(found.group(1)) == len(SERVED)
        saved = tmp_path / "saved.parm"
        start = mavproxy.mark()
        mavproxy.send(f"param save {saved}")
        mavproxy.wait_output(rf"Saved \d+ parameters to {re.escape(str(saved))}", 30, start)
        _same(_read_parm(saved), _expected())
    finally:
        mavproxy.stop()
