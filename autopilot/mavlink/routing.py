"""MAVLink routing between a vehicle's links, sans-IO, as ArduPilot's GCS_MAVLink routing does it.

A link (a TCP connection, a UDP peer) is named by an opaque key the I/O edge gives. Every message
received teaches a route: its sender (system, component) is reachable on the link it came in on.
Then each message is
- handled here if it is broadcast (no target, or target system 0) or targets this vehicle (its
  system with component 0 or 1, or a component of its system no link has been heard from);
- forwarded, as the frame it came in, to every other link with a learned route that matches its
  target: all of them for a broadcast, the links where that system (and component, when the
  target names one) was heard otherwise; at most once per link, never back where it came from.
A link nobody has spoken on receives nothing forwarded (ArduPilot forwards along learned routes
only), so a passive output sees the vehicle's own messages and nothing of other clients'.

Measured on ArduCopter SITL (4.7.0-dev) with two links: a listener that never sent anything got
HEARTBEATs only; once it had spoken it got the PARAM_VALUE of a parameter another link set, but no
COMMAND_ACK or PARAM_VALUE answering the other link's requests.
"""
from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable

from .dialect import AUTOPILOT_COMPONENT_ID as AUTOPILOT_COMPONENT

MAX_ROUTES = 20  # as ArduPilot's MAVLINK_MAX_ROUTES; the longest silent route goes first
RADIO_SYSTEM_ID = 51  # SiK radios report RADIO_STATUS as system 51 ('3'): never a route ArduPilot learns


def targets(msg) -> tuple[int, int]:
    """(target system, target component) of `msg`; 0 where it has no such field (broadcast)."""
    # MANUAL_CONTROL names its target field `target`, with no component
    system = getattr(msg, "target_system", None)
    if system is None:
        system = getattr(msg, "target", 0)
    return int(system or 0), int(getattr(msg, "target_component", 0) or 0)


def never() -> bool:
    return False


class Router:
    def __init__(self, system_id: int, lists_traffic: Callable[[], bool] = never):
        self.system_id = system_id
        # Whether the vehicle's ADS-B list runs: ADSB_VEHICLE is then its own (the ADSB stream
        # sends it on), not forwarded, as ArduPilot's routing keeps it
        self.lists_traffic = lists_traffic
        self._routes: OrderedDict = OrderedDict()  # (system, component) -> link key, least recent first
        self.counters = {"forwarded": 0, "routes_evicted": 0}

    def learn(self, msg, link) -> None:
        sender = (msg.get_srcSystem(), msg.get_srcComponent())
        # our own components (a companion as system 1, component 191) are routes; we ourselves are not
        if sender == (self.system_id, AUTOPILOT_COMPONENT) or sender[0] in (0, RADIO_SYSTEM_ID):
            return
        routes = self._routes
        if routes.get(sender) == link:
            routes.move_to_end(sender)
            return
        if sender not in routes and len(routes) >= MAX_ROUTES:
            routes.popitem(last=False)
            self.counters["routes_evicted"] += 1
        routes[sender] = link
        routes.move_to_end(sender)

    def route(self, msg, link) -> tuple[bool, list]:
        """(whether this vehicle handles `msg`, the other links it is forwarded to). Learns first."""
        self.learn(msg, link)
        if msg.get_type() == "ADSB_VEHICLE" and self.lists_traffic():
            return True, []
        system, component = targets(msg)
        own = self.system_id
        if not self._routes or (system == own and component == AUTOPILOT_COMPONENT):
            return system in (0, own), []
        forward: list = []
        for (route_system, route_component), to in self._routes.items():
            if to == link or to in forward:
                continue
            if system == 0 or (route_system == system and (component == 0 or route_component == component)):
                forward.append(to)
        self.counters["forwarded"] += len(forward)
        # another component of this system (a companion's camera) is served where it was heard;
        # one nobody has heard from is answered here, as ArduPilot does
        local = system == 0 or (system == own and (component == 0 or not forward))
        return local, forward

    def forget(self, link) -> None:
        """A link that closed (a TCP client gone): its routes go with it."""
        for key in [k for k, to in self._routes.items() if to == link]:
            del self._routes[key]

    @property
    def routes(self) -> dict:
        return dict(self._routes)
