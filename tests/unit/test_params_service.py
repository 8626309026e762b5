"""The parameter list stream under repeated requests: one stream for the link, at its own pace,
however many PARAM_REQUEST_LISTs arrive (as ArduPilot streams one list per link)."""
from __future__ import annotations

from firefly.autopilot.mavlink.params_service import LIST_BURST, LIST_RATE_PER_S

from ._session_link import SYSTEM_ID, gcs, link  # noqa: F401 - link is a fixture
from ._util import of_type, wire


def _request_list(link, now: float) -> list:
    return of_type(link.send(wire(gcs().param_request_list_encode(SYSTEM_ID, 1)), now), "PARAM_VALUE")


def test_a_flood_of_list_requests_gets_no_more_than_one_request(link):
    sent = [m for _ in range(2000) for m in _request_list(link, 50.0)]  # two thousand in one instant
    assert len(sent) == LIST_BURST
    # a tenth of a second later, the stream has sent what its pace allows, not a burst per request
    later = [m for _ in range(2000) for m in _request_list(link, 50.1)]
    assert len(later) <= min(LIST_BURST, LIST_RATE_PER_S * 0.1)


def test_a_new_request_restarts_the_list_from_the_first_parameter_at_the_same_pace(link):
    first = _request_list(link, 10.0)
    assert [m.param_index for m in first] == list(range(LIST_BURST))
    assert of_type(link.poll(10.01), "PARAM_VALUE")[0].param_index == LIST_BURST  # the stream goes on
    again = _request_list(link, 10.02)  # restarted: from index 0, only what 10 ms allow
    assert again and again[0].param_index == 0 and len(again) <= LIST_RATE_PER_S * 0.01 + 1


def test_after_a_quiet_spell_a_request_is_answered_with_a_burst_at_once(link):
    assert len(_request_list(link, 10.0)) == LIST_BURST
    assert _request_list(link, 10.0) == []  # the allowance is spent ...
    assert len(_request_list(link, 20.0)) == LIST_BURST  # ... and full again ten seconds later
