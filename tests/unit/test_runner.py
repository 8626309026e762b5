"""The loop's clock: a run of S sim seconds is exactly S / tick ticks, however long it is."""
from __future__ import annotations

import math

import pytest

from firefly.autopilot.io.runner import Runner


@pytest.mark.parametrize("duration_s", [0.3, 5.0, 60.0, 3600.0])
def test_a_run_of_s_seconds_is_exactly_s_over_tick_ticks(duration_s):
    runner = Runner([], math.inf)
    runner.run(duration_s)
    assert runner.ticks == round(duration_s / 0.01)
    assert runner.sim_time_s == pytest.approx(duration_s, abs=1e-9)


def _swarm(count: int, tmp_path, name: str, monkeypatch):
    """`count` vehicles of the scripted flight, built as `autopilot --count` builds them (their
    UNIX epoch, read from the wall clock, pinned), with every frame each one queues kept."""
    from firefly.autopilot.cli import main
    from firefly.autopilot.cli.main import build, build_parser
    from firefly.autopilot.testing.run import free_port_bases

    listen, out = free_port_bases(2, count)
    args = build_parser().parse_args([
        "--count", str(count), "--scenario", "scenarios/scripted_flight.toml", "--quiet", "--wipe",
        "--listen", f"udp:127.0.0.1:{listen}", "--out", f"udp:127.0.0.1:{out}",
        "--state-dir", str(tmp_path / name)])
    with monkeypatch.context() as patch:
        patch.setattr(main.time, "time", lambda: 1_790_000_000.0)
        nodes = [node for node, _ in build(args)]
    sent = [[] for _ in nodes]
    for node, frames in zip(nodes, sent):
        queue = node.endpoint.queue
        node.endpoint.queue = lambda key, fs, queue=queue, frames=frames: (frames.extend(fs), queue(key, fs))
    return nodes, sent


def test_a_swarm_ticked_in_batches_flies_and_sends_as_tick_by_tick(tmp_path, monkeypatch):
    """A swarm at a finite speedup ticks each vehicle several times in a row: every vehicle must
    fly the same trajectory and send the same frames as when all advance tick by tick."""
    runs = []
    for name, batch in (("by_tick", 1), ("batched", 5)):
        nodes, sent = _swarm(12, tmp_path, name, monkeypatch)
        runner = Runner(nodes, 1000.0)
        assert runner.batch_ticks > 1  # a swarm at a finite speedup batches by itself
        runner.batch_ticks = batch
        try:
            runner.run(12.34)  # not a whole number of batches: the last one is cut short
        finally:
            for node in nodes:
                node.endpoint.close()
        assert runner.ticks == 1234
        runs.append(([(n.vehicle.time_s, n.vehicle.sim.state, n.vehicle.sim.battery) for n in nodes], sent))
    (states, sent), (states_batched, sent_batched) = runs
    assert states[0][1].body.d_m < -5.0, "vehicle 1 took off"
    assert states_batched == states
    assert all(len(frames) > 100 for frames in sent)
    assert sent_batched == sent


@pytest.mark.internal_errors
@pytest.mark.parametrize("where", ["run_until", "poll"])
def test_a_bug_in_one_vehicle_of_a_swarm_never_stops_the_others(tmp_path, monkeypatch, where):
    """Vehicle 1's step (or its session's poll) raises every time: it is counted as its internal
    error, and vehicles 2 and 3 fly the whole run and keep sending."""
    nodes, sent = _swarm(3, tmp_path, "swarm", monkeypatch)
    broken = nodes[0]

    def bug(*args, **kw):
        raise RuntimeError("a bug in vehicle 1")
    target = broken.vehicle if where == "run_until" else broken.session
    monkeypatch.setattr(target, where, bug)
    runner = Runner(nodes, math.inf)
    try:
        runner.run(3.0)
    finally:
        for node in nodes:
            node.endpoint.close()
    assert runner.ticks == 300
    assert broken.vehicle.internal_errors.count > 0 and "a bug in vehicle 1" in broken.vehicle.internal_errors.last
    for node, frames in zip(nodes[1:], sent[1:]):
        assert node.vehicle.time_s == pytest.approx(3.0) and not node.vehicle.internal_errors
        assert len(frames) > 50


def test_a_reboot_in_a_swarm_restarts_that_vehicle_alone_ticked_either_way(tmp_path, monkeypatch):
    """A vehicle that accepted PREFLIGHT_REBOOT_SHUTDOWN boots again at the exchange that sent its
    ACK (io/reboot.py): its clock starts 0.2 s later from zero and then follows the runner's; the
    other vehicles fly on; batched or tick by tick, the same trajectories."""
    runs = []
    for name, batch in (("by_tick", 1), ("batched", 5)):
        nodes, _ = _swarm(10, tmp_path, name, monkeypatch)
        runner = Runner(nodes, 1000.0)
        runner.batch_ticks = batch
        nodes[3].vehicle.reboot_requested = True  # as the command handler leaves it
        try:
            runner.run(3.0)
        finally:
            for node in nodes:
                node.endpoint.close()
        assert [node.reboots for node in nodes] == [0, 0, 0, 1] + [0] * 6
        rebooted = nodes[3].vehicle
        assert rebooted.powered_on_at_s == pytest.approx(0.2) and rebooted.time_s == pytest.approx(2.8)
        assert all(node.vehicle.time_s == pytest.approx(3.0) for i, node in enumerate(nodes) if i != 3)
        runs.append([(n.vehicle.time_s, n.vehicle.sim.state) for n in nodes])
    assert runs[0] == runs[1]
