"""perpair.py MAIN_DIR BRANCH_DIR: the pairs whose car PSNR (photo:rays) differs between two sdn3d-bench
counterfactual runs (counterfactual.json), branch - main, sorted; one line per pair: difference, bin, (source, key).

    /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session24/turn41/perpair.py MAIN_DIR BRANCH_DIR
"""

import json
import sys
from pathlib import Path


def load(path: str) -> dict:
    pairs = json.loads((Path(path) / "counterfactual.json").read_text())["pairs"]
    return {(q["source"], q["key"]): (q["bin"], q["metrics"]["photo:rays"]["car"]["psnr"])
            for q in pairs if "photo:rays" in q["metrics"]}


a, b = load(sys.argv[1]), load(sys.argv[2])
rows = sorted((b[k][1] - a[k][1], k, a[k][0]) for k in a if k in b and abs(b[k][1] - a[k][1]) > 1e-4)
for d, k, bn in rows:
    print(f"{d:+.3f} {bn} {k}")
