"""A campaign's results: JSON Lines, one episode per line, appended as each finishes.

The first line names the campaign (its fingerprint, file, Firefly's version); every other line is
one task's record with its full identity (condition, policy, episode, seed, flown or not, version)
and its result or its error. A line is flushed as it is written, so a crash or Ctrl-C loses only
episodes still running; a last line cut short by a kill is dropped when the file is resumed.
"""
from __future__ import annotations

import json
import os
import time
from importlib import metadata
from pathlib import Path

from .spec import Campaign, CampaignError, Task


def version() -> str:
    try:
        return metadata.version("firefly-sitl")
    except metadata.PackageNotFoundError:
        return "unknown"


class ResultStore:
    def __init__(self, path: Path, campaign: Campaign, resume: bool):
        self.path = Path(path)
        self.campaign = campaign
        self.records: dict[str, dict] = {}
        try:
            self._open(resume)
        except OSError as exc:  # --out names a file, or a directory nobody may write
            raise CampaignError(f"--out: cannot write {self.path}: {exc.strerror or exc}") from None

    def _open(self, resume: bool) -> None:
        campaign = self.campaign
        if resume:
            self._read()
            self._file = open(self.path, "a")
        else:
            if self.path.exists() and self.path.stat().st_size > 0:
                raise CampaignError(f"{self.path} already holds results: --resume to go on with them, "
                                    "or give another --out")
            if self.path.parent.exists() and not self.path.parent.is_dir():
                raise CampaignError(f"--out: {self.path.parent} is a file, not a directory")
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._file = open(self.path, "w")
            self._write({"campaign": campaign.name, "fingerprint": campaign.fingerprint, "file": str(campaign.path),
                         "version": version(), "created_unix_s": round(time.time(), 3)})

    def _read(self) -> None:
        if not self.path.exists():
            raise CampaignError(f"--resume: no results file {self.path}")
        raw = self.path.read_bytes()
        whole = raw[:raw.rfind(b"\n") + 1]
        if len(whole) < len(raw):  # a line cut short by a kill: dropped, its episode runs again
            with open(self.path, "r+b") as f:
                f.truncate(len(whole))
        lines = whole.decode().splitlines()
        try:
            header = json.loads(lines[0]) if lines else None
        except json.JSONDecodeError:
            header = None
        if not isinstance(header, dict) or "fingerprint" not in header:
            raise CampaignError(f"--resume: {self.path} is not a campaign results file (no header line)")
        if header["fingerprint"] != self.campaign.fingerprint:
            raise CampaignError(f"--resume: {self.path} holds campaign {header.get('campaign')!r} "
                                f"({header.get('file')}, fingerprint {header['fingerprint']}), not this one "
                                f"({self.campaign.name!r}, fingerprint {self.campaign.fingerprint}): the "
                                "scenario, policies, episodes or sweep differ")
        for n, line in enumerate(lines[1:], start=2):
            try:
                record = json.loads(line)
            except json.JSONDecodeError:
                raise CampaignError(f"--resume: {self.path} line {n} is not JSON") from None
            self.records.setdefault(record["id"], record)

    def _write(self, record: dict) -> None:
        self._file.write(json.dumps(record, default=list) + "\n")
        self._file.flush()

    def add(self, task: Task, ok: bool, value, attempts: int) -> dict:
        record = {"id": task.id, "campaign": self.campaign.fingerprint, "condition": dict(task.condition.values),
                  "policy": task.policy, "episode": task.episode, "seed": self.campaign.seed, "flown": task.flown,
                  "version": version(), "status": "ok" if ok else "failed", "attempts": attempts}
        if ok:
            record |= {"result": value["result"], "wall_s": value["wall_s"]}
        else:
            record["error"] = value
        self.records[task.id] = record
        self._write(record)
        return record

    def close(self) -> None:
        self._file.flush()
        os.fsync(self._file.fileno())
        self._file.close()
