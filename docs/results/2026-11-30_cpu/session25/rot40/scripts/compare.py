"""Paired Table 1 comparison of two codes (session 18 pick's compare.py, trimmed, self-contained).

python compare.py LABEL MAIN_RUN:BRANCH_RUN [...] [--md OUT.md]
Entries pooled over the pairs of runs (one pair per tree, results.json of dbench.py runs), per kind of edit and for
rotates and zooms together: 3D-SDN branch minus main, 3D-SDN minus the 2D paste for main and for the branch (PSNR of
'all', dB; and L1 of 'all', signed so that positive = branch / 3D-SDN better). Mean, 10,000-draw paired bootstrap 95 %
interval (seed 0), wins / losses (n). Entries a method failed on are left out of the pairs."""
import json
import sys

import numpy as np


def load(run):
    out = {}
    for e in next(iter(json.load(open(f"{run}/results.json"))["entries"].values())):
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m and "all" in m["3d-sdn"] and "all" in m["2d"]:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"]["all"], m["2d"]["all"])
    return out


def ci(d):
    d = np.asarray(d, dtype=float)
    if not len(d):
        return "n=0"
    boot = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    return (f"{d.mean():+.3f} [{np.percentile(boot, 2.5):+.3f}, {np.percentile(boot, 97.5):+.3f}] "
            f"{int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n {len(d)})")


def main():
    args = sys.argv[1:]
    md = None
    if "--md" in args:
        k = args.index("--md")
        md, args = args[k + 1], args[:k] + args[k + 2:]
    label, pairs = args[0], [p.split(":") for p in args[1:]]
    rows = []
    for a, b in pairs:
        x, y = load(a), load(b)
        rows += [(x[i], y[i]) for i in sorted(set(x) & set(y))]
    lines = [f"**{label}**: {len(rows)} paired entries from {len(pairs)} tree(s)", "",
             "| metric | kind | 3D-SDN branch - main | 3D-SDN - 2D, main | 3D-SDN - 2D, branch |",
             "|---|---|---|---|---|"]
    kinds = ["ALL", "rotate+zoom"] + sorted({r[0][0] for r in rows})
    for metric, sign in (("psnr", 1), ("l1", -1)):
        for kind in kinds:
            sel = [r for r in rows if kind == "ALL" or r[0][0] == kind
                   or (kind == "rotate+zoom" and r[0][0] in ("rotate", "zoom"))]
            if not sel:
                continue
            br = [sign * (n[1][metric] - m[1][metric]) for m, n in sel]
            gm = [sign * (m[1][metric] - m[2][metric]) for m, _ in sel]
            gb = [sign * (n[1][metric] - n[2][metric]) for _, n in sel]
            lines.append(f"| {metric} all | {kind} | {ci(br)} | {ci(gm)} | {ci(gb)} |")
    text = "\n".join(lines)
    print(text)
    if md:
        with open(md, "a") as f:
            f.write(text + "\n\n")


if __name__ == "__main__":
    main()
