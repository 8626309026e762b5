"""The packed parameter file: Firefly's encoder against pymavlink's and MAVProxy's parsers, and
byte for byte against files recorded from the reference ArduCopter."""
from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import pytest
from MAVProxy.modules.lib import param_ftp
from pymavlink.mavftp import MAVFTP

from firefly.autopilot.mavlink import param_files, param_pack
from firefly.autopilot.params import SERVED_BY_NAME, ParamStore

RECORDED = Path(__file__).resolve().parents[1] / "parity" / "recorded" / "ftp_reference.json"


def _f32(x: float) -> float:
    return struct.unpack("<f", struct.pack("<f", x))[0]


def _download(params, query: str = "", read_size: int = 239) -> bytes:
    f = param_files.open_read(params, "@PARAM/param.pck" + query)
    out, offset = b"", 0
    while block := f.read(offset, read_size):
        out += block
        offset += len(block)
    return out


@pytest.fixture
def params():
    store = ParamStore()
    store.set("WPNAV_SPEED", 1234.5)
    store.set("FENCE_TYPE", 3)
    store.set("MAV1_EXTRA1", 7)
    return store


@pytest.mark.parametrize("read_size", [239, 80, 64, 7])
def test_every_parameter_round_trips_through_pymavlink_and_mavproxy(params, read_size):
    data = _download(params, read_size=read_size)
    magic, count, total = struct.unpack_from("<HHH", data)
    assert (magic, count, total) == (0x671B, len(params), len(params))
    for decoded in (MAVFTP.ftp_param_decode(data), param_ftp.ftp_param_decode(data)):
        assert decoded is not None and decoded.defaults is None
        got = {name.decode(): (value, ptype) for name, value, ptype in decoded.params}
        assert list(got) == params.names()  # every parameter, in the table's order
        for name, (value, ptype) in got.items():
            assert ptype == param_pack.packed_type(params.mav_type(name)), name  # as PARAM_VALUE types it
            assert value == _f32(params[name]), name


def test_with_defaults_carries_the_default_of_each_changed_parameter(params):
    data = _download(params, "?withdefaults=1")
    assert struct.unpack_from("<H", data)[0] == 0x671C
    decoded = MAVFTP.ftp_param_decode(data)
    values = {n.decode(): v for n, v, _ in decoded.params}
    defaults = {n.decode(): v for n, v, _ in decoded.defaults}
    assert values["WPNAV_SPEED"] == 1234.5 and defaults["WPNAV_SPEED"] == SERVED_BY_NAME["WPNAV_SPEED"].default
    assert values["FENCE_TYPE"] == 3 and defaults["FENCE_TYPE"] == SERVED_BY_NAME["FENCE_TYPE"].default
    for name in params.names():
        assert defaults[name] == _f32(SERVED_BY_NAME[name].default), name
    flagged = {e.name for e in param_pack.unpack(data)[2] if e.default is not None}
    assert flagged == {"WPNAV_SPEED", "FENCE_TYPE", "MAV1_EXTRA1"}  # only what differs


@pytest.mark.parametrize("read_size", [239, 80, 64, 33, 5])
@pytest.mark.parametrize("with_defaults", [False, True])
def test_no_record_ends_with_a_value_split_across_read_blocks(params, read_size, with_defaults):
    """ArduPilot's padding rule: a record's last value (the value, or the default when one is
    sent) never straddles two reads, so a re-read block cannot mix old and new bytes of it."""
    data = param_pack.pack(param_files._snapshot(params), len(params), read_size, with_defaults)
    pos, padded = param_pack.HEADER.size, 0
    for _ in range(len(params)):
        while data[pos] == 0:
            pos, padded = pos + 1, padded + 1
        name_len = (data[pos + 1] >> 4) + 1
        n_values = 2 if data[pos] >> 4 else 1
        size = {1: 1, 2: 2, 3: 4, 4: 4}[data[pos] & 0x0F]  # int8, int16, int32, float
        end = pos + 2 + name_len + size * n_values
        assert (end - size) // read_size == (end - 1) // read_size, (pos, read_size)
        pos = end
    assert pos == len(data)
    assert padded > 0 or read_size == 239  # small blocks need padding somewhere


def test_names_share_their_prefix_with_the_previous_one():
    entries = [param_pack.Entry("ATC_RAT_RLL_P", 4, 1.0), param_pack.Entry("ATC_RAT_RLL_I", 4, 2.0),
               param_pack.Entry("ATC_RAT", 3, 3), param_pack.Entry("BATT_X", 1, -5),
               param_pack.Entry("BATT_XY", 2, 300)]
    data = param_pack.pack(entries, 5, 239)
    assert data[6 + 2:6 + 2 + 13] == b"ATC_RAT_RLL_P"
    second = 6 + 2 + 13 + 4
    assert data[second + 1] == 12 | 0 << 4 and data[second + 2:second + 3] == b"I"  # 12 shared, 1 new
    third = second + 2 + 1 + 4
    assert data[third + 1] == 6 | 0 << 4 and data[third + 2:third + 3] == b"T"  # a prefix of the last
    assert [(e.name, e.ptype, e.value) for e in param_pack.unpack(data)[2]] == \
        [(e.name, e.ptype, float(e.value)) for e in entries]


def test_malformed_files_are_refused_not_crashed_on():
    good = param_pack.pack([param_pack.Entry("RTL_ALT", 3, 1500)], 1, 239)
    for bad in (b"", good[:5], b"\x00\x11" + good[2:], good[:-1], good[:6] + b"\x09" + good[7:],
                good[:6] + bytes([3, 0xF5]) + good[8:]):
        with pytest.raises(param_pack.PackError):
            param_pack.unpack(bad)


# ----- the reference's own files --------------------------------------------------------------
def _recorded_files():
    return json.loads(RECORDED.read_text())["files"]


@pytest.mark.parametrize("key", ["param_239", "param_80", "crc_read_64", "param_defaults",
                                 "param_start10_count5"])
def test_repacking_the_reference_file_gives_the_same_bytes(key):
    """Decoded and packed again by Firefly at the same read size, the reference's file comes back
    byte for byte: same header, prefix compression, types, padding and default flags."""
    rec = _recorded_files()[key]
    data = base64.b64decode(rec["base64"])
    magic, total, entries = param_pack.unpack(data)
    with_defaults = magic == param_pack.MAGIC_WITH_DEFAULTS
    if with_defaults:  # an unflagged entry's default is its value
        entries = [e if e.default is not None else param_pack.Entry(e.name, e.ptype, e.value, e.value)
                   for e in entries]
        # The reference flags SIM_OH_RELAY_MSK, an INT16 whose default (65535) wraps to its value -1.
        entries = [param_pack.Entry(e.name, e.ptype, e.value, 65535.0) if e.name == "SIM_OH_RELAY_MSK"
                   else e for e in entries]
    assert param_pack.pack(entries, total, rec["read_size"], with_defaults) == data


def test_file_crc_is_the_references_crc():
    rec = _recorded_files()["crc_read_64"]
    data = base64.b64decode(rec["base64"])
    expected = bytes.fromhex(rec["calc_file_crc32_reply_data"])

    _, total, entries = param_pack.unpack(data)
    crc = param_files.file_crc32(param_files.ParamFile(entries, total))
    assert struct.pack("<I", crc) == expected
