"""Mission microservice, vehicle side: upload and download of mission, fence and rally lists.

The vehicle drives an upload: it requests each item in turn and re-requests after a quiet spell
(clients do not resend), so a lossy link still completes. Items are checked as they arrive. As
ArduCopter does (measured on its SITL), a mission or rally upload writes as it goes: MISSION_COUNT
shortens the stored list to the count, each valid item is written over the item at its seq or
appended, and an upload refused or abandoned at item k leaves the list as far as it got; a fence
is replaced only when its last item is in (ArduPilot collects a fence before it stores it).
Each list has its own transfer, as in ArduPilot (a fence may be uploaded while a mission is);
while a list is being uploaded, a download of it is DENIED, as ArduPilot's is. Partial writes
are saved when the transfer ends. ArduPilot's convention holds: mission seq 0 is home, and an
upload's seq 0 is not written, except after a clear (AP_Mission::add_cmd then writes home first
and the uploaded seq 0 after it, where seq 1 overwrites it).

Retry timers run on the link clock (`link_s`, wall time at the I/O edge), not on sim time: they
are about packets in flight, which take wall time whatever the speedup.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..mission import FENCE, MISSION, RALLY, MissionItem
from ..mission.commands import downloaded_frame
from ..results import Severity
from .dialect import mavlink as mav
from .mission_checks import GLOBAL_FRAMES, check_item, check_list_item, fence_problem, item_from_message
from .telemetry import mission_current

RETRY_S = 0.4
MAX_RETRIES = 10
MAX_ITEMS = {MISSION: 700, FENCE: 200, RALLY: 50}

def saved_result(saved: bool) -> int:
    """A transfer's MISSION_ACK: ACCEPTED, or MAV_MISSION_ERROR when storage refused the change
    (as ArduPilot answers a failed write; the list flies as received, persist.JsonFile)."""
    return mav.MAV_MISSION_ACCEPTED if saved else mav.MAV_MISSION_ERROR


@dataclass
class Upload:
    kind: int
    count: int  # the last seq asked for + 1
    peer: tuple
    items: list = field(default_factory=list)
    last_request_s: float = 0.0
    retries: int = 0
    first: int = 0  # the first seq asked for (MISSION_WRITE_PARTIAL_LIST's start_index)

    @property
    def next_seq(self) -> int:
        return self.first + len(self.items)


class MissionService:
    def __init__(self, store, vehicle, codec):
        self.store = store
        self.vehicle = vehicle
        self.codec = codec
        self.uploads: dict[int, Upload] = {}  # by list: ArduPilot runs one transfer per list at a time
        self._completed = None  # (peer, kind, last seq) of the upload just stored, to re-ACK a resend
        self.refused = 0  # uploads refused: unsupported list, no space, busy, an invalid item
        self._cleared_at_home_set: int | None = None  # the vehicle's home_sets when the mission was cleared
        # ArduCopter warns once per list (and boot) about each of the two float-coordinate messages.
        self._warned: set[tuple[str, int]] = set()
        self._count_mission(announce=False)

    def _count_mission(self, announce: bool = True) -> None:
        """MIS_TOTAL follows the mission's length, home included, as AP_Mission's count does; each
        change is a PARAM_VALUE to every ground station (AP_Param's set_and_save)."""
        params = self.vehicle.params
        total = len(self.listed(MISSION))
        if params["MIS_TOTAL"] != total:
            params.set("MIS_TOTAL", total, in_range=False, announce=announce)

    # ----- helpers ----------------------------------------------------------------------------
    def _ack(self, peer: tuple, result: int, kind: int):
        return self.codec.mission_ack_encode(peer[0], peer[1], result, kind)

    def _request(self, up: Upload, link_s: float):
        """ArduCopter asks for each item with MISSION_REQUEST (not _INT), whichever way the items
        come; a script that waits for MISSION_REQUEST depends on it."""
        up.last_request_s = link_s
        return self.codec.mission_request_encode(up.peer[0], up.peer[1], up.next_seq, up.kind)

    def _warn_once(self, msg, text: str) -> None:
        key = (msg.get_type(), msg.mission_type)
        if key not in self._warned:
            self._warned.add(key)
            self.vehicle.notify(text, Severity.WARNING)

    def listed(self, kind: int) -> list[MissionItem]:
        """The list as ground stations see it: for the mission, home first as seq 0."""
        items = self.store.items(kind)
        if kind != MISSION:
            return items
        if self._cleared:
            return []  # ArduCopter: a cleared mission has no items, home either, until home is set again
        home = self.vehicle.home or self.vehicle.origin
        home_item = MissionItem(mav.MAV_CMD_NAV_WAYPOINT, mav.MAV_FRAME_GLOBAL, 0, 0, 0, 0,
                                int(round(home.lat_deg * 1e7)), int(round(home.lon_deg * 1e7)), home.alt_m)
        return [home_item] + items

    # ----- upload -----------------------------------------------------------------------------
    def on_count(self, msg, link_s: float) -> list:
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        kind = msg.mission_type
        refusal = None
        if kind not in MAX_ITEMS:
            refusal = mav.MAV_MISSION_UNSUPPORTED
        elif kind in self.uploads and self.uploads[kind].peer != peer:
            refusal = mav.MAV_MISSION_DENIED  # someone else is uploading this list
        elif msg.count > MAX_ITEMS[kind] + (1 if kind == MISSION else 0):
            refusal = mav.MAV_MISSION_NO_SPACE
        if refusal is not None:
            self.refused += 1
            return [self._ack(peer, refusal, kind)]
        if kind in self.uploads:  # the same client starts again: what it wrote stays
            self._end(self.uploads[kind])
        if msg.count == 0:
            saved = self.store.clear(kind)
            if kind == MISSION:  # AP_Mission::truncate(0) leaves no home either, as a clear
                self._cleared_at_home_set = self.vehicle.home_sets
                self._count_mission()
                self.vehicle.notify("Flight plan received")
            return [self._ack(peer, saved_result(saved), kind)]
        self._completed = None
        up = self.uploads[kind] = Upload(kind, msg.count, peer)
        if kind == MISSION:
            if not self._cleared:  # stored items are seq 1.. (home is seq 0)
                self.store.truncate(kind, msg.count - 1)
                self._count_mission()
        elif kind == RALLY:
            self.store.truncate(kind, msg.count)
        return [self._request(up, link_s)]

    @property
    def _cleared(self) -> bool:
        """The mission was cleared (ArduPilot's list then has no home either) and not yet rewritten."""
        return self._cleared_at_home_set == self.vehicle.home_sets

    def _write(self, kind: int, seq: int, item: MissionItem) -> int:
        """Write one item of a mission or rally upload as it arrives, as AP_Mission and AP_Rally do:
        MAV_MISSION_ACCEPTED or ERROR (a seq past the end of the list)."""
        if kind == RALLY:
            index = seq
        elif self._cleared:  # AP_Mission::add_cmd writes home first, then the item after it
            self._cleared_at_home_set = None
            self.store.truncate(kind, 0)
            index = 0
        elif seq == 0:
            return mav.MAV_MISSION_ACCEPTED  # home: AP_Mission::replace_cmd ignores index 0
        else:
            index = seq - 1
        if index > len(self.store.items(kind)):
            return mav.MAV_MISSION_ERROR
        self.store.put(kind, index, item)
        if kind == MISSION:
            self._count_mission()
        return mav.MAV_MISSION_ACCEPTED

    def on_write_partial(self, msg, link_s: float) -> list:
        """MISSION_WRITE_PARTIAL_LIST: rewrite the mission's items start_index..end_index (or
        append at its end), each asked for as an upload's are. As ArduPilot: DENIED while an
        upload runs, MAV_MISSION_ERROR and "Flight plan update rejected" for a range outside the
        list. (Measured for the mission only; other lists are not answered.)"""
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        if msg.mission_type != MISSION:
            return []
        if MISSION in self.uploads:
            return [self._ack(peer, mav.MAV_MISSION_DENIED, MISSION)]
        count = len(self.listed(MISSION))
        if not (0 <= msg.start_index <= count and 0 <= msg.end_index <= count and msg.end_index >= msg.start_index):
            self.vehicle.notify("Flight plan update rejected", Severity.WARNING)
            return [self._ack(peer, mav.MAV_MISSION_ERROR, MISSION)]
        self._completed = None
        up = self.uploads[MISSION] = Upload(MISSION, msg.end_index + 1, peer, first=msg.start_index)
        return [self._request(up, link_s)]

    def _end(self, up: Upload) -> bool:
        """The upload is over, complete or not: what it wrote counts as a change and is saved;
        whether the save worked."""
        del self.uploads[up.kind]
        return self.store.changed() if up.kind != FENCE else True

    def on_item(self, msg, link_s: float) -> list:
        up = self.uploads.get(msg.mission_type)
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        if msg.get_type() == "MISSION_ITEM" and msg.mission_type in MAX_ITEMS:
            self._warn_once(msg, "got MISSION_ITEM; GCS should send MISSION_ITEM_INT")
        if up is None and self._completed == (peer, msg.mission_type, msg.seq):
            # Our ACK was lost and the client resends its last item: tell it again, store nothing.
            return [self._ack(peer, mav.MAV_MISSION_ACCEPTED, msg.mission_type)]
        if up is None or peer != up.peer:
            return []
        if msg.seq != up.next_seq:  # a duplicate or out-of-order item: ask again for the one we need
            return [self._request(up, link_s)] if msg.seq > up.next_seq else []
        item = item_from_message(msg)
        result = check_item(item, up.kind)
        if result == mav.MAV_MISSION_ACCEPTED:
            result = check_list_item(item, up.kind, up.count, len(self.store.items(MISSION)) + 1)
        if result == mav.MAV_MISSION_ACCEPTED and up.kind != FENCE:
            result = self._write(up.kind, msg.seq, item)
        if result != mav.MAV_MISSION_ACCEPTED:  # refused in silence, as ArduCopter refuses
            self._end(up)
            self.refused += 1
            return [self._ack(peer, result, up.kind)]
        up.items.append(item)
        up.retries = 0
        if up.next_seq < up.count:
            return [self._request(up, link_s)]
        saved = self._end(up)
        self._completed = (peer, up.kind, up.count - 1)
        if up.kind == FENCE:
            problem = fence_problem(up.items)
            if problem is not None:  # AC_PolyFence_loader keeps the fence it had
                self.refused += 1
                self.vehicle.notify(problem, Severity.WARNING)
                self.vehicle.notify("Fence validation failed", Severity.WARNING)
                return [self._ack(peer, mav.MAV_MISSION_ERROR, up.kind)]
            saved = self.store.replace(up.kind, up.items)
        if up.kind == MISSION:
            self.vehicle.notify("Flight plan received")
        return [self._ack(peer, saved_result(saved), up.kind)]

    def poll(self, link_s: float) -> list:
        out = []
        for up in list(self.uploads.values()):
            if link_s - up.last_request_s < RETRY_S:
                continue
            up.retries += 1
            if up.retries > MAX_RETRIES:
                self._end(up)
                out.append(self._ack(up.peer, mav.MAV_MISSION_OPERATION_CANCELLED, up.kind))
            else:
                out.append(self._request(up, link_s))
        return out

    # ----- download and the rest ----------------------------------------------------------------
    def _receiving(self, kind: int) -> bool:
        """A list of `kind` is being uploaded: ArduPilot DENIES reading it until the upload ends."""
        return kind in self.uploads

    def on_request_list(self, msg) -> list:
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        if msg.mission_type not in MAX_ITEMS:
            return [self._ack(peer, mav.MAV_MISSION_UNSUPPORTED, msg.mission_type)]
        if self._receiving(msg.mission_type):
            return [self._ack(peer, mav.MAV_MISSION_DENIED, msg.mission_type)]
        return [self.codec.mission_count_encode(peer[0], peer[1], len(self.listed(msg.mission_type)),
                                                msg.mission_type)]

    def on_request(self, msg) -> list:
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        if msg.mission_type not in MAX_ITEMS:
            return [self._ack(peer, mav.MAV_MISSION_UNSUPPORTED, msg.mission_type)]
        if self._receiving(msg.mission_type):
            return [self._ack(peer, mav.MAV_MISSION_DENIED, msg.mission_type)]
        items = self.listed(msg.mission_type)
        if not 0 <= msg.seq < len(items):
            return [self._ack(peer, mav.MAV_MISSION_INVALID_SEQUENCE, msg.mission_type)]
        it = items[msg.seq]
        current = 1 if msg.seq == self.vehicle.mission_progress.current_seq() else 0
        if msg.get_type() == "MISSION_REQUEST":
            self._warn_once(msg, "got MISSION_REQUEST; use MISSION_REQUEST_INT!")
        frame = downloaded_frame(it.command, it.frame) if msg.mission_type == MISSION else it.frame
        if msg.get_type() == "MISSION_REQUEST_INT":
            return [self.codec.mission_item_int_encode(peer[0], peer[1], msg.seq, frame, it.command,
                                                       current, it.autocontinue, it.p1, it.p2, it.p3,
                                                       it.p4, it.x, it.y, it.z, msg.mission_type)]
        scale = 1e-7 if frame in GLOBAL_FRAMES else 1.0
        return [self.codec.mission_item_encode(peer[0], peer[1], msg.seq, frame, it.command, current,
                                               it.autocontinue, it.p1, it.p2, it.p3, it.p4,
                                               it.x * scale, it.y * scale, it.z, msg.mission_type)]

    def on_clear_all(self, msg) -> list:
        peer = (msg.get_srcSystem(), msg.get_srcComponent())
        if msg.mission_type not in MAX_ITEMS:
            return [self._ack(peer, mav.MAV_MISSION_UNSUPPORTED, msg.mission_type)]
        self.uploads.pop(msg.mission_type, None)
        saved = self.store.clear(msg.mission_type)
        if msg.mission_type == MISSION:
            self._cleared_at_home_set = self.vehicle.home_sets
            self._count_mission()
        return [self._ack(peer, saved_result(saved), msg.mission_type)]

    def on_set_current(self, msg) -> list:
        """Accepted: MISSION_CURRENT echoing the seq asked for (ground stations take it as the
        answer, seq 0 included); refused: nothing, as ArduPilot."""
        if self.vehicle.set_mission_current(msg.seq):
            return [mission_current(self.vehicle, self.codec, msg.seq)]
        return []
