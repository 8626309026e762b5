"""`autopilot --count N`: several independent vehicles in one process, one UDP port each."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from pymavlink import mavutil

from firefly.autopilot.testing.run import free_port_bases

from .conftest import exit_report_problems
from .pymav import Gcs

pytestmark = pytest.mark.sitl
mav = mavutil.mavlink


def test_three_vehicles_one_process_each_its_own(autopilot_factory):
    (base,) = free_port_bases(1, 3)  # base, base+10, base+20: the three vehicles' --out ports
    ap = autopilot_factory(extra=("--count", "3"), port=base)
    links = [Gcs(f"udpin:127.0.0.1:{base + 10 * k}") for k in range(3)]
    try:
        assert [g.heartbeat.get_srcSystem() for g in links] == [1, 2, 3]
        homes = [g.recv("HOME_POSITION", 5) for g in links]
        lat = [h.latitude / 1e7 for h in homes]
        lon = [h.longitude / 1e7 for h in homes]
        east = [(x - lon[0]) * 111_320 * math.cos(math.radians(lat[0])) for x in lon]
        assert east[1] == pytest.approx(5.0, abs=0.05) and lat[1] == pytest.approx(lat[0], abs=1e-7)
        # Fly vehicle 2 only; 1 and 3 stay on the ground, disarmed.
        middle = links[1]
        assert middle.command(mav.MAV_CMD_DO_SET_MODE, 1, 4) == 0
        assert middle.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == 0
        assert middle.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 8) == 0
        assert middle.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > 7500) is not None
        for g in (links[0], links[2]):
            hb = g.recv("HEARTBEAT", 5)
            assert hb.custom_mode == 0 and not hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
            pos = g.recv("GLOBAL_POSITION_INT", 5)
            assert abs(pos.relative_alt) < 100
    finally:
        for g in links:
            g.close()


def test_a_swarm_that_ticks_in_batches_answers_and_flies_each_vehicle(autopilot_factory):
    """From ten vehicles up, a finite speedup ticks each vehicle several times in a row
    (io/runner.py): a client of the last one is still answered and flies it, and the rest stay
    put."""
    count = 12
    (base,) = free_port_bases(1, count)
    autopilot_factory(speedup="2", extra=("--count", str(count)), port=base)
    last = Gcs(f"udpin:127.0.0.1:{base + 10 * (count - 1)}")
    first = Gcs(f"udpin:127.0.0.1:{base}")
    try:
        assert last.heartbeat.get_srcSystem() == count
        assert last.command(mav.MAV_CMD_DO_SET_MODE, 1, 4) == 0
        assert last.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == 0
        assert last.command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 5) == 0
        assert last.recv("GLOBAL_POSITION_INT", 20, lambda m: m.relative_alt > 4500) is not None
        hb = first.recv("HEARTBEAT", 5)
        assert hb.custom_mode == 0 and not hb.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
    finally:
        last.close()
        first.close()


def _children(pid: int) -> list[int]:
    try:
        return [int(p) for p in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


@pytest.mark.serial  # 255 vehicles keep a core busy while they boot
def test_a_fleet_past_255_runs_in_parts_each_with_ids_from_1(autopilot_factory, tmp_path):
    """`--count 256`: vehicles 0..254 in the process started, vehicle 255 in a child it starts;
    the child's vehicle is system 1 again, stands on the fleet's grid (not on vehicle 0's place),
    answers on its own port, and the child goes when the fleet is stopped."""
    count = 256
    (base,) = free_port_bases(1, count)
    stats = tmp_path / "fleet.json"
    ap = autopilot_factory(speedup="1", extra=("--count", str(count), "--serial0", "none", "--stats", str(stats)),
                           port=base)
    first, last_of_part, child = (Gcs(f"udpin:127.0.0.1:{base + 10 * k}", timeout=120) for k in (0, 254, 255))
    try:
        assert [g.heartbeat.get_srcSystem() for g in (first, last_of_part, child)] == [1, 255, 1]
        homes = [g.recv("HOME_POSITION", 20) for g in (first, child)]
        assert None not in homes
        # vehicle 255 of a 16-column grid: row 15, column 15, 5 m apart
        north = (homes[1].latitude - homes[0].latitude) / 1e7 * 111_320
        assert north == pytest.approx(75.0, abs=0.5)
        assert child.command(mav.MAV_CMD_DO_SET_MODE, 1, 4) == 0  # GUIDED, answered by the child's vehicle
        assert child.recv("HEARTBEAT", 5, lambda m: m.custom_mode == 4) is not None
        assert first.recv("HEARTBEAT", 5, lambda m: m.custom_mode == 0) is not None
        parts = _children(ap.process.pid)
        assert len(parts) == 1
    finally:
        for g in (first, last_of_part, child):
            g.close()
    assert ap.stop() == 0
    assert not any(Path(f"/proc/{pid}").exists() for pid in parts)
    part_stats = tmp_path / "fleet.from-255.json"
    systems = [v["system_id"] for v in json.loads(part_stats.read_text())["vehicles"]]
    assert systems == [1]
    assert not exit_report_problems(part_stats)
