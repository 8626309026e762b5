"""Where a vehicle's MAVLink 2 signing key comes from, and where its signing state is kept.

A key is given as one line of text (a `--signing-key` file, or `[signing] key` in a scenario):
- exactly 64 hexadecimal digits: the 32-byte key itself;
- anything else: a passphrase, hashed with SHA-256 into the key, as MAVProxy's
  `signing setup PASSPHRASE` / `signing key PASSPHRASE` do, so the same word works in both.

The key set over the wire by SETUP_SIGNING and the signing timestamp live in the instance's state
directory (signing.json, written atomically, readable only by its owner), like ArduPilot's
storage: the key survives a restart and the timestamp never goes back. The timestamp kept is a
high-water mark saved before any frame stamped above it is let in (autopilot/mavlink/signing.py),
so a restart, even after kill -9, refuses what was accepted before it and starts from the larger
of that mark and the clock.
"""
from __future__ import annotations

import hashlib
import re
import time
from pathlib import Path

from ..mavlink.signing import LinkSigning, signing_time
from .persist import read_json, write_json_atomic

MAX_KEY_FILE_BYTES = 4096
_HEX_KEY = re.compile(r"[0-9a-fA-F]{64}")


class SigningKeyError(ValueError):
    pass


def key_from_text(text: str) -> bytes:
    """The 32-byte key that one line of text stands for (see the module docstring)."""
    line = text.strip()
    if not line:
        raise SigningKeyError("empty: expected 64 hex digits or a passphrase")
    if "\n" in line or "\r" in line:
        raise SigningKeyError("expected one line (64 hex digits or a passphrase), got several")
    if _HEX_KEY.fullmatch(line):
        key = bytes.fromhex(line)
        if not any(key):
            raise SigningKeyError("an all-zero key means signing off; choose a secret one")
        return key
    return hashlib.sha256(line.encode()).digest()


def read_key_file(path: Path) -> bytes:
    """The key in a key file; SigningKeyError says in a few words what is wrong with it."""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_KEY_FILE_BYTES + 1)
    except FileNotFoundError:
        raise SigningKeyError("no such file") from None
    except OSError as exc:
        raise SigningKeyError(f"cannot read ({exc.strerror})") from None
    if len(data) > MAX_KEY_FILE_BYTES:
        raise SigningKeyError(f"larger than {MAX_KEY_FILE_BYTES} bytes: not a key file")
    try:
        text = data.decode()
    except UnicodeDecodeError:
        raise SigningKeyError("not text: write the key as 64 hex digits or a passphrase") from None
    return key_from_text(text)


def attach_state(signing: LinkSigning, path: Path, key: bytes | None, wipe: bool) -> None:
    """Continue the signing state saved at `path` and save it there from now on.

    `key` (from --signing-key or the scenario), when given, wins over a key set earlier by
    SETUP_SIGNING; --wipe forgets that key, as SITL's -w does."""
    if wipe:
        path.unlink(missing_ok=True)
    signing.restore(read_json(path))
    if key is not None:
        signing.set_key(key)
    signing.persist = lambda record: _save(path, record)
    signing.advance(signing_time(time.time()))


def _save(path: Path, record: dict) -> bool:
    try:
        write_json_atomic(path, record)
    except OSError:  # a full or read-only disk must not stop the vehicle; the failure is counted
        return False
    return True
