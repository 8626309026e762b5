"""The Ray backend: each task a Ray task, on a local Ray (`--ray`) or a cluster (`--ray-address`).

Ray is an optional extra (`pip install firefly-sitl[ray]`), imported only here. A task is retried
once by Ray itself, whether its worker died (max_retries) or it raised (retry_exceptions): a task
that fails twice comes back as an error and is recorded as failed. Every node runs the same
`run_task` as the local pool; a flown episode starts its autopilot on the node that runs it.
"""
from __future__ import annotations

import socket

from .spec import CampaignError

ATTEMPTS = 2
WAIT_S = 0.5
REACH_S = 5.0


def check_reachable(address: str) -> None:
    """One line, not a Ray traceback, for an address nobody answers at."""
    if address == "auto":
        return
    host_port = address.removeprefix("ray://")
    host, sep, port = host_port.rpartition(":")
    if not sep or not port.isdigit():
        raise CampaignError(f"--ray-address {address}: expected HOST:PORT (or ray://HOST:PORT, or auto)")
    try:
        socket.create_connection((host, int(port)), timeout=REACH_S).close()
    except OSError as exc:
        raise CampaignError(f"--ray-address {address}: cannot reach it ({exc.strerror or exc})") from None


def start_ray(address: str | None, workers: int | None):
    try:
        import ray
    except ImportError:
        raise CampaignError("--ray: Ray is not installed (pip install 'firefly-sitl[ray]')") from None
    if address:
        check_reachable(address)
    try:
        if address:
            ray.init(address=address, log_to_driver=False, logging_level="ERROR")
        else:
            ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    except Exception as exc:  # noqa: BLE001 - Ray's many ways to fail to start, said in one line
        raise CampaignError(f"{'--ray-address ' + address if address else '--ray'}: Ray did not start: "
                            f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
    return ray


def run_ray(jobs: list, work, on_done, address: str | None = None, workers: int | None = None) -> None:
    """As pool.run_local, on Ray. `attempts` passed to on_done is what Ray allowed when a task
    failed for good, and 1 for a success (Ray does not say whether a success was a retry)."""
    ray = start_ray(address, workers)
    try:
        remote = ray.remote(max_retries=ATTEMPTS - 1, retry_exceptions=True, num_cpus=1)(work)
        pending = {remote.remote(payload): key for key, payload in jobs}
        while pending:
            done, _ = ray.wait(list(pending), num_returns=min(len(pending), 64), timeout=WAIT_S)
            for ref in done:
                key = pending.pop(ref)
                try:
                    value = ray.get(ref)
                except Exception as exc:  # noqa: BLE001 - the task's failure, after Ray's retry
                    on_done(key, False, _one_line(exc), ATTEMPTS)
                else:
                    on_done(key, True, value, 1)
    finally:
        ray.shutdown()


def _one_line(exc: Exception) -> str:
    cause = getattr(exc, "cause", None)  # a RayTaskError carries the task's own exception
    if cause is not None:
        return f"{type(cause).__name__}: {cause}"
    lines = [line for line in str(exc).splitlines() if line.strip()]
    return f"{type(exc).__name__}: {lines[-1] if lines else ''}"
