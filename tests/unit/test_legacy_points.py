"""Older ground stations' point-by-point fence and rally messages, and a transponder's ADS-B
messages, answered as ArduCopter answers them (texts measured on its SITL: surface_messages)."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mission import RALLY, MissionItem
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import client_codec, wire

GCS = client_codec()


@pytest.fixture
def setup():
    v = Vehicle(VehicleConfig())
    return v, Session(v, new_codec(1))


def send(session, msg):
    replies = session.receive(wire(msg), 0.0, 1.0)
    texts = [m.text for m in replies if m.get_type() == "STATUSTEXT"]
    return texts, [m for m in replies if m.get_type() != "STATUSTEXT"]


def rally(lat=-353600000, lng=1491600000, alt=30):
    return MissionItem(mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT, x=lat, y=lng, z=alt)


def test_fence_messages_are_refused_with_arducopters_texts_and_one_warning(setup):
    v, session = setup
    texts, replies = send(session, GCS.fence_fetch_point_encode(1, 1, 0))
    assert texts == ["Received message (FENCE_FETCH_POINT) is deprecated",
                     "Invalid fence point, index past total(0 >= 0)"] and replies == []
    texts, _ = send(session, GCS.fence_point_encode(1, 1, 0, 5, -35.36, 149.16))
    assert texts == ["Invalid fence point, bad count (5 vs 0)"]  # the warning once, until another kind
    v.params.set("FENCE_TOTAL", 3)
    texts, _ = send(session, GCS.fence_point_encode(1, 1, 0, 3, -35.36, 149.16))
    assert texts == ["Invalid FENCE_TOTAL"]


def test_rally_points_are_read_and_written_one_by_one(setup):
    v, session = setup
    texts, replies = send(session, GCS.rally_fetch_point_encode(1, 1, 0))
    assert texts == ["Received message (RALLY_FETCH_POINT) is deprecated", "Failed to get rally point"]
    texts, _ = send(session, GCS.rally_fetch_point_encode(1, 1, 3))
    assert texts == ["Bad rally point ID"]
    texts, _ = send(session, GCS.rally_point_encode(1, 1, 0, 1, -353600000, 1491600000, 30, 0, 0, 0))
    assert texts == ["Bad rally point ID"] and v.mission.items(RALLY) == []  # no point 0 to write over
    v.mission.replace(RALLY, [rally(), rally(lat=-353610000)])
    texts, _ = send(session, GCS.rally_point_encode(1, 1, 1, 1, -353620000, 1491600000, 40, 0, 0, 0))
    assert texts == ["Bad rally point count"]
    texts, _ = send(session, GCS.rally_point_encode(1, 1, 1, 2, -353620000, 1491600000, 40, 0, 0, 0))
    assert texts == [] and v.mission.items(RALLY)[1] == rally(lat=-353620000, alt=40.0)
    texts, replies = send(session, GCS.rally_fetch_point_encode(1, 1, 1))
    assert texts == [] and [(r.get_type(), r.idx, r.count, r.lat, r.alt) for r in replies] == \
        [("RALLY_POINT", 1, 2, -353620000, 40)]


def test_a_point_off_the_globe_is_dropped_in_silence(setup):
    v, session = setup
    v.mission.replace(RALLY, [rally()])
    texts, _ = send(session, GCS.rally_point_encode(1, 1, 0, 1, 95 * 10**7, 0, 30, 0, 0, 0))
    assert texts == ["Received message (RALLY_FETCH_POINT) is deprecated"] and v.mission.items(RALLY) == [rally()]



def test_an_adsb_transponder_is_announced_as_arducopter_announces_it(setup):
    v, session = setup
    v.drain_events()
    send(session, GCS.uavionix_adsb_out_cfg_encode(0xABCDEF, b"TEST1", 1, 1, 1, 0, 0, 0))
    send(session, GCS.uavionix_adsb_transceiver_health_report_encode(1))
    send(session, GCS.uavionix_adsb_transceiver_health_report_encode(1))  # the same channel: said once
    assert [text for _, text in v.drain_events()] == ["ADSB: Using ICAO_id 11259375 and Callsign TEST1",
                                                      "ADSB: Found transceiver on channel 0"]
