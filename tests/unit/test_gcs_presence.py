"""What tells the vehicle its ground station is there (ArduPilot's sysid_mygcs_seen, which holds off
the GCS failsafe): its heartbeat, and the pilot input it sends, MANUAL_CONTROL and
RC_CHANNELS_OVERRIDE; input another system sends is not heard and counts for nothing."""
from __future__ import annotations

import pytest

from firefly.autopilot.mavlink.dialect import new_codec
from firefly.autopilot.mavlink.session import Session

from ._util import ready_vehicle, wire


@pytest.mark.parametrize("sender, counts", [(255, True), (245, False)])
@pytest.mark.parametrize("kind", ["MANUAL_CONTROL", "RC_CHANNELS_OVERRIDE"])
def test_pilot_input_from_the_ground_station_counts_as_its_heartbeat(kind, sender, counts):
    vehicle = ready_vehicle()
    session = Session(vehicle, new_codec(1))
    codec = new_codec(sender, 190)
    msg = (codec.manual_control_encode(1, 0, 0, 500, 0, 0) if kind == "MANUAL_CONTROL"
           else codec.rc_channels_override_encode(1, 1, *([1500] * 8)))
    assert session.gcs_last_heartbeat_s is None
    session.receive(wire(msg, codec), vehicle.time_s, 7.0)
    assert session.gcs_last_heartbeat_s == (7.0 if counts else None)
