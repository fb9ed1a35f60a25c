"""Pairs rounds.sh's runs: per edit the least CPU (and wall) ms of each code's rounds, the ratio NEW/BASE per edit,
its geometric mean with a paired bootstrap 95 % interval (10k resamples of the edits), wins and losses, per kind.

    python min_rounds.py OUT
"""

import re
import sys
from pathlib import Path

import numpy as np

out = Path(sys.argv[1])
line = re.compile(r"edit (\d+) (\S+): CPU ([\d.]+) ms wall ([\d.]+) ms")


def least(code: str) -> tuple[list[str], np.ndarray]:
    runs = []
    for f in sorted(out.glob(f"{code}_*.txt")):
        rows = [line.match(x) for x in f.read_text().splitlines()]
        runs.append([(m[2], float(m[3]), float(m[4])) for m in rows if m])
    kinds = [k for k, _, _ in runs[0]]
    return kinds, np.array([[[c, w] for _, c, w in r] for r in runs]).min(0), len(runs)


kinds, new, n_new = least("new")
_, base, n_base = least("base")
rng = np.random.default_rng(0)
print(f"{len(kinds)} edits, the least of {n_new} (new) and {n_base} (base) rounds per edit; "
      f"load: {' / '.join(x.split('load average:')[1].strip() for x in (out / 'load.txt').read_text().splitlines())}")
for col, name in ((0, "CPU"), (1, "wall")):
    log = np.log(new[:, col] / base[:, col])
    boot = np.exp(log[rng.integers(0, len(log), (10000, len(log)))].mean(1))
    lo, hi = np.percentile(boot, [2.5, 97.5])
    print(f"{name}: new/base {np.exp(log.mean()):.3f} [95 % {lo:.3f}, {hi:.3f}], wins {int((log < 0).sum())} losses "
          f"{int((log > 0).sum())}; median ms {np.median(new[:, col]):.0f} (new) vs {np.median(base[:, col]):.0f} "
          f"(base), mean {new[:, col].mean():.0f} vs {base[:, col].mean():.0f}")
    for kind in sorted(set(kinds)):
        k = np.array([x == kind for x in kinds])
        print(f"  {kind} ({int(k.sum())}): new/base {np.exp(log[k].mean()):.3f}, median ms "
              f"{np.median(new[k, col]):.0f} vs {np.median(base[k, col]):.0f}")
