"""The process's exit report (--stats FILE): what ran and what was refused, as JSON.

Written when the loop ends for any reason, so a soak or a CI job can check from outside that every
tick ran, nothing escaped, and how much hostile input was dropped or refused, per vehicle.
"""
from __future__ import annotations

import math
import resource
from pathlib import Path

from .persist import write_json_atomic


def report(runner, nodes, exception: BaseException | None, wall_s: float) -> dict:
    vehicles = []
    for node in nodes:
        v, session, endpoint = node.vehicle, node.session, node.endpoint
        counters = dict(session.counters)
        # the link's decode_errors and parsers_evicted keep the udp_ names they had in the endpoint
        counters.update({f"udp_{k}": n for k, n in (endpoint.totals() | node.link.counters).items()})
        counters["param_sets_refused"] = session.params.refused
        counters["param_save_errors"] = v.params.save_errors
        counters["mission_save_errors"] = v.mission.file.save_errors
        counters["mission_uploads_refused"] = session.missions.refused
        if node.log_files is not None:
            counters["log_write_errors"] = node.log_files.write_errors
        if node.link_faults is not None:
            counters.update({f"link_dropped_{way}": n for way, n in node.link_faults.dropped.items()})
        counters.update({f"signing_{k}": n for k, n in session.signing.counters.items()})
        video = session.camera_component.video if session.camera_component is not None else None
        if video is not None:
            counters.update({"video_rendered": video.frames, "video_skipped": video.schedule.skipped,
                             **{f"video_{k}": n for k, n in video.edge_counters.items()}})
        vehicles.append({
            "system_id": v.system_id, "sim_s": v.time_s, "physics_steps": v.sim.steps,
            "armed": v.armed, "mode": v.mode.number,
            "state_finite": all(math.isfinite(x) for x in v.body),
            "counters": counters, "last_handler_error": session.last_handler_error,
            "internal_errors": v.internal_errors.count, "internal_error_bits": v.internal_errors.bits,
            "last_internal_error": v.internal_errors.last,
        })
    return {"ticks": runner.ticks, "sim_s": runner.sim_time_s, "wall_s": wall_s,
            "exception": None if exception is None else f"{type(exception).__name__}: {exception}",
            "max_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "vehicles": vehicles}


def write(path: Path, runner, nodes, exception: BaseException | None, wall_s: float) -> None:
    write_json_atomic(path, report(runner, nodes, exception, wall_s))
