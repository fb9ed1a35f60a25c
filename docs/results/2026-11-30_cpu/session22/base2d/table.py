"""table.py OUT.md MAIN_NAME BRANCH_NAME SEED...: Table 1 photo rows of this helper's t1.sh runs
(/tmp/s22data/base2d/t1/<NAME><SEED>_<row>), main against the branch, per row (predicted, ground-truth masks
(oracle)), pooled over the trees SEED...:

- 3D-SDN: every entry's metrics equal between the codes, and every dumped 3D-SDN picture (``sdn`` of dbench.py's npz)
  byte-identical (the change must leave 3D-SDN's outputs alone);
- the 2D paste (``2d``): branch minus main, per kind and pooled, on PSNR and L1 of ``all`` (L1 signed: positive =
  branch better), and the same on the removals (delete + occluder removed) pooled, the merge rule's figure;
- 3D-SDN minus 2D on main and on the branch (the measurement this corrects).

Each figure: mean, 10,000-resample paired bootstrap 95 % interval (numpy default_rng(0)), wins/losses (n).
Run: /work/main/.venv/bin/python table.py OUT.md main br 31 35 37
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np

ROOT = "/tmp/s22data/base2d/t1"
ROWS = (("semantic", "predicted"), ("gt", "ground-truth masks (oracle)"))
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


def ci(d: list[float], digits: int = 3) -> str:
    """Mean [95 % paired bootstrap] wins/losses (n), ``digits`` decimals."""
    d = np.asarray([x for x in d if np.isfinite(x)])
    if not len(d):
        return "n=0"
    boot = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    lo, hi = np.percentile(boot, 2.5), np.percentile(boot, 97.5)
    return (f"{d.mean():+.{digits}f} [{lo:+.{digits}f}, {hi:+.{digits}f}] "
            f"{int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n {len(d)})")


def identical_sdn(main_run: str, branch_run: str) -> tuple[int, int]:
    """``(same, total)``: dumped 3D-SDN pictures byte-identical between the codes."""
    same = total = 0
    for name in sorted(os.listdir(f"{main_run}.dump")):
        a, b = np.load(f"{main_run}.dump/{name}"), np.load(f"{branch_run}.dump/{name}")
        if "sdn" in a.files or "sdn" in b.files:
            total += 1
            same += int("sdn" in a.files and "sdn" in b.files and np.array_equal(a["sdn"], b["sdn"]))
    return same, total


def main(out: str, main_name: str, branch_name: str, seeds: list[str]) -> None:
    rule: dict[tuple[str, str], float] = {}
    lines = [f"# Table 1 photo rows, {main_name} (main) vs {branch_name} (branch), trees {', '.join(seeds)}", ""]
    for row, title in ROWS:
        pairs, same, total, metrics_equal = [], 0, 0, True
        for seed in seeds:
            a_run, b_run = f"{ROOT}/{main_name}{seed}_{row}", f"{ROOT}/{branch_name}{seed}_{row}"
            a, b = load(a_run), load(b_run)
            for i in sorted(set(a) & set(b)):
                pairs.append((a[i], b[i]))
                metrics_equal &= a[i][1] == b[i][1]
            s, t = identical_sdn(a_run, b_run)
            same, total = same + s, total + t
        lines += [f"## {title}: {len(pairs)} paired entries", "",
                  f"3D-SDN: metrics equal on every entry: **{metrics_equal}**; pictures byte-identical: "
                  f"**{same}/{total}**", ""]
        for metric, sign in (("psnr", 1), ("l1", -1)):
            signed = " (signed: positive = branch / 3D-SDN better)" if sign < 0 else ""
            lines += [f"### {metric.upper()} all{signed}",
                      "", "| kind | 2D branch - main | 3D-SDN - 2D, main | 3D-SDN - 2D, branch |", "|---|---|---|---|"]
            kinds = sorted({p[0][0] for p in pairs})
            for kind in ["ALL", "removals (delete + occluder_removed)", *kinds]:
                sel = [p for p in pairs if kind == "ALL" or p[0][0] == kind
                       or (kind.startswith("removals") and p[0][0] in REMOVALS)]
                sel = [p for p in sel if "all" in p[0][2] and "all" in p[1][2]]
                d2 = [sign * (b[2]["all"][metric] - a[2]["all"][metric]) for a, b in sel]
                gap_a = [sign * (a[1]["all"][metric] - a[2]["all"][metric]) for a, _ in sel]
                gap_b = [sign * (b[1]["all"][metric] - b[2]["all"][metric]) for _, b in sel]
                digits = 3 if metric == "psnr" else 4
                lines.append(f"| {kind} | {ci(d2, digits)} | {ci(gap_a, digits)} | {ci(gap_b, digits)} |")
                if kind.startswith("removals"):
                    rule[(title, metric)] = float(np.mean(d2)) if d2 else float("nan")
            lines.append("")
    lines += ["## The merge rule's figures: mean of the 2D paste's branch - main on the removals (>= 0 holds)", "",
              "| row | metric | mean | holds |", "|---|---|---|---|"]
    lines += [f"| {row} | {metric} all | {value:+.6f} | {value >= 0} |" for (row, metric), value in rule.items()]
    text = "\n".join(lines)
    tmp = f"{out}.tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, out)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:])
