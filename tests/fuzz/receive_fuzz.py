"""Byte-level fuzz of the receive path: datagrams from several clients -> the vehicle's sans-IO
link (one parser per sender, signing admission, link faults) -> the session -> the vehicle, which
flies on meanwhile, and back: everything the vehicle answers is packed by the link.

No sockets: each datagram is handed to the link as (bytes, sender) from one of four client
addresses, as the UDP endpoint would (tests/fuzz/test_flood.py exercises that endpoint itself).
After every batch the vehicle must be valid (tests/fuzz/checks.py), no handler may have raised,
everything the vehicle answers must pack, and it may only have armed on an accepted ARM.

    python -m tests.fuzz.receive_fuzz --frames 1000000 --seed 1      (what `make fuzz` runs)
"""
from __future__ import annotations

import argparse
import collections
import json
import sys
import time

from firefly.autopilot.faults.link import LinkFaults
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.link import Link
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from .checks import vehicle_problems
from .frames import FrameSource

BATCH = 32  # datagrams per exchange
STEPS_PER_BATCH = 4  # physics steps (10 ms of sim time) per batch
CLIENTS = [("127.0.0.1", 40001 + k) for k in range(4)]  # the senders' addresses, as recvfrom gives them
UNIX_EPOCH_S = 1_750_000_000.0  # the wall clock handed to the link: a fixed instant plus sim time
ARM = 400


class FuzzFailure(AssertionError):
    pass


def run(frames: int, seed: int = 1, progress=None) -> dict:
    vehicle = Vehicle(VehicleConfig())
    vehicle.run_until(0.5)
    session = Session(vehicle, new_codec(1))
    link = Link(session.codec, session.signing, LinkFaults(vehicle.params, seed))
    source = FrameSource(seed)
    kinds = collections.Counter()
    stats = collections.Counter()
    acks = collections.Counter()
    t0 = time.monotonic()
    sent = 0
    while sent < frames:
        link.advance(UNIX_EPOCH_S + vehicle.time_s, vehicle.time_s)
        for _ in range(min(BATCH, frames - sent)):
            kind, data = source.frame()
            kinds[kind] += 1
            sender = source.rng.choice(CLIENTS)
            sent += 1
            for msg, answerable in link.receive(data, sender):  # each judged after the last was handled
                if answerable and msg.get_type() == "BAD_DATA":
                    raise FuzzFailure(f"a damaged frame would make {sender} a peer")
                _deliver(vehicle, session, link, msg, stats, acks)
        armed = vehicle.armed
        for _ in range(STEPS_PER_BATCH):
            vehicle.step()
        if vehicle.armed and not armed:
            raise FuzzFailure("the vehicle armed itself between messages")
        link.pack(session.poll(vehicle.time_s, vehicle.time_s))  # telemetry after hostile input encodes
        problems = vehicle_problems(vehicle, session)
        if problems:
            raise FuzzFailure(f"after {sent} datagrams: {problems}")
        if progress and sent % 50_000 < BATCH:
            progress(sent, time.monotonic() - t0)
    wall = time.monotonic() - t0
    return {"datagrams": sent, "kinds": dict(kinds), "messages": stats["messages"],
            "bad_data": session.counters["bad_data"], "decode_errors": link.counters["decode_errors"],
            "ignored_other_system": session.counters["ignored_other_system"],
            "refused": session.counters["refused"], "handler_errors": session.counters["handler_errors"],
            "acks_by_result": dict(acks), "arms": stats["arms"], "sim_s": vehicle.time_s,
            "wall_s": wall, "datagrams_per_s": sent / wall if wall else 0.0}


def _deliver(vehicle, session, link, msg, stats, acks) -> None:
    stats["messages"] += 1
    armed = vehicle.armed
    out = session.receive(msg, vehicle.time_s, vehicle.time_s)
    link.pack(out)  # everything the vehicle says must encode
    arm_acked = False
    for m in out:
        if m.get_type() == "COMMAND_ACK":
            acks[m.result] += 1
            arm_acked |= m.command == ARM and m.result == 0
    if vehicle.armed and not armed:
        if not (arm_acked and msg.get_type() in ("COMMAND_LONG", "COMMAND_INT") and msg.param1 == 1):
            raise FuzzFailure(f"armed by {msg} without an accepted ARM")
        stats["arms"] += 1


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="receive_fuzz", description=__doc__.splitlines()[0])
    p.add_argument("--frames", type=int, default=1_000_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, help="write the figures here")
    args = p.parse_args(argv)

    def progress(sent, wall):
        print(f"fuzz: {sent:,}/{args.frames:,} datagrams, {wall:.0f} s, {sent / wall:,.0f}/s",
              file=sys.stderr, flush=True)
    try:
        result = run(args.frames, args.seed, progress)
    except FuzzFailure as exc:
        print(f"fuzz: FAILED: {exc}", file=sys.stderr)
        return 1
    print(json.dumps(result, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
