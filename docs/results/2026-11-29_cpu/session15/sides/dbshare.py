"""dbshare.py PROBE.log ...: per log of session 14's probe.py (one bin of a counterfactual tree), the dB each
(part, source code) class of the drawn pixels costs: per pair 10 log10(1 / (1 - its share of the pair's squared
error)), averaged over the pairs (from the six largest shares probe.py prints per pair), and summed by source and by
part."""

from __future__ import annotations

import json
import math
import sys
from collections import defaultdict


def main() -> None:
    for path in sys.argv[1:]:
        rows = [json.loads(line) for line in open(path) if line.startswith("{")]
        gain: dict = defaultdict(float)
        by_source: dict = defaultdict(float)
        by_part: dict = defaultdict(float)
        for r in rows:
            for k, v in r["split"].items():
                g = 10 * math.log10(1 / max(1e-6, 1 - v)) / len(rows)
                gain[k] += g
                by_source[k.split("/")[1]] += g
                by_part[k.split("/")[0]] += g
        print(path, "pairs", len(rows))
        print("  by class (dB if removed, mean over pairs):",
              {k: round(v, 2) for k, v in sorted(gain.items(), key=lambda kv: -kv[1])[:8]})
        print("  by source:", {k: round(v, 2) for k, v in sorted(by_source.items(), key=lambda kv: -kv[1])})
        print("  by part:", {k: round(v, 2) for k, v in sorted(by_part.items(), key=lambda kv: -kv[1])})


if __name__ == "__main__":
    main()
