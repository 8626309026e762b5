"""The parameter list as a ground station downloads it (PARAM_REQUEST_LIST, missing indices read
again one by one): every name with its MAVLink type and value on a fresh vehicle."""
from __future__ import annotations

from ..client import Client
from ..facts import Tol, Trace

AREA = "params"
VALUE = Tol(abs=1e-6, rel=1e-6, why="float32 on the wire")


def fetch_all(client: Client, sim_s: float = 60.0) -> dict[str, tuple[int, float]]:
    got: dict[int, tuple[str, int, float]] = {}
    total = [None]
    client.conn.mav.param_request_list_send(1, 1)

    def take():
        for _, msg in client.log:
            if msg.get_type() == "PARAM_VALUE" and 0 <= msg.param_index < 65535:
                got[msg.param_index] = (msg.param_id, msg.param_type, msg.param_value)
                total[0] = msg.param_count
        client.log.clear()
        return total[0] is not None and len(got) >= total[0]
    client.logging = True
    try:
        if not client.try_wait(take, 10):
            for _ in range(3):
                for index in set(range(total[0] or 0)) - set(got):
                    client.conn.mav.param_request_read_send(1, 1, b"", index)
                if client.try_wait(take, 10):
                    break
    finally:
        client.logging = False
    return {name: (ptype, value) for name, ptype, value in got.values()}


def run(target) -> dict[str, Trace]:
    client = target.boot()
    try:
        t = Trace()
        for name, (ptype, value) in sorted(fetch_all(client).items()):
            t.fact(name, [ptype, value], VALUE)
        return {"list": t}
    finally:
        target.close()
