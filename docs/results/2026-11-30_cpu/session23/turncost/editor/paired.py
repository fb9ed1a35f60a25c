"""paired.py OUT: run.sh's JSON, candidate against main at the session start, turn by turn (the same car, angle and
repetition): the geometric mean of cand / base with a 10,000-resample paired bootstrap 95 % interval (seed 0), wins /
losses and the medians, for the first turn (which makes the removal in both codes) and for the later ones (which
reuse it)."""

import json
import sys
from pathlib import Path

import numpy as np

out = Path(sys.argv[1])
rows = []
for path in sorted(out.glob("base_*.json")):
    other = out / path.name.replace("base_", "cand_")
    if not other.exists():
        continue
    a, b = json.loads(path.read_text()), json.loads(other.read_text())
    for i, (ta, tb) in enumerate(zip(a["turns"], b["turns"], strict=True)):
        rows.append((a["id"], i == 0, ta["wall_ms"], tb["wall_ms"], ta["cpu_ms"], tb["cpu_ms"]))
print(f"{len(rows)} paired turns from {out}")
print("| turns | measure | n | main median ms | candidate median ms | candidate / main [95 %] | wins / losses |")
print("|---|---|---|---|---|---|---|")
for first, label in ((True, "first of a car (makes the removal)"), (False, "later (reuse it)")):
    for col, name in ((4, "CPU"), (2, "wall")):
        sel = [r for r in rows if r[1] == first]
        base, cand = np.array([r[col] for r in sel]), np.array([r[col + 1] for r in sel])
        logs = np.log(cand / base)
        boots = np.exp(logs[np.random.default_rng(0).integers(0, len(logs), (10000, len(logs)))].mean(1))
        lo, hi = np.percentile(boots, [2.5, 97.5])
        print(f"| {label} | {name} | {len(sel)} | {np.median(base):.0f} | {np.median(cand):.0f} | "
              f"{np.exp(logs.mean()):.3f} [{lo:.3f}, {hi:.3f}] | {(cand < base).sum()} / {(cand > base).sum()} |")
