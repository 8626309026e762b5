"""Fleets past 255 vehicles: one command, several processes.

MAVLink system ids end at 255 on one network. A vehicle here is its own network already (its
own UDP and TCP ports, talked to by its own clients), so ids may repeat across a fleet as long
as the vehicles that share a process (and its air: the traffic they see of each other) have
distinct ones. Instance N is system id N % 255 + 1 (N + 1 below 255, as ArduPilot SITL numbers
its instances), and `autopilot --count N` runs the fleet in parts of 255 consecutive instances,
one process each: the first in the process started, the rest in child processes it starts with
the same options and waits for. A fleet is the same vehicles, seeds, places and ports whether
it runs in one process or in several; a part's vehicles only hear each other, and two cores run
two parts at once.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from ..instances import PART_SIZE, system_id_of

__all__ = ["MAX_INSTANCE", "PART_SIZE", "parse_fleet", "part_stats_path", "parts", "start_parts", "stop_parts",
           "system_id_of"]
# The highest instance: its ports (14540 + 10N for the second default --out, 5760 + 10N) must
# exist, and 5000 vehicles is far past what two cores fly at 1x.
MAX_INSTANCE = 4999


def parts(total: int) -> list[tuple[int, int]]:
    """(first vehicle index, vehicles) of each process of a fleet of `total`."""
    return [(first, min(PART_SIZE, total - first)) for first in range(0, total, PART_SIZE)]


def parse_fleet(text: str) -> tuple[int, int]:
    """--fleet FIRST,TOTAL (how a fleet's parent starts a part): the part's first vehicle index and
    the fleet's size."""
    first, _, total = text.partition(",")
    try:
        first_n, total_n = int(first), int(total)
    except ValueError:
        raise ValueError(f"expected FIRST,TOTAL, got {text!r}") from None
    if not 0 <= first_n < total_n:
        raise ValueError(f"expected 0 <= FIRST < TOTAL, got {text!r}")
    return first_n, total_n


def part_stats_path(stats: str, first: int) -> str:
    """Where a part's --stats report goes: beside the fleet's, named by its first vehicle."""
    path = Path(stats)
    return str(path.with_name(f"{path.stem}.from-{first}{path.suffix}"))


def start_parts(argv: list[str], total: int, stats: str | None) -> list[subprocess.Popen]:
    """Every part but the first, each a child process with this process's options (argparse takes
    the last of a repeated option: the part's count, its place in the fleet, this process as the
    parent it stops with, its own --stats file)."""
    children = []
    for first, count in parts(total)[1:]:
        extra = ["--count", str(count), "--fleet", f"{first},{total}", f"--exit-with-parent={os.getpid()}",
                 "--quiet"]
        if stats:
            extra += ["--stats", part_stats_path(stats, first)]
        children.append(subprocess.Popen([sys.executable, "-m", "firefly.autopilot", *argv, *extra],
                                         stdin=subprocess.DEVNULL))
    return children


def stop_parts(children: list[subprocess.Popen], wait_s: float = 10.0) -> int:
    """Stop the children (SIGTERM, as the parent was) and wait; the first non-zero exit status of a
    child, else 0."""
    for child in children:
        if child.poll() is None:
            child.terminate()
    worst = 0
    for child in children:
        try:
            code = child.wait(wait_s)
        except subprocess.TimeoutExpired:
            child.kill()
            code = child.wait()
        if code and not worst:
            worst = code
    return worst
