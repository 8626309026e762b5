"""The local backend: worker processes of this machine, one task at a time each.

Each worker holds one task at a time, so when a worker dies (killed, out of memory) the task it
held is known exactly: it is given again to a fresh worker, and a task that has failed twice, by
an exception or by the death of its worker, is recorded as failed with its error. The rest of the
campaign goes on. Ctrl-C stops the workers at once; what has finished is already recorded.
"""
from __future__ import annotations

import multiprocessing
import signal
import traceback
from collections import deque
from multiprocessing.connection import wait

ATTEMPTS = 2


def _worker(conn, work) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    while True:
        job = conn.recv()
        if job is None:
            return
        key, payload = job
        try:
            conn.send((key, True, work(payload)))
        except Exception as exc:  # noqa: BLE001 - any failure of the task is the task's outcome
            where = traceback.extract_tb(exc.__traceback__)[-1]
            conn.send((key, False, f"{type(exc).__name__}: {exc} ({where.filename.rsplit('/', 1)[-1]}:{where.lineno})"))


class _Worker:
    def __init__(self, ctx, work):
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_worker, args=(child, work), daemon=True)
        self.process.start()
        child.close()
        self.job = None  # (key, payload) held

    def give(self, job) -> bool:
        """Hand over `job`; False if the worker had died while idle (it then holds nothing)."""
        try:
            self.conn.send(job)
        except (BrokenPipeError, OSError):
            return False
        self.job = job
        return True

    def stop(self) -> None:
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.conn.close()


def run_local(jobs: list, work, on_done, workers: int) -> None:
    """Run work(payload) for each (key, payload) of `jobs` on `workers` processes; on_done(key,
    ok, value_or_error, attempts) as each finishes or fails for good."""
    ctx = multiprocessing.get_context("fork")
    queue = deque(jobs)
    attempts: dict = {}
    pool = [_Worker(ctx, work) for _ in range(min(workers, len(jobs)) or 1)]

    def failed(job, error: str) -> None:
        key = job[0]
        attempts[key] = attempts.get(key, 0) + 1
        if attempts[key] < ATTEMPTS:
            queue.appendleft(job)  # again, next
        else:
            on_done(key, False, error, attempts[key])

    try:
        while queue or any(w.job for w in pool):
            for i, w in enumerate(pool):
                if w.job is not None or not queue:
                    continue
                job = queue.popleft()
                if not w.give(job):  # it died idle: nothing of its to run again, a fresh one takes the job
                    w.stop()
                    pool[i] = w = _Worker(ctx, work)
                    if not w.give(job):
                        raise RuntimeError("a fresh worker process could not take a task")
            busy = [w for w in pool if w.job is not None]
            ready = wait([w.conn for w in busy] + [w.process.sentinel for w in busy])
            for i, w in enumerate(pool):
                if w.job is None:
                    continue
                if w.conn in ready:
                    try:
                        key, ok, value = w.conn.recv()
                    except (EOFError, OSError):
                        ok = None  # died while answering: handled below as a death
                    else:
                        job, w.job = w.job, None
                        if ok:
                            on_done(key, True, value, attempts.get(key, 0) + 1)
                        else:
                            failed(job, value)
                        continue
                if w.process.sentinel in ready or not w.process.is_alive():
                    job = w.job
                    w.process.join()
                    code = w.process.exitcode
                    w.stop()
                    pool[i] = _Worker(ctx, work)
                    failed(job, f"the worker running it died (exit code {code})")
        for w in pool:
            w.give(None)  # the end; a worker that died idle since its last result has nothing to lose
    finally:
        for w in pool:
            w.stop()
