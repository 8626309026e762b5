"""The mission protocol over a lossy in-memory link: a scripted ground station against the
vehicle's sans-IO session. Uploads and downloads complete despite loss or fail cleanly, and a
failed upload leaves the mission as far as it got, as ArduCopter's does (measured on its SITL:
tests/parity/probes/missions.py)."""
from __future__ import annotations

import math
import random

import pytest

from firefly.autopilot.results import Result

from firefly.autopilot.mavlink.dialect import mavlink as mav
from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session
from firefly.autopilot.mission import MissionItem, MissionStore
from firefly.autopilot.results import Result
from firefly.autopilot.vehicle import Vehicle, VehicleConfig

from ._util import wire

TICK_S = 0.05  # link-clock step between exchanges
CLIENT_RETRY_S = 1.0


class LossyLink:
    """Carries packed frames both ways, dropping each with probability `loss` (seeded)."""

    def __init__(self, loss: float, seed: int):
        self.rng = random.Random(seed)
        self.loss = loss
        self.cut_after = None  # drop everything once this many frames have crossed
        self.crossed = 0
        self.decoders = {}
        self.delivered = []  # (direction, message) of everything that got through

    def carry(self, msgs, codec, direction: str) -> list:
        out = []
        decoder = self.decoders.setdefault(direction, new_codec(1 if direction == "up" else 255))
        for msg in msgs:
            self.crossed += 1
            if (self.cut_after is not None and self.crossed > self.cut_after) or self.rng.random() < self.loss:
                continue
            out.extend(m for m in decoder.parse_buffer(msg.pack(codec)) or [])
        self.delivered += [(direction, m) for m in out]
        return out


class GroundStation:
    """Minimal mission client: resends what it is waiting on after CLIENT_RETRY_S of silence."""

    def __init__(self):
        self.codec = new_codec(255, 190)
        self.outbox = []
        self.done = None
        self.items = []
        self.downloaded = {}
        self.expected = None
        self.last_sent_s = 0.0
        self.retry = None

    def send(self, msg, now, retry=True):
        self.outbox.append(msg)
        self.last_sent_s = now
        self.retry = msg if retry else None

    def start_upload(self, items, now):
        self.items = items
        self.send(self.codec.mission_count_encode(1, 1, len(items), 0), now)

    def start_download(self, now):
        self.send(self.codec.mission_request_list_encode(1, 1, 0), now)

    def on(self, msg, now):
        t = msg.get_type()
        if t == "MISSION_REQUEST" and msg.seq < len(self.items):  # ArduCopter asks with MISSION_REQUEST
            # The last item is resent until the ACK arrives (MAVSDK's upload does the same).
            self.send(self.items[msg.seq], now, retry=msg.seq == len(self.items) - 1)
        elif t == "MISSION_ACK":
            self.done = msg.type
            self.retry = None
        elif t == "MISSION_COUNT":
            self.expected = msg.count
            self._request_next(now)
        elif t == "MISSION_ITEM_INT" and self.expected is not None:
            self.downloaded[msg.seq] = msg
            self._request_next(now)

    def _request_next(self, now):
        missing = [s for s in range(self.expected) if s not in self.downloaded]
        if missing:
            self.send(self.codec.mission_request_int_encode(1, 1, missing[0], 0), now)
        else:
            self.send(self.codec.mission_ack_encode(1, 1, 0, 0), now, retry=False)
            self.done = 0

    def poll(self, now):
        if self.retry is not None and now - self.last_sent_s >= CLIENT_RETRY_S:
            self.send(self.retry, now)


def item(seq, command=16, lat=-35.36, lon=149.16, alt=10.0, frame=mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT):
    return mav.MAVLink_mission_item_int_message(1, 1, seq, frame, command, 0, 1, 0, 0, 0, 0,
                                                int(lat * 1e7), int(lon * 1e7), alt, 0)


def plan(n, lat0=-35.36):
    return [item(0)] + [item(k, lat=lat0 + k * 1e-4) for k in range(1, n)]


def run(session, gcs, link, max_s=120.0):
    now = 0.0
    while gcs.done is None and now < max_s:
        now += TICK_S
        for msg in link.carry(gcs.outbox, gcs.codec, "up"):
            replies = session.receive(msg, 0.0, now)
            for reply in link.carry(replies, session.codec, "down"):
                gcs.on(reply, now)
        gcs.outbox = []
        for reply in link.carry(session.poll(0.0, now), session.codec, "down"):
            if reply.get_type().startswith("MISSION"):
                gcs.on(reply, now)
        gcs.poll(now)
    return now


def stored_lats(vehicle):
    return [i.x for i in vehicle.mission.items(0)]


@pytest.fixture
def setup():
    v = Vehicle(VehicleConfig())
    return v, Session(v, new_codec(1))


@pytest.mark.parametrize("seed", range(8))
def test_upload_completes_over_a_lossy_link(setup, seed):
    v, session = setup
    gcs = GroundStation()
    items = plan(12)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.25, seed))
    assert gcs.done == mav.MAV_MISSION_ACCEPTED
    assert stored_lats(v) == [i.x for i in items[1:]]  # seq 0 is home and is not stored


@pytest.mark.parametrize("seed", range(3))
def test_download_completes_over_a_lossy_link(setup, seed):
    v, session = setup
    v.mission.replace(0, [MissionItem(16, 6, x=-353600000 + k, y=1491600000, z=10.0 + k) for k in range(8)])
    gcs = GroundStation()
    gcs.start_download(0.0)
    run(session, gcs, LossyLink(0.25, seed))
    assert gcs.done == 0 and gcs.expected == 9
    assert [gcs.downloaded[s].x for s in range(1, 9)] == [-353600000 + k for k in range(8)]
    assert gcs.downloaded[0].command == mav.MAV_CMD_NAV_WAYPOINT  # home


def test_a_download_keeps_the_frame_only_of_items_stored_with_a_location(setup):
    """AP_Mission keeps a frame only in a Location: measured on ArduCopter, an RTL uploaded in
    GLOBAL_RELATIVE_ALT (as DroneKit's scripts send it) downloads in frame 0, a waypoint in its own."""
    v, session = setup
    relative = mav.MAV_FRAME_GLOBAL_RELATIVE_ALT
    v.mission.replace(0, [MissionItem(16, relative, x=-353600000, y=1491600000, z=10.0),
                          MissionItem(20, relative), MissionItem(178, relative, p2=5.0)])
    gcs = GroundStation()
    gcs.start_download(0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert [gcs.downloaded[s].frame for s in (1, 2, 3)] == [relative, mav.MAV_FRAME_GLOBAL, mav.MAV_FRAME_GLOBAL]


@pytest.mark.parametrize("cut_after", [3, 8, 15, 40])
def test_an_interrupted_upload_leaves_the_mission_as_far_as_it_got(setup, cut_after):
    """The items that got through before the link died are written over the old ones; the old
    ones after them stay."""
    v, session = setup
    first = GroundStation()
    first.start_upload(plan(5, lat0=-35.0), 0.0)
    run(session, first, LossyLink(0.0, 0))
    before = stored_lats(v)
    assert len(before) == 4
    second = GroundStation()
    new = plan(20, lat0=-36.0)
    second.start_upload(new, 0.0)
    link = LossyLink(0.0, 0)
    link.cut_after = cut_after
    run(session, second, link, max_s=30.0)
    written = len({m.seq for direction, m in link.delivered
                   if direction == "up" and m.get_type() == "MISSION_ITEM_INT" and m.seq > 0})
    assert written == {3: 0, 8: 1, 15: 3, 40: 12}[cut_after]  # none, one, three or all four of the old ones replaced
    assert stored_lats(v) == [i.x for i in new[1:1 + written]] + before[written:]
    assert not session.missions.uploads, "the vehicle gave up on the dead transfer"


def test_an_invalid_item_refuses_the_upload_and_keeps_what_came_before_it(setup):
    """MISSION_COUNT shortens the list to its count, item 1 is written, item 2 is refused: the
    old items 2 and 3 stay."""
    v, session = setup
    good = GroundStation()
    good.start_upload(plan(6), 0.0)
    run(session, good, LossyLink(0.0, 0))
    before = stored_lats(v)
    bad = GroundStation()
    items = plan(4, lat0=-36.0)
    items[2] = item(2, lat=95.0)
    bad.start_upload(items, 0.0)
    run(session, bad, LossyLink(0.0, 0))
    assert bad.done == mav.MAV_MISSION_INVALID_PARAM5_X
    assert stored_lats(v) == [items[1].x] + before[1:3]


@pytest.mark.parametrize("command, accepted", [(mav.MAV_CMD_DO_CHANGE_SPEED, True), (mav.MAV_CMD_NAV_WAYPOINT, False)])
def test_nan_altitude_is_refused_only_where_it_is_an_altitude(setup, command, accepted):
    """MAVSDK's mission plugin sends DO_CHANGE_SPEED with z = NaN; ArduCopter stores it."""
    v, session = setup
    gcs = GroundStation()
    items = plan(3)
    items[2] = item(2, command=command, alt=float("nan"), frame=mav.MAV_FRAME_MISSION if accepted else
                    mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == (mav.MAV_MISSION_ACCEPTED if accepted else mav.MAV_MISSION_INVALID_PARAM7)
    assert len(v.mission.items(0)) == (2 if accepted else 1)  # refused: item 1 was written


def test_a_cleared_mission_lists_nothing_until_home_is_set_again(setup):
    """ArduCopter: MISSION_CLEAR_ALL leaves no items, home included (MISSION_COUNT 0), until home
    is written again; a fresh vehicle lists its home item."""
    v, session = setup

    def listed() -> int:
        gcs = GroundStation()
        gcs.start_download(0.0)
        run(session, gcs, LossyLink(0.0, 0))
        return gcs.expected

    assert listed() == 1
    gcs = GroundStation()
    gcs.start_upload(plan(3), 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert listed() == 3
    session.receive(gcs.codec.mission_clear_all_encode(1, 1, 0), 0.0, 0.0)
    assert listed() == 0
    assert v.set_home(None) == Result.ACCEPTED
    assert listed() == 1


@pytest.mark.parametrize("frame", [mav.MAV_FRAME_BODY_FRD, mav.MAV_FRAME_LOCAL_NED])
def test_bad_frame_is_refused(setup, frame):
    """A waypoint can only be a latitude/longitude: ArduCopter refuses a local NED one too."""
    v, session = setup
    gcs = GroundStation()
    items = plan(3)
    items[1] = item(1, frame=frame)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == mav.MAV_MISSION_UNSUPPORTED_FRAME
    assert v.mission.items(0) == []


def test_an_item_without_a_position_may_come_in_a_local_frame(setup):
    v, session = setup
    gcs = GroundStation()
    items = plan(3)
    items[2] = item(2, command=mav.MAV_CMD_DO_CHANGE_SPEED, lat=0.0, lon=0.0, alt=0.0, frame=mav.MAV_FRAME_LOCAL_NED)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == mav.MAV_MISSION_ACCEPTED
    assert [i.command for i in v.mission.items(0)] == [mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_CMD_DO_CHANGE_SPEED]


def test_fence_and_rally_lists_are_separate(setup):
    v, session = setup
    for kind, count in ((1, 4), (2, 2)):
        gcs = GroundStation()
        items = [mav.MAVLink_mission_item_int_message(1, 1, s, mav.MAV_FRAME_GLOBAL_INT,
                                                      5001 if kind == 1 else 5100, 0, 1, 4, 0, 0, 0,
                                                      int((-35.36 + s * 1e-4) * 1e7), 1491600000, 0, kind)
                 for s in range(count)]
        gcs.items = items
        gcs.send(gcs.codec.mission_count_encode(1, 1, count, kind), 0.0)
        run(session, gcs, LossyLink(0.0, 0))
        assert gcs.done == 0
    assert len(v.mission.items(1)) == 4 and len(v.mission.items(2)) == 2 and v.mission.items(0) == []


def test_a_refused_rally_upload_keeps_what_came_before_it_and_a_refused_fence_nothing(setup):
    """Rally points are written as they arrive, like mission items; a fence is collected and
    stored only when complete (ArduPilot's fence protocol keeps the old fence on a failure)."""
    v, session = setup

    def upload(kind: int, count: int, lat0: float, bad_seq: int | None = None) -> int:
        gcs = GroundStation()
        command = 5001 if kind == 1 else 5100  # a polygon vertex, a rally point
        gcs.items = [mav.MAVLink_mission_item_int_message(
            1, 1, s, mav.MAV_FRAME_GLOBAL_INT, mav.MAV_CMD_NAV_WAYPOINT if s == bad_seq else command, 0, 1, 4,
            0, 0, 0, int((lat0 + s * 1e-4) * 1e7), 1491600000, 0, kind) for s in range(count)]
        gcs.send(gcs.codec.mission_count_encode(1, 1, count, kind), 0.0)
        run(session, gcs, LossyLink(0.0, 0))
        return gcs.done

    for kind in (1, 2):
        assert upload(kind, 4, -35.0) == mav.MAV_MISSION_ACCEPTED
    old = {kind: [i.x for i in v.mission.items(kind)] for kind in (1, 2)}
    for kind in (1, 2):
        assert upload(kind, 3, -36.0, bad_seq=2) == mav.MAV_MISSION_UNSUPPORTED  # a waypoint in either
    assert [i.x for i in v.mission.items(1)] == old[1]
    new = [int((-36.0 + s * 1e-4) * 1e7) for s in range(2)]
    assert [i.x for i in v.mission.items(2)] == new + old[2][2:3]  # shortened to 3, then 0 and 1 written


def test_clear_all(setup):
    v, session = setup
    v.mission.replace(0, [MissionItem(16, 6, x=1, y=1, z=5)])
    codec = new_codec(255, 190)
    decoder = new_codec(1)
    msg = decoder.parse_buffer(codec.mission_clear_all_encode(1, 1, 0).pack(codec))[0]
    replies = session.receive(msg, 0.0, 0.0)
    assert [r.get_type() for r in replies] == ["MISSION_ACK"] and replies[0].type == 0
    assert v.mission.items(0) == []


def test_a_resent_last_item_after_a_lost_ack_is_acked_again_and_stored_once(setup):
    v, session = setup
    gcs = GroundStation()
    items = plan(4)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == mav.MAV_MISSION_ACCEPTED
    version = v.mission.version
    again = session.receive(new_codec(0, 0).parse_buffer(items[-1].pack(gcs.codec))[0], 0.0, 1.0)
    assert [(m.get_type(), m.type) for m in again] == [("MISSION_ACK", mav.MAV_MISSION_ACCEPTED)]
    assert v.mission.version == version  # nothing stored twice
    other = session.receive(new_codec(0, 0).parse_buffer(items[1].pack(gcs.codec))[0], 0.0, 1.0)
    assert other == []  # only the last item is answered


def test_a_list_being_uploaded_cannot_be_downloaded_until_the_upload_ends(setup):
    """ArduPilot DENIES MISSION_REQUEST_LIST and MISSION_REQUEST_INT of a list it is receiving."""
    v, session = setup
    gcs = GroundStation()
    session.receive(gcs.codec.mission_count_encode(1, 1, 3, 0), 0.0, 0.0)
    for ask in (gcs.codec.mission_request_list_encode(1, 1, 0), gcs.codec.mission_request_int_encode(1, 1, 0, 0)):
        replies = session.receive(ask, 0.0, 0.0)
        assert [(r.get_type(), r.type) for r in replies] == [("MISSION_ACK", mav.MAV_MISSION_DENIED)]
    rally = session.receive(gcs.codec.mission_request_list_encode(1, 1, 2), 0.0, 0.0)
    assert [r.get_type() for r in rally] == ["MISSION_COUNT"]  # another list is read as ever


@pytest.mark.parametrize("kind, command, frame, p1, z, result", [
    (1, mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, mav.MAV_FRAME_GLOBAL_INT, 100, 0, mav.MAV_MISSION_ACCEPTED),
    (1, mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, mav.MAV_FRAME_MISSION, 100, 0, mav.MAV_MISSION_UNSUPPORTED_FRAME),
    (1, mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_INT, 0, 0, mav.MAV_MISSION_UNSUPPORTED),
    (1, mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, mav.MAV_FRAME_GLOBAL_INT, 300, 0, mav.MAV_MISSION_INVALID_PARAM1),
    (2, mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 40, mav.MAV_MISSION_ACCEPTED),
    (2, mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 40, mav.MAV_MISSION_UNSUPPORTED),
    (2, mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0, 40_000, mav.MAV_MISSION_INVALID_PARAM7),
    (2, mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_LOCAL_NED, 0, 40, mav.MAV_MISSION_UNSUPPORTED_FRAME),
])
def test_fence_and_rally_items_are_checked_as_their_own_lists_check_them(setup, kind, command, frame, p1, z, result):
    """ArduPilot's fence and rally protocols convert items by their own rules (the fence's frame
    first, then its command; the rally's command, position and altitude, then its frame)."""
    v, session = setup
    gcs = GroundStation()
    gcs.items = [mav.MAVLink_mission_item_int_message(1, 1, 0, frame, command, 0, 1, p1, 0, 0, 0,
                                                      -353600000, 1491600000, z, kind)]
    gcs.send(gcs.codec.mission_count_encode(1, 1, 1, kind), 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == result


def test_a_fence_uploads_while_a_mission_upload_is_under_way(setup):
    """Each list has its own transfer, as ArduPilot's: a fence uploaded in the middle of a mission
    upload leaves the mission upload going on."""
    v, session = setup
    gcs = GroundStation()
    mission = plan(3)
    requests = session.receive(gcs.codec.mission_count_encode(1, 1, 3, 0), 0.0, 0.0)
    assert [(r.get_type(), r.seq, r.mission_type) for r in requests] == [("MISSION_REQUEST", 0, 0)]
    requests = session.receive(mission[0], 0.0, 0.0)
    fence = GroundStation()
    fence.items = [mav.MAVLink_mission_item_int_message(1, 1, 0, mav.MAV_FRAME_GLOBAL_INT,
                                                        mav.MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 1, 100, 0, 0, 0,
                                                        -353600000, 1491600000, 0, 1)]
    fence.send(fence.codec.mission_count_encode(1, 1, 1, 1), 0.0)
    run(session, fence, LossyLink(0.0, 0))
    assert fence.done == mav.MAV_MISSION_ACCEPTED and len(v.mission.items(1)) == 1
    for item in mission[1:]:  # the mission's transfer goes on where it was
        assert [(r.get_type(), r.seq) for r in requests] == [("MISSION_REQUEST", item.seq)]
        requests = session.receive(item, 0.0, 0.0)
    assert [(r.get_type(), r.type) for r in requests] == [("MISSION_ACK", mav.MAV_MISSION_ACCEPTED)]
    assert stored_lats(v) == [i.x for i in mission[1:]]


def test_a_refusing_disk_answers_mission_error_and_the_list_still_flies(tmp_path):
    """Storage that refuses the save (its directory replaced by a file): counted, answered with
    MAV_MISSION_ERROR as ArduPilot answers a failed write, and the vehicle keeps the list."""
    gone = tmp_path / "gone"
    gone.mkdir()
    v = Vehicle(VehicleConfig(), mission=MissionStore(gone / "missions.json"))
    session = Session(v, new_codec(1))
    gone.rmdir()
    gone.write_text("a file where the state directory was")
    gcs = GroundStation()
    items = plan(4)
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == mav.MAV_MISSION_ERROR
    assert stored_lats(v) == [i.x for i in items[1:]]
    assert v.mission.file.save_errors >= 1 and "missions.json" in v.mission.file.last_save_error


@pytest.mark.parametrize("command, params, result", [
    (mav.MAV_CMD_DO_JUMP, (math.nan, math.nan, 0, 0), mav.MAV_MISSION_INVALID_PARAM1),
    (mav.MAV_CMD_DO_JUMP, (2, math.nan, 0, 0), mav.MAV_MISSION_INVALID_PARAM2),
    (mav.MAV_CMD_NAV_WAYPOINT, (0, 0, 0, math.nan), mav.MAV_MISSION_ACCEPTED),  # NaN yaw: unchanged
    (mav.MAV_CMD_NAV_LOITER_TIME, (5, 0, 0, math.nan), mav.MAV_MISSION_INVALID_PARAM4),
    (0, (0, 0, 0, 0), mav.MAV_MISSION_INVALID),  # reserved command ids
    (1, (0, 0, 0, 0), mav.MAV_MISSION_INVALID),
])
def test_nan_params_are_refused_where_ap_mission_refuses_them(setup, command, params, result):
    v, session = setup
    items = plan(2)
    items.append(mav.MAVLink_mission_item_int_message(1, 1, 2, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, command,
                                                      0, 1, *params, int(-35.36 * 1e7), int(149.16 * 1e7), 10.0, 0))
    gcs = GroundStation()
    gcs.start_upload(items, 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    assert gcs.done == result


def test_float_coordinate_messages_are_served_with_arducopters_one_warning_each(setup):
    """MISSION_ITEM and MISSION_REQUEST still work; ArduCopter warns once about each (per list)."""
    v, session = setup
    codec = GroundStation().codec
    first = plan(1)[0]
    item = mav.MAVLink_mission_item_message(1, 1, 1, first.frame, first.command, 0, 1, 0, 0, 0, 0,
                                            first.x * 1e-7, first.y * 1e-7, first.z, 0)
    for _ in range(2):
        assert [r.get_type() for r in session.receive(codec.mission_count_encode(1, 1, 2, 0), 0.0, 0.0)] \
            == ["MISSION_REQUEST"]
        session.receive(plan(1)[0], 0.0, 0.0)  # item 0 (home's place) as MISSION_ITEM_INT
        replies = session.receive(item, 0.0, 0.0)
        assert [(r.get_type(), r.type) for r in replies] == [("MISSION_ACK", mav.MAV_MISSION_ACCEPTED)]
        assert [r.get_type() for r in session.receive(codec.mission_request_encode(1, 1, 1, 0), 0.0, 0.0)] \
            == ["MISSION_ITEM"]
    said = [text for _, text in v.events]
    assert said.count("got MISSION_ITEM; GCS should send MISSION_ITEM_INT") == 1
    assert said.count("got MISSION_REQUEST; use MISSION_REQUEST_INT!") == 1


def test_a_partial_write_rewrites_only_the_items_asked_for(setup):
    v, session = setup
    gcs = GroundStation()
    gcs.start_upload(plan(4), 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    before = stored_lats(v)
    partial = gcs.codec.mission_write_partial_list_encode(1, 1, 2, 2, 0)
    asked = session.receive(wire(partial, gcs.codec), 0.0, 1.0)
    assert [(m.get_type(), m.seq) for m in asked] == [("MISSION_REQUEST", 2)]
    replies = session.receive(wire(item(2, lat=-35.0), gcs.codec), 0.0, 1.1)
    assert [(m.get_type(), m.type) for m in replies] == [("MISSION_ACK", mav.MAV_MISSION_ACCEPTED)]
    after = stored_lats(v)
    assert after[1] == int(-35.0 * 1e7) != before[1]  # seq 2 is stored item 1 (seq 0 is home)
    assert after[0] == before[0] and after[2] == before[2] and len(after) == len(before)


@pytest.mark.parametrize("start, end", [(5, 5), (2, 1), (-1, 2), (0, 9)])
def test_a_partial_write_outside_the_list_is_rejected_and_changes_nothing(setup, start, end):
    v, session = setup
    gcs = GroundStation()
    gcs.start_upload(plan(3), 0.0)
    run(session, gcs, LossyLink(0.0, 0))
    before = stored_lats(v)
    v.drain_events()
    partial = gcs.codec.mission_write_partial_list_encode(1, 1, start, end, 0)
    replies = session.receive(wire(partial, gcs.codec), 0.0, 1.0)
    assert [(m.get_type(), m.type) for m in replies] == [("MISSION_ACK", mav.MAV_MISSION_ERROR)]
    assert stored_lats(v) == before and not session.missions.uploads
    assert "Flight plan update rejected" in [text for _, text in v.drain_events()]


def test_mis_total_counts_the_mission_with_home_and_each_change_is_announced(setup):
    v, session = setup
    assert v.params["MIS_TOTAL"] == 1  # home alone
    gcs, link = GroundStation(), LossyLink(0.0, 0)
    gcs.start_upload(plan(4), 0.0)
    run(session, gcs, link)
    assert v.params["MIS_TOTAL"] == 4
    # to every link (sets of one name between two takes coalesce into the last value)
    assert [(m.param_id, m.param_value) for _, m in session.take_announced()] == [("MIS_TOTAL", 4.0)]
    clear = gcs.codec.mission_clear_all_encode(1, 1, 0)
    session.receive(wire(clear, gcs.codec), 0.0, 3.0)
    assert v.params["MIS_TOTAL"] == 0  # a cleared mission has no home either (AP_Mission::truncate(0))
    session.poll(0.0, 3.1)
    assert [(m.param_id, m.param_value) for _, m in session.take_announced()] == [("MIS_TOTAL", 0.0)]
