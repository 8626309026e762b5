"""PathTol: a flown track compared with the reference's as a path, and photo places as a set."""
from tests.parity.facts import PathTol, Trace, compare

SQUARE = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]]


def test_a_track_sampled_elsewhere_along_the_same_path_matches():
    resampled = [[0.0, 0.0], [3.3, 0.2], [7.1, -0.3], [10.0, 0.0], [10.0, 5.5], [10.0, 10.0]]
    assert PathTol(abs=0.5).accepts(SQUARE, resampled)


def test_a_cut_corner_is_as_far_off_as_it_cuts():
    cut = [[0.0, 0.0], [8.0, 0.0], [10.0, 2.0], [10.0, 10.0]]
    assert round(PathTol(abs=1.0).distance(SQUARE, cut), 3) == 1.414
    assert not PathTol(abs=1.0).accepts(SQUARE, cut) and PathTol(abs=1.5).accepts(SQUARE, cut)


def test_a_track_that_stops_short_fails_however_close_its_points_are():
    assert not PathTol(abs=1.0).accepts(SQUARE, SQUARE[:2])


def test_photo_places_are_matched_one_by_one_not_along_a_line():
    assert PathTol(abs=1.0, points=True).accepts([[0, 0], [8, 0]], [[0.5, 0], [8, 0.5]])
    assert not PathTol(abs=1.0, points=True).accepts([[0, 0], [8, 0]], [[0, 0], [4, 0], [8, 0]])
    assert PathTol(abs=1.0, points=True).accepts([], []) and not PathTol(abs=1.0, points=True).accepts([[0, 0]], [])


def test_compare_uses_the_path_tolerance():
    trace = Trace()
    trace.fact("track", [[0.0, 0.2], [10.0, 0.3], [10.2, 10.0]], PathTol(abs=0.5))
    trace.fact("other", [[1, 2]])
    checks = {c.name: c.ok for c in compare("a", "p", {"track": SQUARE, "other": [[1, 2]]}, trace)}
    assert checks == {"p/track": True, "p/other": True}
