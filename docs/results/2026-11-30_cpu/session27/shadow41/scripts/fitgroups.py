"""fitgroups.py DIR [DIR ...]: diagtab.py's per-pair split of the residual darkening (main's dumps), averaged over
groups of pairs by the predicted proposal's fit to the true car (ground truth, an oracle, used only to diagnose):
the proposal misses 3 or more of the car's bottom rows / not; the true band lies under 80 % inside the search
region (the fitted footprint grown) / not. Markdown, darkening points."""

from __future__ import annotations

import sys
from pathlib import Path

from diagtab import CATS, analyse


def main() -> int:
    rows = [r for d in sys.argv[1:] for p in sorted(Path(d).glob("*.npz")) if (r := analyse(p))]
    groups = {"proposal misses >= 3 bottom rows": [r for r in rows if r["miss rows"] >= 3],
              "proposal misses < 3 bottom rows": [r for r in rows if not r["miss rows"] >= 3],
              "band < 80 % in the search region": [r for r in rows if r["in search"] < 0.8],
              "band >= 80 % in the search region": [r for r in rows if r["in search"] >= 0.8],
              "all": rows}
    print("| group | n | darkening | truth's | excess | " + " | ".join(CATS) + " |")
    print("|" + "---|" * (5 + len(CATS)))
    for name, g in groups.items():
        if not g:
            continue
        n = len(g)
        cells = [name, str(n), f"{sum(r['dark'] for r in g) / n:.2f}", f"{sum(r['truth'] for r in g) / n:.2f}",
                 f"{sum(sum(r[c] for c in CATS) for r in g) / n:+.2f}"]
        cells += [f"{sum(r[c] for r in g) / n:+.2f}" for c in CATS]
        print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
