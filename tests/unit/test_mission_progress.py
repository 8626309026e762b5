"""Mission progress (mission/progress.py): AP_Mission's rules over a stored list, with a scripted
runner in place of AUTO. Each rule was checked on ArduCopter's SITL (tests/parity/recorded)."""
from __future__ import annotations

from firefly.autopilot.mission import MISSION, MissionItem, MissionStore
from firefly.autopilot.mission.progress import MissionProgress, MissionState

TAKEOFF = MissionItem(22, 3, z=10.0)
WAYPOINT = MissionItem(16, 3, z=10.0)
RTL = MissionItem(20, 3)
SPEED = MissionItem(178, 3, p1=1, p2=4.0)


def jump(seq: int, repeat: int) -> MissionItem:
    return MissionItem(177, 3, p1=seq, p2=repeat)


class Runner:
    """Starts every item; a navigation item is done when the test says so."""

    def __init__(self):
        self.started: list[int] = []
        self.done: set[int] = set()
        self.completed = 0

    def start_command(self, index, item):
        self.started.append(index + 1)
        return True

    def verify_command(self, index, item):
        return item.command > 95 or index + 1 in self.done

    def mission_complete(self):
        self.completed += 1


def progress_with(*items) -> tuple[MissionProgress, Runner, list]:
    store = MissionStore()
    store.replace(MISSION, list(items))
    texts: list[str] = []
    progress = MissionProgress(store, texts.append)
    runner = Runner()
    progress.bind(runner)
    return progress, runner, texts


def finish(progress: MissionProgress, runner: Runner, seq: int) -> None:
    runner.done.add(seq)
    progress.update()


def test_an_empty_mission_reports_seq_0_and_refuses_set_current():
    progress = MissionProgress(MissionStore())
    assert progress.current_seq() == 0
    assert not progress.set_current(1) and not progress.set_current(0)
    assert progress.state is MissionState.NOT_STARTED


def test_start_announces_and_flies_the_first_item():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, RTL)
    progress.start_or_resume(restart=False)
    assert progress.running and progress.current_seq() == 1
    assert texts == ["Mission: 1 Takeoff"] and runner.started == [1]
    finish(progress, runner, 1)
    assert progress.current_seq() == 2 and progress.drain_reached() == [1]
    assert texts[-1] == "Mission: 2 WP"


def test_the_last_item_done_completes_the_mission_once():
    progress, runner, _ = progress_with(TAKEOFF, RTL)
    progress.start()
    finish(progress, runner, 1)
    finish(progress, runner, 2)
    assert progress.state is MissionState.COMPLETE and runner.completed == 1
    assert progress.current_seq() == 2 and progress.drain_reached() == [1, 2]
    progress.update()
    assert runner.completed == 1


def test_stop_keeps_the_item_and_resume_starts_it_again():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, RTL)
    progress.start()
    finish(progress, runner, 1)
    finish(progress, runner, 2)
    progress.stop()
    assert progress.state is MissionState.NOT_STARTED and progress.current_seq() == 3
    progress.start_or_resume(restart=False)
    assert progress.running and progress.current_seq() == 3 and texts[-2:] == ["Mission: 3 WP"] * 2


def test_mis_restart_1_starts_over():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, RTL)
    progress.start()
    finish(progress, runner, 1)
    progress.stop()
    progress.start_or_resume(restart=True)
    assert progress.current_seq() == 1 and texts[-1] == "Mission: 1 Takeoff"


def test_reset_forgets_the_item_but_not_the_state():
    """Disarming resets: a landed vehicle flies a mission again from its first item."""
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, RTL)
    progress.start()
    finish(progress, runner, 1)
    progress.stop()
    progress.reset()
    assert progress.current_seq() == 0 and progress.state is MissionState.NOT_STARTED
    progress.start_or_resume(restart=False)
    assert progress.current_seq() == 1 and texts[-1] == "Mission: 1 Takeoff"


def test_a_running_mission_reset_starts_over_at_the_next_update():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT)
    progress.start()
    finish(progress, runner, 1)
    progress.reset()
    assert progress.running and progress.current_seq() == 0
    progress.update()
    assert progress.current_seq() == 1 and texts[-1] == "Mission: 1 Takeoff"


def test_a_new_list_resumes_at_the_same_index_if_never_reset():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, WAYPOINT, RTL)
    progress.start()
    for seq in (1, 2, 3, 4):
        finish(progress, runner, seq)
    progress.stop()
    progress.store.replace(MISSION, [TAKEOFF, WAYPOINT, WAYPOINT, WAYPOINT, WAYPOINT, RTL])
    progress.resume()
    assert progress.current_seq() == 5 and texts[-1] == "Mission: 5 WP"


def test_a_shorter_new_list_starts_over():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, RTL)
    progress.start()
    for seq in (1, 2, 3):
        finish(progress, runner, seq)
    progress.stop()
    progress.store.replace(MISSION, [TAKEOFF, RTL])
    progress.resume()
    assert progress.current_seq() == 1 and texts[-1] == "Mission: 1 Takeoff"


def test_a_completed_mission_resumes_from_its_first_item():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT)
    progress.start()
    finish(progress, runner, 1)
    finish(progress, runner, 2)
    progress.resume()
    assert progress.running and progress.current_seq() == 1


def test_set_current_when_stopped_only_moves_the_item():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, SPEED, WAYPOINT, RTL)
    assert progress.set_current(4)
    assert progress.state is MissionState.NOT_STARTED and progress.current_seq() == 4
    assert runner.started == [] and texts == []
    assert progress.set_current(3)  # a "do" item: the navigation item after it becomes current
    assert progress.current_seq() == 4
    assert progress.set_current(0) and progress.current_seq() == 1
    assert not progress.set_current(6) and progress.current_seq() == 1
    progress.resume()
    assert progress.running and runner.started == [1]


def test_set_current_when_running_starts_the_item_at_once():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, RTL)
    progress.start()
    assert progress.set_current(3)
    assert progress.running and progress.current_seq() == 3 and texts[-1] == "Mission: 3 WP"
    assert progress.set_current(0) and progress.current_seq() == 1


def test_set_current_in_a_completed_mission_waits_for_a_resume():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT)
    progress.start()
    finish(progress, runner, 1)
    finish(progress, runner, 2)
    assert progress.set_current(2)
    assert progress.state is MissionState.NOT_STARTED and progress.current_seq() == 2
    progress.resume()
    assert progress.current_seq() == 2 and texts[-1] == "Mission: 2 WP"


def test_do_items_start_with_the_next_navigation_item_and_are_reached_in_turn():
    progress, runner, texts = progress_with(TAKEOFF, SPEED, SPEED, WAYPOINT, RTL)
    progress.start()
    finish(progress, runner, 1)
    assert texts[-2:] == ["Mission: 2 ChangeSpeed", "Mission: 4 WP"]
    assert progress.current_seq() == 4 and progress.drain_reached() == [1, 2]
    progress.update()
    assert texts[-1] == "Mission: 3 ChangeSpeed" and progress.drain_reached() == []
    progress.update()
    assert progress.drain_reached() == [3] and progress.current_seq() == 4


def test_do_jump_repeats_with_its_text_and_is_never_current():
    progress, runner, texts = progress_with(TAKEOFF, WAYPOINT, WAYPOINT, jump(2, 2), RTL)
    progress.start()
    flown = []
    for _ in range(7):
        seq = progress.current_seq()
        flown.append(seq)
        runner.done = {seq}
        progress.update()
    assert flown == [1, 2, 3, 2, 3, 2, 3]
    assert progress.current_seq() == 5
    assert [t for t in texts if "Jump" in t] == ["Mission: 4 Jump 1/2", "Mission: 4 Jump 2/2"]


def test_a_loop_of_jumps_only_ends_the_mission():
    progress, runner, _ = progress_with(jump(2, -1), jump(1, -1))
    progress.start()
    assert progress.state is MissionState.COMPLETE and runner.completed == 1


def test_starts_with_takeoff_looks_from_the_current_item_unless_restarting():
    progress, runner, _ = progress_with(WAYPOINT, TAKEOFF, WAYPOINT)
    assert not progress.starts_with_takeoff(restart=False)
    progress.set_current(2)
    assert progress.starts_with_takeoff(restart=False)
    assert not progress.starts_with_takeoff(restart=True)
