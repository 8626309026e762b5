"""The point-by-point fence and rally messages older ground stations send (FENCE_POINT,
FENCE_FETCH_POINT, RALLY_POINT, RALLY_FETCH_POINT), answered as ArduCopter answers them.

ArduPilot still handles them beside the mission protocol, each with one "Received message (...) is
deprecated" per link (said again only when another of these kinds comes between). Rally points are
read and written here in the store's rally list. Of the old fence protocol only the refusals are
served: its counts run on FENCE_TOTAL, which Firefly (like ArduCopter, whose mission-protocol fence
leaves it 0) never sets, so a fence point always answers "index past total" or "bad count" unless a
ground station sets FENCE_TOTAL itself; the upload that would then follow is not emulated.
"""
from __future__ import annotations

from ..c_casts import as_uint16
from ..mission import FENCE, RALLY, MissionItem
from ..results import Severity
from .dialect import mavlink as mav

# The message name ArduPilot's warning names for each kind (it names the fetch for both).
DEPRECATED_AS = {"FENCE_POINT": "FENCE_FETCH_POINT", "FENCE_FETCH_POINT": "FENCE_FETCH_POINT",
                 "RALLY_POINT": "RALLY_FETCH_POINT", "RALLY_FETCH_POINT": "RALLY_FETCH_POINT"}
RALLY_MAX = 50  # the rally points the store holds (MAX_ITEMS in mission_service.py)
OLD_FENCE_MIN_TOTAL = 5  # a return point, a closing point and three vertices


def _latlng_ok(lat_e7: int, lng_e7: int) -> bool:
    return abs(lat_e7) <= 90 * 10**7 and abs(lng_e7) <= 180 * 10**7


class LegacyPoints:
    def __init__(self, store, params, codec):
        self.store = store
        self.params = params
        self.codec = codec
        self._last_warned: dict[object, str] = {}  # link -> the kind its last warning named

    def handle(self, msg, link) -> tuple[list[tuple[int, str]], list]:
        """(texts for the asking link, messages for it)."""
        kind = msg.get_type()
        texts: list[tuple[int, str]] = []
        named = DEPRECATED_AS[kind]
        if self._last_warned.get(link) != named:
            self._last_warned[link] = named
            texts.append((Severity.INFO, f"Received message ({named}) is deprecated"))
        replies: list = []
        if kind == "FENCE_FETCH_POINT":
            texts += self._fence_fetch(msg)
        elif kind == "FENCE_POINT":
            texts += self._fence_point(msg)
        elif kind == "RALLY_FETCH_POINT":
            replies = self._rally_fetch(msg, texts)
        else:
            texts += self._rally_point(msg)
        return texts, replies

    # ----- fence: the refusals of AC_PolyFence_loader's old protocol ---------------------------------
    def _fence_total(self) -> int:
        return int(self.params["FENCE_TOTAL"])

    def _fence_compatible(self) -> bool:
        """Whether the stored fence could be told point by point: one inclusion polygon and a return
        point at most (ArduPilot's contains_compatible_fence)."""
        items = self.store.items(FENCE)
        polygons, i = 0, 0
        while i < len(items):
            item = items[i]
            if item.command == mav.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION:
                polygons += 1
                i += max(1, as_uint16(item.p1) & 0xFF)  # param 1: the polygon's vertex count
            elif item.command == mav.MAV_CMD_NAV_FENCE_RETURN_POINT:
                i += 1
            else:
                return False
        return polygons <= 1

    def _fence_fetch(self, msg) -> list[tuple[int, str]]:
        total = self._fence_total()
        if not self._fence_compatible():
            return [(Severity.WARNING, "Vehicle contains advanced fences")]
        if total != 0 and total < OLD_FENCE_MIN_TOTAL:
            return [(Severity.WARNING, "Invalid FENCE_TOTAL")]
        if msg.idx >= total:
            return [(Severity.WARNING, f"Invalid fence point, index past total({msg.idx} >= {total})")]
        return []  # a point of an old-protocol fence: not emulated (see the module's text)

    def _fence_point(self, msg) -> list[tuple[int, str]]:
        total = self._fence_total()
        if total != 0 and total < OLD_FENCE_MIN_TOTAL:
            return [(Severity.WARNING, "Invalid FENCE_TOTAL")]
        if msg.count != total:
            return [(Severity.WARNING, f"Invalid fence point, bad count ({msg.count} vs {total})")]
        if msg.idx >= total:
            return [(Severity.WARNING, f"Invalid fence point, index past total ({msg.idx} >= {total})")]
        return []

    # ----- rally: AP_Rally's points, one at a time -------------------------------------------------------
    def _rally_fetch(self, msg, texts: list) -> list:
        items = self.store.items(RALLY)
        if msg.idx > len(items):
            texts.append((Severity.WARNING, "Bad rally point ID"))
            return []
        if msg.idx >= len(items):
            texts.append((Severity.WARNING, "Failed to get rally point"))
            return []
        point = items[msg.idx]
        alt = max(-32768, min(32767, int(point.z)))
        return [self.codec.rally_point_encode(msg.get_srcSystem(), msg.get_srcComponent(), msg.idx, len(items),
                                              point.x, point.y, alt, 0, 0, 0)]

    def _rally_point(self, msg) -> list[tuple[int, str]]:
        total = len(self.store.items(RALLY))
        if msg.idx >= total or msg.idx >= RALLY_MAX:
            return [(Severity.WARNING, "Bad rally point ID")]
        if msg.count != total:
            return [(Severity.WARNING, "Bad rally point count")]
        if not _latlng_ok(msg.lat, msg.lng):
            return []  # ArduPilot drops it in silence
        self.store.put(RALLY, msg.idx, MissionItem(mav.MAV_CMD_NAV_RALLY_POINT, mav.MAV_FRAME_GLOBAL_RELATIVE_ALT,
                                                   x=msg.lat, y=msg.lng, z=float(msg.alt)))
        if not self.store.changed():
            return [(Severity.CRITICAL, "Error setting rally point")]
        return []
