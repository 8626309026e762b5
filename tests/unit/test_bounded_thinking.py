"""Bounded thinking (issue 30, item 4): what a find changes (the earlier finds relocated, the
hot spots fitted, the belief rebuilt from every reading) is worked through a few chunks per step,
the vehicle holding over the find meanwhile, and the belief in use is replaced only when its
successor has every reading (strategy/controller.py, "Thinking spread over steps")."""
from __future__ import annotations

import numpy as np
import pytest

from firefly.groundstation.evaluation.episodes import EpisodeConfig, run_episode
from firefly.groundstation.strategy import controller, make_policy
from firefly.groundstation.strategy.belief import Belief, Geometry
from firefly.groundstation.strategy.controller import Goto, SearchController
from firefly.sim.fire import Fire, FireWorld, true_temperature


def two_fire_world() -> FireWorld:
    return FireWorld(fires=(Fire(135.0, 72.0, 45.0), Fire(45.0, 150.0, 40.0)), area_m=200.0, survey_alt_m=25.0,
                     ambient_c=18.0)


def test_a_find_is_thought_over_across_steps_while_the_vehicle_holds_over_it(monkeypatch):
    chunks_in_step = []  # generator steps of every job, per controller step
    record = []  # per step: (job kinds after it, the belief in use, the answer)
    work = SearchController._work

    def counted_work(self, chunks):
        before = calls[0]
        work(self, chunks)
        chunks_in_step[-1] += calls[0] - before

    calls = [0]
    absorbing = Belief.absorbing

    def counted_absorbing(self, readings, chunk=100):
        for _ in absorbing(self, readings, chunk):
            calls[0] += 1
            yield

    step = SearchController.step

    def recorded_step(self, *args, **kwargs):
        chunks_in_step.append(0)
        move = step(self, *args, **kwargs)
        record.append(([kind for kind, _ in self._jobs], self.belief, move, self._holding))
        return move

    monkeypatch.setattr(SearchController, "_work", counted_work)
    monkeypatch.setattr(Belief, "absorbing", counted_absorbing)
    monkeypatch.setattr(SearchController, "step", recorded_step)
    result = run_episode(two_fire_world(), 11, 34, make_policy("gig"),
                         EpisodeConfig(fixed_fire=True, fires=2, max_fires=None))
    assert result.fires_found == 2 and not result.false_declaration

    # no step works through more of the rebuilds' chunks than its share
    assert max(chunks_in_step) <= controller.JOB_CHUNKS_PER_STEP
    # a find's job spans steps, and meanwhile the vehicle holds over the find
    finding = [(move, holding) for kinds, _, move, holding in record if "find" in kinds]
    assert len(finding) >= 2
    assert all(isinstance(move, Goto) and move.target == holding[0] and move.height_m is None
               for move, holding in finding)
    # the belief with the finds known replaces the one in use only once it has every reading,
    # steps after it was asked for
    rebuilding = [i for i, (kinds, *_) in enumerate(record) if "rebuild" in kinds]
    assert rebuilding
    first = rebuilding[0]
    end = next(i for i in range(first, len(record)) if "rebuild" not in record[i][0])
    assert end - first >= 2
    assert all(record[i][1] is record[first][1] for i in range(first, end))
    assert record[end][1] is not record[first][1]


def test_readings_taken_together_reach_the_belief_taken_one_by_one():
    w = FireWorld(fires=(Fire(200.0, 120.0, 50.0), Fire(200.0, 280.0, 40.0)), ambient_c=21.0, noise_k=1.0)
    rng = np.random.default_rng(5)
    points = rng.uniform(0.0, w.area_m, size=(300, 2))
    readings = [(n, e, true_temperature(w, n, e, 30.0, 0.0) + rng.normal(0.0, 1.0), 30.0) for n, e in points]
    readings[260] = readings[260][:2] + (readings[260][2] + 40.0, 30.0)  # a wild one among the new

    def belief():
        b = Belief(Geometry.from_world(w), subcells=3, outlier_rate=0.02, known=((200.0, 120.0, 0.0, 0.0),),
                   null_prior=0.5)
        b.absorb(readings[:250])
        return b
    one_by_one, together = belief(), belief()
    for r in readings[250:]:
        one_by_one.update(*r)
    together.update_together(readings[250:275])
    together.update_together(readings[275:])
    assert together.n == one_by_one.n == 300
    assert together.most_likely()[1] == one_by_one.most_likely()[1]
    assert 0.5 * np.abs(together.p - one_by_one.p).sum() < 0.01
    assert together.p_fire == pytest.approx(one_by_one.p_fire, abs=0.01)


def test_with_heavy_finds_known_a_step_works_one_chunk(monkeypatch):
    """HEAVY_KNOWN finds make each chunk's fits dearer: a step then works at most one chunk.
    Lowered to two here, so that a two-fire world reaches it."""
    monkeypatch.setattr(controller, "HEAVY_KNOWN", 2)
    given = []  # per call of _work: (finds known, chunks allowed)
    work = SearchController._work

    def recorded_work(self, chunks):
        given.append((len(self.found), chunks))
        work(self, chunks)

    monkeypatch.setattr(SearchController, "_work", recorded_work)
    result = run_episode(two_fire_world(), 11, 34, make_policy("gig"),
                         EpisodeConfig(fixed_fire=True, fires=2, max_fires=None))
    assert result.fires_found == 2
    assert any(known >= 2 for known, _ in given), "the search never worked a job with two finds known"
    assert all(chunks <= 1 for known, chunks in given if known >= 2)
    assert any(chunks == controller.JOB_CHUNKS_PER_STEP for known, chunks in given if known < 2)


def test_a_belief_over_more_hypotheses_gets_smaller_chunks_and_one_a_step(monkeypatch):
    """With known fires, a belief over more than REFERENCE_HYPOTHESES hypotheses (several plume
    leans) feeds proportionally fewer readings a chunk, and a step works one chunk. The reference
    is lowered here to half this world's hypotheses."""
    hypotheses = 3_600  # the 200 m world: 20 x 20 cells of 3 x 3 sub-positions
    monkeypatch.setattr(controller, "REFERENCE_HYPOTHESES", hypotheses // 2)
    sizes, given = [], []
    absorbing, work = Belief.absorbing, SearchController._work

    def recorded_absorbing(self, readings, chunk=100):
        assert self.hyp_n.size == hypotheses
        sizes.append((len(self.known), chunk))
        return absorbing(self, readings, chunk)

    def recorded_work(self, chunks):
        given.append((len(self.found), chunks))
        work(self, chunks)

    monkeypatch.setattr(Belief, "absorbing", recorded_absorbing)
    monkeypatch.setattr(SearchController, "_work", recorded_work)
    result = run_episode(two_fire_world(), 11, 34, make_policy("gig"),
                         EpisodeConfig(fixed_fire=True, fires=2, max_fires=None))
    assert result.fires_found == 2
    assert any(known for known, _ in sizes)
    assert all(chunk == controller.JOB_ROWS // 2 for known, chunk in sizes if known)
    assert all(chunks <= 1 for found, chunks in given if found)


def test_a_policy_deciding_at_every_observation_still_gets_its_rebuild_judged(monkeypatch):
    """Greedy decides at every observation, and a step that decides works no chunk: the rebuild
    that an estimated wind asks for starved, the search never judged it, and every episode in wind
    flew its whole path budget. A step that follows one that worked nothing works a chunk."""
    rebuilds = []
    rebuild = SearchController._rebuild

    def counted_rebuild(self, judged=True):
        rebuilds.append(self.observations)
        rebuild(self, judged)

    monkeypatch.setattr(SearchController, "_rebuild", counted_rebuild)
    config = EpisodeConfig(air_ne_m_s=(1.0, 0.0))
    result = run_episode(FireWorld(), 5, 0, make_policy("greedy"), config)
    assert rebuilds, "the estimated wind asked for no rebuild: nothing was tested"
    assert not result.forced and result.success
    assert result.path_m < config.budget_m / 5
