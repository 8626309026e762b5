"""The surface score (tests/parity/surface/score.py): an entry is matching only when every fact
its probes recorded matches; an unprobed in-scope entry counts against Firefly."""
from __future__ import annotations

from tests.parity.compare_run import judge
from tests.parity.facts import Check
from tests.parity.surface.score import Entry, share, statuses


def check(name: str, ok: bool) -> Check:
    return Check("params", name, 1, 1 if ok else 2, ok)


SURFACE = {"parameters": [Entry("parameters", "A"), Entry("parameters", "B"), Entry("parameters", "C"),
                          Entry("parameters", "D"), Entry("parameters", "E", in_scope=False, why="hardware")]}


def test_each_entry_is_judged_by_all_its_checks_and_unprobed_ones_count_as_gaps():
    checks = [check("list/A", True), check("list/B", False), check("list/C", False)]
    differences = [{"checks": ["params/list/C"], "why": "on purpose"}]
    result = judge("params", checks, differences, gaps={"parameters": {"B"}})
    assert not result.unexplained  # B is a listed gap, C a listed difference
    column = statuses([result], SURFACE)["parameters"]
    assert column == {"A": "matching", "B": "not yet", "C": "deliberate", "D": "not probed", "E": "out of scope"}
    assert share(column) == (4, 1, 1, 2)


def test_a_mismatch_in_an_entry_not_listed_is_a_regression():
    result = judge("params", [check("list/A", False), check("list/B", False)], [], gaps={"parameters": {"B"}})
    assert [c.name for c in result.unexplained] == ["list/A"]


def test_a_listed_difference_that_matches_is_stale_unless_it_differs_sometimes():
    matching = [check("list/A", True)]
    assert judge("params", matching, [{"checks": ["params/list/A"], "why": "gone"}]).stale == ["params/list/A"]
    sometimes = {"checks": ["params/list/A"], "why": "differs in one run of four", "sometimes": True}
    assert judge("params", matching, [sometimes]).stale == []
