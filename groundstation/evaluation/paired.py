"""Two `groundstation evaluate --json` runs of the same episodes compared (issue 32, item 5: the
camera against the point sensor): per run success, mean path, time to declaration, false
declarations and decision times, then the paired differences, second minus first, over the episodes
both ran (each episode is the same world in both), with 95 % intervals (Student's t).

    python -m groundstation.evaluation.paired out/eval/point.json out/eval/camera.json
"""
from __future__ import annotations

import json
import math
import sys

import numpy as np

from .evaluate import t_975


def rows_of(path: str) -> tuple[str, list[dict]]:
    payload = json.loads(open(path).read())
    (policy, rows), = payload["results"].items()  # one policy per run
    return f"{payload['config'].get('sensor', 'point')}/{policy}", rows


def line(name: str, rows: list[dict]) -> str:
    decisions = sum(r["decisions"] for r in rows)
    ms_mean = sum(r["ms_mean"] * r["decisions"] for r in rows) / decisions if decisions else 0.0
    frames = sum(r.get("frames", 0) for r in rows)
    frame_ms = sum(r.get("frame_ms_mean", 0.0) * r.get("frames", 0) for r in rows) / frames if frames else 0.0
    return (f"{name:<14} {len(rows):>4} {np.mean([r['success'] for r in rows]):>7.3f} "
            f"{np.mean([r['path_m'] for r in rows]):>7.0f} {np.mean([r.get('time_s', math.nan) for r in rows]):>6.0f} "
            f"{np.nanmean([r['first_find_m'] if r.get('first_find_m') is not None else math.nan for r in rows]):>6.0f} "
            f"{sum(r['false_declarations'] if 'false_declarations' in r else r['false_declaration'] for r in rows):>5d} "
            f"{ms_mean:>6.1f} {max(r['ms_max'] for r in rows):>6.1f} {frame_ms:>7.2f} "
            f"{max((r.get('frame_ms_max', 0.0) for r in rows), default=0.0):>7.1f}")


def difference(first: dict[int, dict], second: dict[int, dict], key: str) -> str:
    both = sorted(set(first) & set(second))
    d = np.array([float(second[k][key] or 0.0) - float(first[k][key] or 0.0) for k in both])
    mean = float(d.mean())
    half = t_975(d.size - 1) * float(d.std(ddof=1)) / math.sqrt(d.size) if d.size > 1 else math.nan
    ratio = np.mean([second[k][key] or 0.0 for k in both]) / max(np.mean([first[k][key] or 0.0 for k in both]), 1e-9)
    return f"  {key:<13} {mean:>+8.1f}  [{mean - half:+.1f}, {mean + half:+.1f}]  ratio of means {ratio:.2f}"


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("usage: python -m groundstation.evaluation.paired FIRST.json SECOND.json", file=sys.stderr)
        return 2
    (a, ra), (b, rb) = rows_of(argv[0]), rows_of(argv[1])
    print(f"{'run':<14} {'eps':>4} {'success':>7} {'path m':>7} {'time s':>6} {'1st m':>6} {'false':>5} "
          f"{'ms/dec':>6} {'max ms':>6} {'ms/frm':>7} {'max frm':>7}")
    print(line(a, ra))
    print(line(b, rb))
    first, second = {r["episode"]: r for r in ra}, {r["episode"]: r for r in rb}
    both = sorted(set(first) & set(second))
    print(f"{b} minus {a} on the same {len(both)} episodes, mean [95 % CI]:")
    for key in ("path_m", "time_s", "first_find_m"):
        print(difference(first, second, key))
    ok = [k for k in both if first[k]["success"]]
    print(f"  success where {a} succeeds: {sum(second[k]['success'] for k in ok)}/{len(ok)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
