# ruff: noqa: E501
"""paired.py LABEL MAIN_DIR BRANCH_DIR [LABEL MAIN_DIR BRANCH_DIR ...]: branch against main on the same counterfactual
pairs (sdn3d-bench counterfactual.json of each run), one Markdown row per tree label, source scene, kind (deletes:
the vacated region plus shadow band; turns: per angle bin, the car's target pixels and the changed ones: the car's,
the vacated ones and the shadow band) and photo fill both ran: mean
PSNR of each, the paired difference branch - main (10k bootstrap resamples, 95 %) with wins/losses/ties; for deletes
also the residual darkening of the shadow band (the benchmark's: the band's darkening against the road ring; the
truth's, the exact render without the car, alongside) and the paired difference of its error (lower is better)."""

from __future__ import annotations

import json
import sys
from collections import defaultdict

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "gt": "ground-truth masks (oracle)", "semantic": "predicted"}


def load(path: str) -> dict:
    return {(p["source"], p["bin"], p["key"]): p for p in json.load(open(f"{path}/counterfactual.json"))["pairs"]}


def rows(label: str, main: dict, branch: dict) -> list[str]:
    out = []
    groups = defaultdict(list)
    for k in sorted(set(main) & set(branch)):
        groups[(k[0], k[1])].append(k)
    for (source, bin_), keys in sorted(groups.items()):
        fills = sorted({m for k in keys for m in branch[k]["metrics"] if m.startswith("photo:")} & {m for k in keys for m in main[k]["metrics"]})
        for fill, region in [(f, r) for f in fills for r in (("hole",) if bin_ == "delete" else ("car", "changed"))]:
            got = [(main[k]["metrics"][fill][region], branch[k]["metrics"][fill][region], main[k].get("reference") or {}) for k in keys
                   if fill in main[k]["metrics"] and fill in branch[k]["metrics"]]
            if not got:
                continue
            a = [g[1]["psnr"] for g in got]
            b = [g[0]["psnr"] for g in got]
            d = paired_difference(a, b, True)
            cells = [label, LABELS.get(source, source), bin_ if bin_ == "delete" else f"{bin_}, {region} pixels", fill, str(d.n), f"{sum(b) / len(b):.3f}", f"{sum(a) / len(a):.3f}",
                     f"{d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}]", f"{d.wins}/{d.losses}/{d.ties}"]
            if bin_ == "delete":
                e = paired_difference([g[1]["darkening_error"] for g in got], [g[0]["darkening_error"] for g in got], False)
                truth = sum(g[2].get("target", 0.0) for g in got) / len(got)
                cells += [f"{sum(g[0]['darkening'] for g in got) / len(got):+.4f}", f"{sum(g[1]['darkening'] for g in got) / len(got):+.4f}",
                          f"{truth:+.4f}", f"{e.mean:+.4f} [{e.low:+.4f}, {e.high:+.4f}] {e.wins}/{e.losses}/{e.ties}"]
            else:
                cells += ["", "", "", ""]
            out.append("| " + " | ".join(cells) + " |")
    return out


def main() -> int:
    args = sys.argv[1:]
    print("| tree | source scene | kind / bin | fill | n | PSNR main | PSNR branch | branch - main [95 % CI] | wins/losses/ties "
          "| residual darkening main | branch | truth's | darkening error branch - main [95 % CI] w/l/t (lower better) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for i in range(0, len(args), 3):
        for r in rows(args[i], load(args[i + 1]), load(args[i + 2])):
            print(r)
    return 0


if __name__ == "__main__":
    sys.exit(main())
