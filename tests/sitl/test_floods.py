"""Floods against the real process at speedup 1: whatever a flood asks of the vehicle, its loop
keeps time, so its HEARTBEAT never stops for long and a legitimate client is still answered.

Each flood comes from another process, from many source ports, for FLOOD_S seconds, while a
listener on the vehicle's --out port times its HEARTBEATs and a client sends a command every
quarter second. Before a request's answers and a receive's work were bounded, the parameter-list
flood silenced the heartbeat for the whole 5 s (2 of 20 commands answered), the FTP burst flood
too (3 of 20), and 2 KB datagrams of the costliest junk for pymavlink's parser as well; now the
longest gap is about 1.0 s in each, every command answered.

A flood of PARAM_SETs of new values, or of MISSION_CLEAR_ALLs, once wrote the store's file
(fsync included) for each and stalled the loop for seconds; a store now writes at most twice a
second (persist.JsonFile), the rest at the next write or at exit.
"""
from __future__ import annotations

import json
import time

import pytest

from .conftest import free_udp_port, start_autopilot
from .floods import Listener, Prober, start_flood

pytestmark = [pytest.mark.sitl, pytest.mark.serial]  # the heartbeat's gaps are timed in wall seconds
FLOOD_S = 5.0
MAX_GAP_S = 1.5  # HEARTBEAT is 1 Hz

FLOODS = [  # kind (tests/sitl/floods.py), datagrams a second, source ports
    pytest.param("param_list", 8000, 300, id="param_list"),  # PARAM_REQUEST_LIST: was a burst of 40 each
    pytest.param("junk64k", 150, 300, id="junk64k"),  # 64 KB datagrams of 0xFD
    pytest.param("junk2k", 2000, 300, id="junk2k"),  # 2 KB of empty MAVLink 1 frames: ~2 ms to parse
    pytest.param("ftp_burst", 2000, 50, id="ftp_burst"),  # FTP BurstReadFile of the parameter file
    pytest.param("mission_list", 8000, 300, id="mission_list"),  # MISSION_REQUEST_LIST, _REQUEST_INT
    pytest.param("param_set", 8000, 300, id="param_set"),  # PARAM_SET of new values: a file write each
    pytest.param("mission_clear", 8000, 300, id="mission_clear"),  # MISSION_CLEAR_ALL: a file write each
]


@pytest.mark.parametrize("kind,rate,ports", FLOODS)
def test_a_flood_does_not_silence_the_heartbeat_nor_the_answers(tmp_path, kind, rate, ports):
    listen = free_udp_port()
    address = ("127.0.0.1", listen)
    stats = tmp_path / "stats.json"
    ap = start_autopilot(tmp_path, "1", ("--listen", f"udp:127.0.0.1:{listen}", "--stats", str(stats)))
    listener = Listener(ap.port)
    try:
        assert listener.wait(lambda lst: lst.heartbeats, 30), "no HEARTBEAT before the flood"
        prober = Prober(address, listener.sock)
        start = time.monotonic()
        flood = start_flood(kind, address, rate, FLOOD_S, ports)
        prober.start()
        sent = int(flood.communicate(timeout=FLOOD_S + 60)[0])
        end = time.monotonic()
        prober.stop()
        listener.wait(lambda lst: lst.probe_acks >= prober.sent, 2.0)  # the last probes' answers
        gap, answered = listener.longest_gap(start, end), listener.probe_acks
    finally:
        listener.close()
        ap.stop()
    assert sent >= 0.8 * rate * FLOOD_S, "the flood itself fell short"
    assert gap <= MAX_GAP_S, f"{kind}: no HEARTBEAT for {gap:.2f} s during the flood"
    assert answered >= 0.5 * prober.sent, f"{kind}: {answered} of {prober.sent} commands answered"
    report = json.loads(stats.read_text())
    counters = report["vehicles"][0]["counters"]
    assert report["exception"] is None and counters["handler_errors"] == 0
    # every datagram was read or counted as dropped by the kernel (a few may be left unread at exit)
    assert counters["udp_datagrams"] + counters["udp_kernel_dropped"] >= 0.95 * sent
    if kind == "junk64k":
        # every datagram read but the probes was dropped unparsed
        assert counters["udp_oversize_dropped"] >= counters["udp_datagrams"] - prober.sent
