"""changed.py MAIN_DIR BRANCH_DIR [...pairs of dirs]: the counterfactual deletes whose PSNR (vacated region plus
shadow band, photo:rays) differs between main and the branch (sdn3d-bench counterfactual.json of each run), one line
each: run, source scene, pair key, main, branch, branch - main.

    python changed.py /tmp/s21data/island/bench/main_cf39_oracle_delete /tmp/s21data/island/bench/br1_cf39_oracle_delete
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def main() -> int:
    args = sys.argv[1:]
    for a, b in zip(args[::2], args[1::2], strict=True):
        runs = [{(p["source"], p["key"]): p for p in json.loads((Path(d) / "counterfactual.json").read_text())["pairs"]
                 if p["bin"] == "delete"} for d in (a, b)]
        for k in sorted(set(runs[0]) & set(runs[1])):
            if not all("photo:rays" in r[k]["metrics"] for r in runs):
                continue
            m, n = (r[k]["metrics"]["photo:rays"]["hole"]["psnr"] for r in runs)
            if abs(n - m) > 1e-6:
                print(Path(b).name, k[0], k[1], f"{m:.3f}", f"{n:.3f}", f"{n - m:+.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
