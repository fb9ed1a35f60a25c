"""The diagnosis table of README.md from diagnose.py's json files.

    cd /work/wt/occl/docs/results/2026-11-30_cpu/session24/occl && \
        /work/main/.venv/bin/python scripts/summarize.py diag_tune.json diag_2215.json
"""

from __future__ import annotations

import json
import sys
from collections import Counter


def main() -> None:
    print("| seed/world | test frames | visible cars per frame | partly hidden cars | not hidden (> 80 % visible) | "
          "partly hidden but < 119 px | partly hidden, other refusal | occluders refused | candidate pairs | "
          "pairs revealing >= 1.2x |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path in sys.argv[1:]:
        for key, frames in json.load(open(path)).items():
            refused, occ = Counter(), Counter()
            for f in frames:
                for why, n in f["hidden_refused"].items():
                    reasons = why.split("+")
                    refused["not hidden" if "visible_fraction>0.8" in reasons else
                            "small" if reasons == ["pixels<119"] else "other"] += n
                occ.update(f["occluder_refused"])
            pairs = [p for f in frames for p in f["pairs"]]
            good = sum(p["gain"] >= 1.2 for p in pairs)
            print(f"| {key} | {frames[0]['frame']}-{frames[-1]['frame']} | "
                  f"{min(f['visible_cars'] for f in frames)}-{max(f['visible_cars'] for f in frames)} | "
                  f"{sum(f['hidden_ok'] for f in frames)} | "
                  f"{refused['not hidden']} | {refused['small']} | {refused['other']} | "
                  f"{', '.join(f'{k} {v}' for k, v in occ.most_common()) or '-'} | {len(pairs)} | {good} |")


if __name__ == "__main__":
    main()
