"""Probes by area. Each module has AREA and run(target) -> {probe name: Trace}; a module with KIND
covers one kind of ArduCopter's surface (surface/score.py), one probe per entry."""
from . import (adsb, autotune, avoid, camera, commands, flight, flip, follow, ftp, guided, mavsdk_client, mission_companion,
               mission_doitems, mission_navgeo, mission_plans, mission_resume, mission_terrain, mission_wpyaw,
               mission_navtime, missions, modes, mount, nav_flight,
               offboard, params, payload_outputs, pilot, precland, rangefinder, refusals, startup, surface_commands,
               surface_messages, surface_mission,
               surface_modes, surface_sim_faults, takeoff, telemetry, throw, wind, proximity, extnav, prearm, oa, oa_bendy,
               motor_test, relays, misc_commands, winch, flow, ekf_flags, ekf_variances, prearm_health, terrain, terrain_modes)

AREAS = {m.AREA: m for m in (commands, modes, telemetry, flight, missions, mavsdk_client, params, ftp, startup,
                             refusals, surface_commands, surface_modes, surface_messages, surface_mission,
                             surface_sim_faults, flip, nav_flight, guided, offboard, pilot, follow, autotune, throw,
                             mission_navgeo, mission_doitems, mission_navtime, mission_companion, mission_resume,
                             mission_plans, camera, mission_wpyaw, mission_terrain, takeoff, wind, rangefinder, adsb, precland, avoid, proximity, extnav,
                             prearm, oa, oa_bendy, payload_outputs, motor_test, relays, misc_commands, mount,
                             winch, flow, ekf_flags, ekf_variances, prearm_health, terrain, terrain_modes)}
