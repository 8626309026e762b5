"""The state-space walk as a long run: a seeded random walk over the sans-IO vehicle and session
(state_machine.py's actions and invariants), episode after episode, each from a fresh vehicle
(realistic start-up mostly, instant sometimes, now and then with a camera). A failure ends its episode; the walk goes on with
the next, counting each distinct failure and keeping its first reproductions, shrunk.

    python -m tests.fuzz.state_walk --steps 1000000 --seed 1 --json out/state_walk.json

Progress goes to stderr every few seconds; the figures (steps, messages sent by type, states
visited with counts, commands acknowledged, failures with reproductions) to stdout and --json.
The exit status is 1 when the walk found any failure.
"""
from __future__ import annotations

import argparse
import json
import random
import sys
import time
from collections import Counter
from pathlib import Path

from .state_machine import ACTIONS, START_AT_S, Walk, WalkFailure, render, shrink

EPISODE_STEPS = (20, 800)  # steps in one episode: a fresh vehicle each
REALISTIC_SHARE = 0.75
CAMERA_SHARE = 0.1  # instant starts with a camera; the rest of the episodes start instantly without one
PROGRESS_EVERY_S = 5.0
DECODE_EVERY = 16  # telemetry frames decoded again: one in this many (all of them pack; answers all decode)


def run(steps: int, seed: int = 1, progress=None, repros: int = 3, shrink_budget_s: float = 20.0,
        shrink_total_s: float = 600.0) -> dict:
    """Walk `steps` steps (messages sent and advances of time, each one step). `repros`:
    reproductions kept per distinct failure, the first of them shrunk (within shrink_budget_s,
    while the shrinking of the whole run stays within shrink_total_s)."""
    rng = random.Random(seed)
    names = list(ACTIONS)
    weights = [ACTIONS[n][0] for n in names]
    visited, facets, sent, acks, actions = Counter(), Counter(), Counter(), Counter(), Counter()
    failures: dict[str, dict] = {}
    kinds = Counter()
    episodes = done = 0
    shrinking_s = 0.0
    t0 = last_report = time.monotonic()
    walk = None
    while done < steps:
        episodes += 1
        draw = rng.random()
        start = "realistic" if draw < REALISTIC_SHARE else "camera" if draw < REALISTIC_SHARE + CAMERA_SHARE \
            else "instant"
        walk = Walk(start, decode_every=DECODE_EVERY)
        length = rng.randint(*EPISODE_STEPS)
        try:
            if walk.start == "realistic":  # from any stage of the start-up
                walk.advance_to(rng.choice(START_AT_S))
            while walk.steps < length and done + walk.steps < steps:
                name = rng.choices(names, weights)[0]
                actions[name] += 1
                ACTIONS[name][1](walk, rng)
        except WalkFailure as exc:
            f = exc.failure
            kinds[f.kind] += 1
            sig = f.signature()
            entry = failures.get(sig)
            if entry is None:
                entry = failures[sig] = {"signature": sig, "kind": f.kind, "where": f.where, "count": 0,
                                         "states": Counter(), "reproductions": []}
            entry["count"] += 1
            entry["states"][f.state] += 1
            if len(entry["reproductions"]) < repros:
                shrunk = None
                if not entry["reproductions"] and shrinking_s < shrink_total_s:
                    began = time.monotonic()
                    shrunk = render(shrink(f, min(shrink_budget_s, shrink_total_s - shrinking_s)))
                    shrinking_s += time.monotonic() - began
                entry["reproductions"].append({"state": f.state, "message": f.message, "detail": f.detail,
                                               "episode_step": f.step, "reproduction": shrunk or render(f.trace)})
        done += walk.steps
        visited.update(walk.visited)
        facets.update(walk.facets)
        sent.update(walk.sent)
        acks.update(walk.acks)
        now = time.monotonic()
        if progress and now - last_report >= PROGRESS_EVERY_S:
            last_report = now
            progress(done, steps, len(visited), sum(sent.values()), sum(kinds.values()), len(failures), now - t0,
                     now - t0 - shrinking_s)
    wall = time.monotonic() - t0
    return {
        "steps": done, "seed": seed, "episodes": episodes, "wall_s": wall, "shrinking_s": shrinking_s,
        "steps_per_s": done / (wall - shrinking_s) if wall > shrinking_s else 0.0,
        "messages_sent": sum(sent.values()), "messages_by_type": dict(sent.most_common()),
        "actions": dict(actions.most_common()),
        "states_visited": len(visited), "states": dict(visited.most_common()),
        "facets": dict(sorted(facets.items())),
        "commands_acknowledged": sum(acks.values()),
        "acks_by_command_result": {f"{c}:{res}": n for (c, res), n in sorted(acks.items())},
        "failures_found": sum(kinds.values()), "failures_by_kind": dict(kinds),
        "exceptions": kinds["exception"], "handler_errors": kinds["handler_error"],
        "internal_errors": kinds["internal_error"],
        "distinct_failures": [{**e, "states": dict(e["states"].most_common(10))}
                              for e in sorted(failures.values(), key=lambda e: -e["count"])],
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="state_walk", description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=1_000_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, help="write the figures here")
    p.add_argument("--shrink-budget", type=float, default=20.0, help="wall seconds to shrink each distinct failure")
    args = p.parse_args(argv)

    def progress(done, total, states, messages, found, distinct, wall, walking):
        print(f"state_walk: {done:,}/{total:,} steps, {states:,} states, {messages:,} messages, "
              f"{found:,} failures ({distinct} distinct), {wall:.0f} s, {done / max(walking, 1e-9):,.0f} steps/s "
              f"(shrinking aside)", file=sys.stderr, flush=True)
    result = run(args.steps, args.seed, progress, shrink_budget_s=args.shrink_budget)
    summary = {k: v for k, v in result.items() if k not in ("states", "distinct_failures")}
    print(json.dumps(summary, indent=1))
    for entry in result["distinct_failures"]:
        first = entry["reproductions"][0]
        print(f"\nFAILURE x{entry['count']}: {entry['signature']}\n  state: {first['state']}\n"
              f"  message: {first['message']}\n  {first['detail'].strip().splitlines()[-1]}\n"
              + "\n".join("    " + line for line in first["reproduction"].splitlines()), file=sys.stderr)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return 1 if result["failures_found"] else 0


if __name__ == "__main__":
    sys.exit(main())
