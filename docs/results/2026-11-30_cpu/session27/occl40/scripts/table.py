"""table.py OUT.md MAIN_NAME BRANCH_NAME ROWS SEED...: Table 1 photo rows of this helper's t1.sh runs
(/tmp/s23data/rmpred/t1/<NAME><SEED>_<row>), main against the branch, per row (ROWS: comma-separated of semantic =
predicted, gt = ground-truth masks (oracle)), pooled over the trees SEED...: per kind, the removals (delete +
occluder removed) pooled and all kinds pooled, on PSNR and L1 of ``all`` (L1 signed: positive = branch / 3D-SDN
better):

- 3D-SDN branch minus main (and how many entries' 3D-SDN metrics are equal between the codes);
- 3D-SDN minus the 2D paste on main and on the branch.

Each figure: mean, 10,000-resample paired bootstrap 95 % interval (numpy default_rng(0)), wins/losses (n). Last, the
merge rule's test (README): predicted removals branch - main mean > 0 and interval not wholly below 0; every kind and
pooled, both rows: interval not wholly below 0 and mean not below 0 (PSNR all).
Run: /work/main/.venv/bin/python table.py OUT.md main br semantic,gt 31 35 37
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np

ROOT = "/tmp/s23data/rmpred/t1"
TITLES = {"semantic": "predicted", "gt": "ground-truth masks (oracle)"}
REMOVALS = ("delete", "occluder_removed")


def load(run: str) -> dict[int, tuple[str, dict, dict]]:
    """``{entry index: (kind, 3D-SDN photo metrics, 2D photo metrics)}`` of a run's results.json (entries with both)."""
    entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
    out = {}
    for e in entries:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"], m["2d"])
    return out


def stats(d: list[float]) -> tuple[float, float, float, int, int, int]:
    """``(mean, lo, hi, wins, losses, n)``: 10,000-resample paired bootstrap 95 % interval."""
    a = np.asarray([x for x in d if np.isfinite(x)])
    if not len(a):
        return (float("nan"),) * 3 + (0, 0, 0)
    boot = a[np.random.default_rng(0).integers(0, len(a), (10000, len(a)))].mean(1)
    return (float(a.mean()), float(np.percentile(boot, 2.5)), float(np.percentile(boot, 97.5)),
            int((a > 1e-9).sum()), int((a < -1e-9).sum()), len(a))


def fmt(s: tuple, digits: int = 3) -> str:
    m, lo, hi, w, lo_n, n = s
    return f"{m:+.{digits}f} [{lo:+.{digits}f}, {hi:+.{digits}f}] {w}/{lo_n} (n {n})" if n else "n=0"


def main(out: str, main_name: str, branch_name: str, rows: list[str], seeds: list[str]) -> None:
    lines = [f"# Table 1 photo rows, {main_name} (main) vs {branch_name} (branch), trees {', '.join(seeds)}", ""]
    verdict = []
    for row in rows:
        pairs = []
        for seed in seeds:
            a, b = load(f"{ROOT}/{main_name}{seed}_{row}"), load(f"{ROOT}/{branch_name}{seed}_{row}")
            pairs += [(a[i], b[i]) for i in sorted(set(a) & set(b))]
        equal = sum(a[1] == b[1] for a, b in pairs)
        lines += [f"## {TITLES[row]}: {len(pairs)} paired entries; 3D-SDN metrics equal on {equal}", ""]
        for metric, sign in (("psnr", 1), ("l1", -1)):
            digits = 3 if metric == "psnr" else 4
            signed = " (signed: positive = branch / 3D-SDN better)" if sign < 0 else ""
            lines += [f"### {metric.upper()} all{signed}", "",
                      "| kind | 3D-SDN branch - main | 3D-SDN - 2D, main | 3D-SDN - 2D, branch |", "|---|---|---|---|"]
            kinds = sorted({p[0][0] for p in pairs})
            for kind in ["all kinds", "removals (delete + occluder_removed)", *kinds]:
                sel = [p for p in pairs if kind == "all kinds" or p[0][0] == kind
                       or (kind.startswith("removals") and p[0][0] in REMOVALS)]
                sel = [p for p in sel if "all" in p[0][1] and "all" in p[1][1] and "all" in p[0][2]]
                d = stats([sign * (b[1]["all"][metric] - a[1]["all"][metric]) for a, b in sel])
                gap_a = stats([sign * (a[1]["all"][metric] - a[2]["all"][metric]) for a, _ in sel])
                gap_b = stats([sign * (b[1]["all"][metric] - b[2]["all"][metric]) for _, b in sel])
                lines.append(f"| {kind} | {fmt(d, digits)} | {fmt(gap_a, digits)} | {fmt(gap_b, digits)} |")
                if metric == "psnr" and d[5]:
                    if kind.startswith("removals"):
                        if row == "semantic":
                            verdict.append((f"{TITLES[row]} removals: mean > 0, interval not wholly below 0",
                                            d[0] > 0 and d[2] >= 0, d))
                    else:
                        verdict.append((f"{TITLES[row]} {kind}: mean >= 0, interval not wholly below 0",
                                        d[0] >= 0 and d[2] >= 0, d))
            lines.append("")
    lines += ["## The merge rule (PSNR all, 3D-SDN branch - main)", "", "| test | holds | figure |", "|---|---|---|"]
    lines += [f"| {name} | {ok} | {fmt(d)} |" for name, ok, d in verdict]
    lines += ["", f"**All hold: {all(ok for _, ok, _ in verdict)}**"]
    text = "\n".join(lines) + "\n"
    tmp = f"{out}.tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, out)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(","), sys.argv[5:])
