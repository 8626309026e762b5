"""A fleet past 255 vehicles: its parts and their system ids (autopilot/cli/fleet.py)."""
from __future__ import annotations

import pytest

from firefly.autopilot.cli.fleet import PART_SIZE, parse_fleet, part_stats_path, parts, system_id_of


def test_parts_cover_the_fleet_in_order_each_at_most_one_network():
    for total in (1, 254, 255, 256, 510, 511, 1000):
        got = parts(total)
        assert [first for first, _ in got] == list(range(0, total, PART_SIZE))
        assert sum(n for _, n in got) == total and all(1 <= n <= PART_SIZE for _, n in got)


def test_system_ids_are_the_instance_plus_one_then_start_again_and_never_repeat_within_a_part():
    assert [system_id_of(n) for n in (0, 1, 254, 255, 256, 999)] == [1, 2, 255, 1, 2, 235]
    for first, count in parts(1000):
        ids = [system_id_of(first + k) for k in range(count)]
        assert len(set(ids)) == len(ids) and min(ids) >= 1 and max(ids) <= 255


@pytest.mark.parametrize("text", ["3,2", "-1,4", "a,b", "5", "2,2"])
def test_a_bad_fleet_part_is_refused(text):
    with pytest.raises(ValueError):
        parse_fleet(text)


def test_a_part_reports_beside_the_fleet():
    assert part_stats_path("/tmp/run/stats.json", 255) == "/tmp/run/stats.from-255.json"
    assert parse_fleet("255,1000") == (255, 1000)
