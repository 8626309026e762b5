"""The recorded reference: one JSON file per area under tests/parity/recorded/, written by
`python -m tests.parity.record` against ArduCopter SITL, read by the comparison in CI."""
from __future__ import annotations

import json
from pathlib import Path

RECORDED = Path(__file__).parent / "recorded"
ARDUPILOT_COMMIT = "90700977c553d2dfd95a305acf1c3e098e4d9477"  # ArduCopter 4.7.0-dev
PROBE_VERSION = 2  # raise when a probe changes what it measures; re-record then (2: state read from a fresh HEARTBEAT)


def path_of(area: str) -> Path:
    return RECORDED / f"{area}.json"


def save(area: str, traces: dict, boot_s: float | None = None) -> Path:
    RECORDED.mkdir(exist_ok=True)
    doc = {"area": area, "ardupilot_commit": ARDUPILOT_COMMIT, "probe_version": PROBE_VERSION,
           "probes": {name: trace.values for name, trace in traces.items()}}
    path = path_of(area)
    path.write_text(json.dumps(doc, indent=1, sort_keys=False) + "\n")
    return path


def load(area: str) -> dict:
    doc = json.loads(path_of(area).read_text())
    if doc.get("probe_version") != PROBE_VERSION:
        raise ValueError(f"{path_of(area)}: recorded by probe version {doc.get('probe_version')}, "
                         f"the probes are version {PROBE_VERSION}: re-record it")
    return doc
