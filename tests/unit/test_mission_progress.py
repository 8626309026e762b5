"""Mission progress (mission/progress.py): AP_Mission's verbs over a stored list, without a vehicle."""
from __future__ import annotations

from autopilot.mission import MISSION, MissionItem, MissionStore
from autopilot.mission.progress import MissionProgress, MissionState

WAYPOINT = MissionItem(16, 3, z=10.0)


def progress_with(n: int) -> MissionProgress:
    store = MissionStore()
    store.replace(MISSION, [WAYPOINT] * n)
    return MissionProgress(store)


def test_an_empty_mission_reports_seq_0_and_refuses_set_current():
    progress = MissionProgress(MissionStore())
    assert progress.current_seq() == 0 and progress.index == 0
    assert not progress.set_current(1)
    assert progress.state is MissionState.NOT_STARTED


def test_set_current_takes_seqs_of_stored_items_only():
    progress = progress_with(3)
    assert progress.set_current(3) and progress.current_seq() == 3 and progress.index == 2
    for seq in (0, 4, -1):
        assert not progress.set_current(seq)
    assert progress.current_seq() == 3  # a refused seq changes nothing


def test_the_index_stays_within_a_shorter_new_list():
    progress = progress_with(5)
    progress.set_index(4)
    progress.store.replace(MISSION, [WAYPOINT] * 2)
    assert progress.index == 1 and progress.current_seq() == 2


def test_start_runs_from_the_first_item_resume_from_the_current_one():
    progress = progress_with(4)
    progress.set_current(3)
    progress.resume()
    assert progress.running and progress.index == 2
    progress.start()
    assert progress.running and progress.index == 0


def test_reset_goes_back_to_the_first_item_without_running():
    progress = progress_with(4)
    progress.set_current(4)
    progress.resume()
    progress.reset()
    assert progress.index == 0 and progress.state is MissionState.NOT_STARTED


def test_pause_only_pauses_a_running_mission():
    progress = progress_with(2)
    progress.pause()
    assert progress.state is MissionState.NOT_STARTED
    progress.resume()
    progress.pause()
    assert progress.state is MissionState.PAUSED


def test_complete_is_announced_once():
    progress = progress_with(2)
    progress.resume()
    assert progress.complete() and progress.state is MissionState.COMPLETE
    assert not progress.complete()


def test_mission_start_restarts_a_completed_mission_and_resumes_a_paused_one():
    progress = progress_with(3)
    progress.set_current(3)
    progress.resume()
    progress.complete()
    progress.prepare_start()
    assert progress.index == 0 and progress.state is MissionState.NOT_STARTED
    progress.set_current(2)
    progress.resume()
    progress.pause()
    progress.prepare_start()
    assert progress.index == 1 and progress.state is MissionState.NOT_STARTED
    progress.resume()
    progress.prepare_start()  # a running mission is left running
    assert progress.running


def test_reached_items_are_reported_once_as_seqs():
    progress = progress_with(3)
    progress.item_reached(0)
    progress.item_reached(2)
    assert progress.reached == [1, 3]
    assert progress.drain_reached() == [1, 3]
    assert progress.drain_reached() == [] and progress.reached == []
