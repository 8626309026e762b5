"""Where the signing key comes from (--signing-key file, [signing] in a scenario) and how the
signing state survives a restart. Files only, no sockets."""
from __future__ import annotations

import hashlib
import stat
import time
from types import SimpleNamespace

import pytest

from firefly.autopilot.cli import main as cli
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mavlink.signing import RESERVE, LinkSigning, signing_time
from firefly.autopilot.io.persist import read_json
from firefly.autopilot.cli.scenario import ScenarioError, load_scenario, scenario_from_dict
from firefly.autopilot.io.signing_keys import (MAX_KEY_FILE_BYTES, SigningKeyError, attach_state, key_from_text,
                                    read_key_file)

from ._util import ready_vehicle

HEX_KEY = "00112233445566778899aabbccddeeff" * 2


# ----- key text and key files -------------------------------------------------------------------------
def test_64_hex_digits_are_the_key_itself():
    assert key_from_text(HEX_KEY + "\n") == bytes.fromhex(HEX_KEY)
    assert key_from_text(HEX_KEY.upper()) == bytes.fromhex(HEX_KEY)


def test_a_passphrase_is_hashed_as_mavproxy_signing_setup_does():
    from MAVProxy.modules.mavproxy_signing import SigningModule
    assert key_from_text("firefly-secret\n") == SigningModule.passphrase_to_key(None, "firefly-secret")
    assert key_from_text("firefly-secret") == hashlib.sha256(b"firefly-secret").digest()


@pytest.mark.parametrize("text,why", [("", "empty"), ("  \n", "empty"), ("one\ntwo\n", "one line"),
                                      ("0" * 64, "all-zero")])
def test_unusable_key_text_says_why(text, why):
    with pytest.raises(SigningKeyError, match=why):
        key_from_text(text)


def test_key_file_problems_are_named(tmp_path):
    binary = tmp_path / "key.bin"
    binary.write_bytes(bytes(range(200, 232)))
    huge = tmp_path / "huge"
    huge.write_text("x" * (MAX_KEY_FILE_BYTES + 1))
    for path, why in [(tmp_path / "missing", "no such file"), (binary, "not text"), (huge, "larger"),
                      (tmp_path, "cannot read")]:
        with pytest.raises(SigningKeyError, match=why):
            read_key_file(path)


def test_cli_reports_a_bad_key_file_in_one_line_naming_option_and_file(tmp_path, capsys):
    path = tmp_path / "empty.key"
    path.write_text("")
    assert cli.main(["--signing-key", str(path), "--state-dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "--signing-key" in err and str(path) in err and "empty" in err
    assert "Traceback" not in err


# ----- scenario [signing] ------------------------------------------------------------------------------
def test_scenario_key_or_key_file_relative_to_the_scenario(tmp_path):
    assert scenario_from_dict({"signing": {"key": "sesame"}}).signing_key == hashlib.sha256(b"sesame").digest()
    (tmp_path / "vehicle.key").write_text(HEX_KEY + "\n")
    path = tmp_path / "s.toml"
    path.write_text('[signing]\nkey_file = "vehicle.key"\n')
    assert load_scenario(path).signing_key == bytes.fromhex(HEX_KEY)
    assert scenario_from_dict({}).signing_key is None


@pytest.mark.parametrize("table,words", [({}, "exactly one"), ({"key": "a", "key_file": "b"}, "exactly one"),
                                         ({"passphrase": "a"}, "exactly one"), ({"key": 5}, "[signing].key"),
                                         ({"key": "0" * 64}, "all-zero"), ({"key_file": "nope"}, "no such file")])
def test_scenario_signing_errors_name_the_table_and_key(tmp_path, table, words):
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict({"signing": table}, "test.toml", tmp_path)
    message = str(info.value)
    assert message.startswith("test.toml: [signing]") and words in message and "\n" not in message


def test_a_scenario_key_error_never_shows_the_key():
    with pytest.raises(ScenarioError) as info:
        scenario_from_dict({"signing": {"key": "secret\nword"}}, "test.toml")
    assert "secret" not in str(info.value)


# ----- state across restarts ---------------------------------------------------------------------------
def new_link() -> LinkSigning:
    return LinkSigning(new_codec(1))


def saved_after_setup(path) -> LinkSigning:
    """A link attached to `path` whose key was then set by SETUP_SIGNING, saved."""
    link = new_link()
    attach_state(link, path, None, wipe=False)
    assert not link.enabled and not path.exists()  # nothing to keep without signing
    link.setup_key = bytes.fromhex(HEX_KEY)
    link.set_key(link.setup_key)
    link.save()
    return link


def test_setup_key_and_timestamp_survive_a_restart_in_an_owner_only_file(tmp_path):
    path = tmp_path / "instance-0" / "signing.json"
    first = saved_after_setup(path)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    second = new_link()
    attach_state(second, path, None, wipe=False)
    assert second.key == bytes.fromhex(HEX_KEY)
    assert first.timestamp <= second.timestamp <= signing_time(time.time()) + RESERVE


def test_the_command_line_key_wins_and_is_not_kept(tmp_path):
    path = tmp_path / "signing.json"
    cli_key = key_from_text("from-the-command-line")
    first = new_link()
    attach_state(first, path, cli_key, wipe=False)
    assert first.key == cli_key and path.exists()  # the timestamp is kept from the start
    first.save()
    second = new_link()
    attach_state(second, path, None, wipe=False)
    assert not second.enabled and second.timestamp >= first.timestamp


def test_wipe_forgets_the_setup_key(tmp_path):
    path = tmp_path / "signing.json"
    saved_after_setup(path)
    second = new_link()
    attach_state(second, path, None, wipe=True)
    assert not second.enabled


def test_an_unwritable_state_dir_is_counted_not_fatal(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    link = new_link()
    attach_state(link, blocker / "signing.json", key_from_text("k"), wipe=False)
    assert link.enabled and link.counters["save_failed"] >= 1


def test_exit_report_saves_the_timestamp_and_says_what_was_dropped(tmp_path, capsys):
    session = Session(ready_vehicle(), new_codec(1))
    path = tmp_path / "signing.json"
    attach_state(session.signing, path, key_from_text("k"), wipe=False)
    session.signing.admit(new_codec(255, 190).heartbeat_encode(6, 8, 0, 0, 0).pack(new_codec(255, 190)))
    session.signing.advance(session.signing.timestamp + 5)
    cli.report_signing(SimpleNamespace(session=session, vehicle=session.vehicle), quiet=False)
    assert capsys.readouterr().out == ("system 1: signing on: dropped 1 unsigned, 0 bad signature, "
                                       "0 replay, 0 future, 0 stream table full\n")
    assert read_json(path)["timestamp"] == session.signing.timestamp
