"""Routing between a vehicle's links (autopilot/mavlink/routing.py), as ArduPilot's routing does it."""
from __future__ import annotations

from firefly.autopilot.mavlink.routing import MAX_ROUTES, Router

from ._util import mav, new_codec

GCS, COMPANION, PASSIVE = ("udp", 14550), ("tcp", 5760, 1), ("udp", 14540)


def message(build, system: int = 255, component: int = 190):
    codec = new_codec(system, component)
    return codec.parse_buffer(build(codec).pack(codec))[0]


def heartbeat(codec):
    return codec.heartbeat_encode(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0, 0)


def command_to(system: int, component: int):
    return lambda codec: codec.command_long_encode(system, component, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                                   148, 0, 0, 0, 0, 0, 0)


def test_a_broadcast_is_handled_and_goes_to_every_other_link_heard_from():
    router = Router(1)
    assert router.route(message(heartbeat, 1, 191), COMPANION) == (True, [])  # nobody else heard yet
    local, onward = router.route(message(heartbeat), GCS)
    assert local and onward == [COMPANION]
    assert router.route(message(heartbeat, 1, 191), COMPANION) == (True, [GCS])
    assert PASSIVE not in onward, "a link nobody spoke on gets nothing forwarded"


def test_a_message_for_a_component_heard_elsewhere_goes_there_and_not_here():
    router = Router(1)
    router.route(message(heartbeat, 1, 191), COMPANION)
    assert router.route(message(command_to(1, 191)), GCS) == (False, [COMPANION])
    assert router.route(message(command_to(1, 1)), GCS) == (True, []), "the autopilot's own: here only"
    assert router.route(message(command_to(1, 0)), GCS) == (True, [COMPANION]), "the whole system: both"
    assert router.route(message(command_to(1, 154)), GCS) == (True, []), "nobody heard as 154: answered here"
    assert router.route(message(command_to(7, 1)), GCS) == (False, []), "an unknown system: dropped"


def test_a_message_for_another_system_goes_only_where_it_was_heard():
    router = Router(1)
    router.route(message(heartbeat, 2, 1), COMPANION)
    router.route(message(heartbeat, 3, 1), PASSIVE)
    assert router.route(message(command_to(2, 1)), GCS) == (False, [COMPANION])
    assert router.route(message(command_to(2, 1), 2, 1), COMPANION) == (False, []), "never back where it came from"


def test_routes_are_bounded_and_a_closed_link_forgets_its_own():
    router = Router(1)
    for n in range(MAX_ROUTES + 5):
        router.learn(message(heartbeat, 100 + n, 1), ("tcp", 5760, n))
    assert len(router.routes) == MAX_ROUTES and router.counters["routes_evicted"] == 5
    router.forget(("tcp", 5760, MAX_ROUTES + 4))
    assert (100 + MAX_ROUTES + 4, 1) not in router.routes and len(router.routes) == MAX_ROUTES - 1


def test_the_vehicle_itself_is_never_a_route():
    router = Router(1)
    router.learn(message(heartbeat, 1, 1), GCS)
    assert router.routes == {}


def test_traffic_reports_are_not_forwarded_while_the_vehicle_lists_traffic():
    lists = [False]
    router = Router(1, lambda: lists[0])
    router.route(message(heartbeat), GCS)
    report = message(lambda codec: codec.adsb_vehicle_encode(1, 0, 0, 0, 0, 0, 0, 0, b"T", 1, 1, 3, 1200), 1, 191)
    assert router.route(report, COMPANION) == (True, [GCS])  # ADSB_TYPE 0: a broadcast like any other
    lists[0] = True
    assert router.route(report, COMPANION) == (True, [])
