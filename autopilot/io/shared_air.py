"""The vehicles of one process as if on one radio network: what each says of where it is
(GLOBAL_POSITION_INT, as its streams send it) is heard by every other, as ArduCopters sharing a
MAVLink network hear each other, so that one can FOLLOW another with no client in between.
Heard only: nothing is relayed to the other vehicles' links, whose clients go on seeing their
own vehicle alone.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .runner import Node

HEARD = frozenset({"GLOBAL_POSITION_INT"})


class SharedAir:
    def __init__(self, nodes: Sequence[Node]):
        self.nodes = nodes
        self.listeners: list[Node] = list(nodes)

    def refresh(self) -> None:
        """Who listens, asked once a round of ticks (the runner's), not once a message: a vehicle
        that neither follows, avoids nor points a gimbal at another system has no use for their
        positions, and asking each of N vehicles about each of N senders' messages cost a swarm of
        250 a third of its time at 1x."""
        self.listeners = [node for node in self.nodes if node.vehicle.hears_positions()]

    def broadcast(self, sender: Node, out: Sequence[Any]) -> None:
        """What `sender` sent this exchange (its poll's messages), heard by the listeners now."""
        listeners = self.listeners
        if not listeners:
            return
        for msg in out:
            if msg.get_type() in HEARD:
                system_id = sender.vehicle.system_id
                for node in listeners:
                    if node is not sender:  # looked up each time: a reboot replaces a node's parts
                        node.session.overhear(msg, system_id, node.vehicle.time_s)
