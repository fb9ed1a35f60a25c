# ruff: noqa: E402, E501, E701, E702
"""flatcheck.py MAIN_DIR BRANCH_DIR [...]: per source scene, how many turn pairs' flat-colour share (fill rays, the
car's target pixels) differs between main and the branch (exact equality), over each pair of runs given."""
from __future__ import annotations

import json
import sys
from collections import Counter

FILL = "photo:rays"


def load(path: str) -> dict:
    return {(p["source"], p["key"]): p["metrics"][FILL]["car"]["flat"]
            for p in json.load(open(f"{path}/counterfactual.json"))["pairs"] if p["kind"] == "turn" and FILL in p["metrics"]}


def main() -> int:
    n, differ = Counter(), Counter()
    args = sys.argv[1:]
    for m_dir, b_dir in zip(args[::2], args[1::2], strict=True):
        m, b = load(m_dir), load(b_dir)
        for key in m.keys() & b.keys():
            n[key[0]] += 1
            differ[key[0]] += m[key] != b[key]
    for source in sorted(n):
        print(f"{source}: {differ[source]} of {n[source]} pairs differ in flat-colour share")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
