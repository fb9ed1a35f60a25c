"""paired.py OUT.md TITLE A_TEMPLATE B_TEMPLATE SEED...: Table 1 photo runs (sdn3d-bench results.json) of code/setting
A (main) against B (the branch or a variant), per kind, pooled over the trees SEED... (a template's {seed} is the
tree's seed, e.g. /tmp/s27data/occl40/t1/g0{seed}_semantic). Per kind, removals (delete + occluder removed) and all
kinds: 3D-SDN B - A, 3D-SDN - 2D paste on A and on B, on PSNR all (mean, 10,000-resample paired bootstrap 95 %
interval with numpy default_rng(0), wins/losses, n) and how many entries' 3D-SDN metrics are equal. Entries are
paired by tree and index; only entries that both runs evaluated with both methods count.
Run: /work/main/.venv/bin/python paired.py OUT.md TITLE A_TEMPLATE B_TEMPLATE 11 13 31 33 35 37 39
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

REMOVALS = ("delete", "occluder_removed")


def load(run: str) -> dict[int, tuple[str, dict, dict]]:
    """``{entry index: (kind, 3D-SDN photo metrics, 2D photo metrics)}`` of a run (entries with both)."""
    entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
    out = {}
    for e in entries:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m and "all" in m["3d-sdn"] and "all" in m["2d"]:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"], m["2d"])
    return out


def stats(d: list[float]) -> str:
    """Mean [95 % paired bootstrap interval] wins/losses (n)."""
    a = np.asarray(d, dtype=np.float64)
    if not len(a):
        return "n 0"
    boot = a[np.random.default_rng(0).integers(0, len(a), (10000, len(a)))].mean(1)
    return (f"{a.mean():+.3f} [{np.percentile(boot, 2.5):+.3f}, {np.percentile(boot, 97.5):+.3f}] "
            f"{int((a > 1e-9).sum())}/{int((a < -1e-9).sum())} (n {len(a)})")


def main(out: str, title: str, a_tpl: str, b_tpl: str, seeds: list[str]) -> None:
    pairs = []
    for seed in seeds:
        a, b = load(a_tpl.format(seed=seed)), load(b_tpl.format(seed=seed))
        pairs += [(a[i], b[i]) for i in sorted(set(a) & set(b))]
    lines = [f"# {title}", "", f"A: `{a_tpl}`, B: `{b_tpl}`, trees {', '.join(seeds)}; PSNR all, paired per entry.", "",
             "| kind | 3D-SDN B - A | 3D-SDN - 2D, A | 3D-SDN - 2D, B | 3D-SDN equal |", "|---|---|---|---|---|"]
    kinds = sorted({p[0][0] for p in pairs})
    for kind in ["all kinds", "removals (delete + occluder_removed)", *kinds]:
        sel = [p for p in pairs if kind == "all kinds" or p[0][0] == kind
               or (kind.startswith("removals") and p[0][0] in REMOVALS)]
        d = [b[1]["all"]["psnr"] - a[1]["all"]["psnr"] for a, b in sel]
        ga = [a[1]["all"]["psnr"] - a[2]["all"]["psnr"] for a, _ in sel]
        gb = [b[1]["all"]["psnr"] - b[2]["all"]["psnr"] for _, b in sel]
        equal = sum(a[1] == b[1] for a, b in sel)
        lines.append(f"| {kind} | {stats(d)} | {stats(ga)} | {stats(gb)} | {equal}/{len(sel)} |")
    text = "\n".join(lines) + "\n"
    tmp = Path(out + ".tmp")
    tmp.write_text(text)
    tmp.replace(out)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:])
