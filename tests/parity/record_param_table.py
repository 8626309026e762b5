"""Record the reference ArduCopter's full parameter table into autopilot/data/arducopter_params.json.

Run against a freshly booted reference SITL (its run folder deleted first, so every value is its
default), for example:

    rm -rf /work/ref/run-5
    /work/shared/reference/run-arducopter-sitl /work/ref 5 14905 5 &
    python -m tests.parity.record_param_table --port 14905 --ardupilot /work/ref/ardupilot

It asks the vehicle for its whole list (PARAM_REQUEST_LIST), asks again by index for whatever
did not arrive (PARAM_REQUEST_READ), and adds the range each parameter's documentation comment
gives (`@Range`) in the reference's source tree. What is written is what the reference served:
names in its index order, MAVLink types and default values as reported.
"""
from __future__ import annotations

import argparse
import json
import struct
import subprocess
import sys
import time
from pathlib import Path

from pymavlink import mavutil

from .param_docs import documented_params

REPO = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO / "autopilot" / "data" / "arducopter_params.json"
INT_TYPES = {mavutil.mavlink.MAV_PARAM_TYPE_INT8, mavutil.mavlink.MAV_PARAM_TYPE_INT16,
             mavutil.mavlink.MAV_PARAM_TYPE_INT32, mavutil.mavlink.MAV_PARAM_TYPE_UINT8,
             mavutil.mavlink.MAV_PARAM_TYPE_UINT16, mavutil.mavlink.MAV_PARAM_TYPE_UINT32}
QUIET_S = 2.0  # a list transfer with nothing new for this long has ended (or lost the rest)


def _name(raw) -> str:
    if isinstance(raw, bytes):
        raw = raw.decode("ascii", "replace")
    return raw.split("\0", 1)[0]


def fetch_params(port: int, timeout_s: float = 120.0) -> tuple[int, dict[int, tuple[str, float, int]]]:
    """(param_count, {index: (name, value, MAVLink type)}) of the vehicle sending to udp `port`."""
    conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255)
    try:
        heartbeat = conn.wait_heartbeat(timeout=timeout_s)
        if heartbeat is None:
            raise TimeoutError(f"no HEARTBEAT on udp port {port} within {timeout_s:g} s")
        target = (conn.target_system, conn.target_component)
        deadline = time.monotonic() + timeout_s
        count, values = None, {}
        conn.mav.param_request_list_send(*target)
        while time.monotonic() < deadline:
            last_new = time.monotonic()
            while time.monotonic() - last_new < QUIET_S and time.monotonic() < deadline:
                msg = conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=0.5)
                if msg is None or msg.param_index >= msg.param_count:
                    continue  # 65535: an unsolicited echo, not part of the list
                if count not in (None, msg.param_count):
                    raise RuntimeError(f"param_count changed from {count} to {msg.param_count}")
                count = msg.param_count
                if msg.param_index not in values:
                    last_new = time.monotonic()
                values[msg.param_index] = (_name(msg.param_id), msg.param_value, msg.param_type)
                if len(values) == count:
                    return count, values
            if count is None:
                conn.mav.param_request_list_send(*target)
                continue
            for index in sorted(set(range(count)) - set(values))[:50]:
                conn.mav.param_request_read_send(*target, b"", index)
        raise TimeoutError(f"got {len(values)} of {count} parameters within {timeout_s:g} s")
    finally:
        conn.close()


def float32_text(value: float) -> float:
    """The shortest decimal that is the same float32 as `value` (0.135, not 0.13500000536441803)."""
    packed = struct.pack("<f", value)
    for digits in range(1, 10):
        shorter = float(f"{value:.{digits}g}")
        if struct.pack("<f", shorter) == packed:
            return shorter
    return value


def table(count: int, values: dict, docs: dict) -> list[dict]:
    entries = []
    for index in range(count):
        name, value, ptype = values[index]
        entry = {"name": name, "type": ptype,
                 "default": int(value) if ptype in INT_TYPES else float32_text(value)}
        doc = docs.get(name)
        rng = doc.range() if doc is not None else None
        if rng is not None:
            entry["low"], entry["high"] = (int(x) if x == int(x) else x for x in rng)
        entries.append(entry)
    return entries


def write(path: Path, header: dict, entries: list[dict]) -> None:
    """One parameter a line, so that a re-recording diffs by parameter."""
    lines = [json.dumps(entry) for entry in entries]
    head = json.dumps(header, indent=1)[:-2]  # the header's fields, its closing brace left open
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(head + ',\n "params": [\n  ' + ",\n  ".join(lines) + "\n ]\n}\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--port", type=int, required=True, help="udp port the reference sends to")
    parser.add_argument("--ardupilot", type=Path, required=True, help="the reference's source tree")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    parser.add_argument("--timeout", type=float, default=120.0)
    args = parser.parse_args(argv)
    commit = subprocess.run(["git", "-C", str(args.ardupilot), "rev-parse", "HEAD"], check=True,
                            capture_output=True, text=True).stdout.strip()
    count, values = fetch_params(args.port, args.timeout)
    docs = documented_params(args.ardupilot / "ArduCopter")
    entries = table(count, values, docs)
    header = {
        "reference": "ArduCopter SITL (--model quad), fresh boot, defaults: "
                     "Tools/autotest/default_params/copter.parm and SIM_FLOAT_EXCEPT 0",
        "commit": commit,
        "recorded_by": "tests/parity/record_param_table.py",
        "fields": "name, type (MAV_PARAM_TYPE as served), default (as served), "
                  "low/high (the @Range of the parameter's documentation, where it has one)",
        "param_count": count,
    }
    write(args.out, header, entries)
    ranged = sum(1 for e in entries if "low" in e)
    print(f"{count} parameters ({ranged} with a documented range) from {commit[:10]} -> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
