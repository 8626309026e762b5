"""The full ArduCopter parameter set over the wire: pymavlink's param_fetch_all, MAVSDK's
get_all_params and MAVProxy's `param fetch` each receive every parameter of the paced list;
parameters Firefly does not model are settable (echoed with the new value) and survive a restart."""
from __future__ import annotations

import time

import pytest
from mavsdk.asyncio.plugins.param import ParamAsync

from firefly.groundstation.flight.reference_flight import connect

from .pymav import Gcs, mav
from .test_mavproxy import mavproxy_factory  # noqa: F401 - a fixture

pytestmark = pytest.mark.sitl

WELL_KNOWN = ("ARMING_CHECK", "FS_THR_ENABLE", "FLTMODE1", "BATT_MONITOR", "SERIAL1_PROTOCOL")
NEW_VALUES = {"ARMING_CHECK": 0, "FS_THR_ENABLE": 2, "FLTMODE1": 4, "BATT_MONITOR": 3, "SERIAL1_PROTOCOL": 1}
FETCH_TIMEOUT_S = 30.0


def _fetch_all(gcs: Gcs) -> tuple[int, dict]:
    """pymavlink's own param_fetch_all: the connection fills conn.params as PARAM_VALUEs arrive."""
    gcs.conn.param_fetch_all()
    count, indices = None, set()
    deadline = time.monotonic() + FETCH_TIMEOUT_S
    while count is None or len(indices) < count:
        msg = gcs.recv("PARAM_VALUE", max(0.0, deadline - time.monotonic()))
        assert msg is not None, f"parameter download stalled at {len(indices)} of {count}"
        assert count in (None, msg.param_count), "parameter count changed during download"
        count = msg.param_count
        indices.add(msg.param_index)
    assert indices == set(range(count))
    return count, dict(gcs.conn.params)


def _set(gcs: Gcs, name: str, value: float):
    gcs.conn.param_set_send(name, value)
    return gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == name)


def test_pymavlink_fetches_every_parameter_then_sets_and_keeps_them_across_a_restart(autopilot_factory):
    ap = autopilot_factory(speedup="1")
    gcs = Gcs(ap.pymavlink_url)
    count, params = _fetch_all(gcs)
    assert count >= 1300 and len(params) == count
    assert set(WELL_KNOWN) <= set(params)
    for name, value in NEW_VALUES.items():
        echo = _set(gcs, name, value)
        assert echo is not None and echo.param_value == value, (name, echo)
    gcs.conn.close()
    ap.stop()

    again = autopilot_factory(speedup="1", port=ap.port, wipe=False)
    gcs = Gcs(again.pymavlink_url)
    for name, value in NEW_VALUES.items():
        gcs.mav.param_request_read_send(1, 1, name.encode(), -1)
        msg = gcs.recv("PARAM_VALUE", 5, lambda m, n=name: m.param_id == n)
        assert msg is not None and msg.param_value == value, (name, msg)
    gcs.conn.close()


def test_an_index_read_matches_the_list(autopilot):
    gcs = Gcs(autopilot.pymavlink_url)
    gcs.mav.param_request_read_send(1, 1, b"FLTMODE1", -1)
    by_name = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_id == "FLTMODE1")
    assert by_name is not None and by_name.param_type == mav.MAV_PARAM_TYPE_INT8
    gcs.mav.param_request_read_send(1, 1, b"", by_name.param_index)
    by_index = gcs.recv("PARAM_VALUE", 5, lambda m: m.param_index == by_name.param_index)
    assert by_index is not None and by_index.param_id == "FLTMODE1"
    gcs.conn.close()


async def test_mavsdk_gets_all_params_and_sets_one_firefly_does_not_model(autopilot):
    mavsdk, system = await connect(autopilot.mavsdk_url)
    try:
        param = ParamAsync(system)
        every = await param.get_all_params()
        names = {p.name for p in every.int_params} | {p.name for p in every.float_params}
        assert len(names) >= 1300
        assert set(WELL_KNOWN) <= names
        await param.set_param_int("FLTMODE1", 4)
        assert await param.get_param_int("FLTMODE1") == 4
    finally:
        mavsdk.destroy()


def test_mavproxy_param_fetch_receives_every_parameter_and_sets_one(autopilot, mavproxy_factory):
    proxy = mavproxy_factory(autopilot.port)
    first = int(proxy.wait_output(r"Received (\d+) parameters", FETCH_TIMEOUT_S).group(1))  # at connect
    assert first >= 1300
    mark = proxy.mark()
    proxy.send("param fetch")
    assert int(proxy.wait_output(r"Received (\d+) parameters", FETCH_TIMEOUT_S, mark).group(1)) == first
    proxy.send("param set FLTMODE1 4")
    _shown(proxy, "FLTMODE1", "4.0")


def _shown(proxy, name: str, value: str, timeout: float = 10.0) -> None:
    """Ask `param show` until MAVProxy's copy (updated by the echoed PARAM_VALUE) holds `value`."""
    deadline = time.monotonic() + timeout
    while True:
        mark = proxy.mark()
        proxy.send(f"param show {name}")
        shown = proxy.wait_output(rf"(?:^|> ){name}\s+(\S+)\s*$", 5, mark).group(1)
        if shown == value:
            return
        assert time.monotonic() < deadline, f"MAVProxy still shows {name} {shown}, not {value}"
