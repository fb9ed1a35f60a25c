# ruff: noqa: E402, E501, E701, E702
"""paired.py OUT.md RUN.json...: paired comparison of this branch and main over the runs of
benchmarks/photo_latency.py --against main=... --json RUN.json (the same 14 lat3 edits per run, the two codes taking
turns edit by edit). Per kind: the median over runs and edits of the wall and CPU ms of each code, p90 of both, the
per-edit ratio this/main of the CPU ms averaged over the runs with a paired 95 % bootstrap interval (10000
resamples of the edits), and the win count (edit-runs where this code took less CPU / wall than main)."""
import json
import sys

import numpy as np

out, paths = sys.argv[1], sys.argv[2:]
runs = [json.load(open(p)) for p in paths]
this_key = next(k for k in runs[0] if k.startswith("this:"))
main_key = next(k for k in runs[0] if k.startswith("main:"))
kinds = [e[0] for e in runs[0][this_key]]
wall = {c: np.array([[e[1] for e in r[k]] for r in runs]) for c, k in (("this", this_key), ("main", main_key))}  # (R, E)
cpu = {c: np.array([[e[2] for e in r[k]] for r in runs]) for c, k in (("this", this_key), ("main", main_key))}
rng = np.random.default_rng(0)
lines = [f"{len(runs)} runs x {len(kinds)} edits (lat3, fresh source state, 1 thread); ms; ratio = this / main of each edit's CPU ms averaged over the runs, paired bootstrap 95 % interval over edits", "",
         "| kind | edits x runs | this wall median / p90 | main wall median / p90 | this CPU median / p90 | main CPU median / p90 | CPU ratio (95 % CI) | wall ratio (95 % CI) | CPU wins | wall wins |",
         "|---|---|---|---|---|---|---|---|---|---|"]
for kind in ["all", *sorted(set(kinds))]:
    sel = np.array([kind == "all" or k == kind for k in kinds])
    def stats(a, sel=sel): return f"{np.median(a[:, sel]):.0f} / {np.percentile(a[:, sel], 90):.0f}"
    cells = []
    for what in (cpu, wall):
        t, m = what["this"][:, sel].mean(0), what["main"][:, sel].mean(0)  # per edit, over runs
        ratio = t.sum() / m.sum()
        boots = []
        for _ in range(10000):
            i = rng.integers(0, len(t), len(t))
            boots.append(t[i].sum() / m[i].sum())
        lo, hi = np.percentile(boots, [2.5, 97.5])
        cells.append(f"{ratio:.3f} ({lo:.3f}-{hi:.3f})")
    wins = [int((what["this"][:, sel] < what["main"][:, sel]).sum()) for what in (cpu, wall)]
    n = int(sel.sum()) * len(runs)
    lines.append(f"| {kind} | {sel.sum()} x {len(runs)} | {stats(wall['this'])} | {stats(wall['main'])} | {stats(cpu['this'])} | {stats(cpu['main'])} | {cells[0]} | {cells[1]} | {wins[0]}/{n} | {wins[1]}/{n} |")
open(out, "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
