"""A short run of the byte-level fuzz in every CI run (`make fuzz` runs a million datagrams)."""
from __future__ import annotations

from .frames import FrameSource
from .receive_fuzz import run


def test_twenty_thousand_hostile_datagrams_leave_the_vehicle_valid_and_counted():
    result = run(20_000, seed=3)  # raises FuzzFailure on an invalid vehicle or an unasked arm
    assert result["handler_errors"] == 0
    assert set(result["kinds"]) == {"valid", "bit_flips", "truncated", "spliced", "garbage", "bad_crc",
                                    "mavlink1", "unknown_id", "many_in_one", "oversize"}
    assert result["bad_data"] > 1000  # broken frames were seen and counted, not silently lost
    assert result["ignored_other_system"] > 0 and result["refused"] > 0
    assert result["acks_by_result"].get(0, 0) > 0  # and well-formed commands still work


def test_the_frame_source_is_deterministic():
    a, b = FrameSource(5), FrameSource(5)
    assert [a.frame() for _ in range(200)] == [b.frame() for _ in range(200)]
