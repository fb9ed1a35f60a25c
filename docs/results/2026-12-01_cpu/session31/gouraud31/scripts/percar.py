# ruff: noqa: E402, E501, E701, E702
"""percar.py MAIN_DIR BRANCH_DIR: branch - main per car (world / instance id, its frames and variations pooled) on the
turn pairs of 45 degrees and more (fill rays, the car's target pixels), per source scene: n pairs, mean PSNR and L1
difference; then the mean over cars (each car once). Reported beside the rule, deciding nothing: a parked car's frames
give near-identical pairs, which the pairs' bootstrap counts as independent."""
from __future__ import annotations

import json
import sys
from collections import defaultdict

FILL = "photo:rays"


def load(path: str) -> dict:
    return {(p["source"], p["bin"], p["key"]): p["metrics"][FILL]["car"]
            for p in json.load(open(f"{path}/counterfactual.json"))["pairs"] if p["kind"] == "turn" and FILL in p["metrics"]}


def main() -> int:
    main_, branch = load(sys.argv[1]), load(sys.argv[2])
    cars = defaultdict(list)
    for key in sorted(main_.keys() & branch.keys()):
        source, bin_, name = key
        if int(bin_.split()[-1]) < 45:
            continue
        world, rest = name.split("/")[0], name.split()[0].split("_")[-1]
        m, b = main_[key], branch[key]
        cars[(source, f"{world}/{rest}")].append((b["psnr"] - m["psnr"], b["l1"] - m["l1"]))
    print("| source scene | car | pairs | PSNR branch - main | L1 branch - main |")
    print("|---|---|---|---|---|")
    for source in sorted({s for s, _ in cars}):
        means = []
        for (s, car), d in sorted(cars.items()):
            if s != source:
                continue
            dp, dl = sum(x[0] for x in d) / len(d), sum(x[1] for x in d) / len(d)
            means.append((dp, dl))
            print(f"| {source} | {car} | {len(d)} | {dp:+.3f} | {dl:+.4f} |")
        print(f"| {source} | **mean over {len(means)} cars** ({sum(m[0] > 0 for m in means)} gain in PSNR, "
              f"{sum(m[1] < 0 for m in means)} in L1) | | **{sum(m[0] for m in means) / len(means):+.3f}** | "
              f"{sum(m[1] for m in means) / len(means):+.4f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
