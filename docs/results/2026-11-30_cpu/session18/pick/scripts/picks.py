# ruff: noqa: E501
"""picks.py MAIN_POSES.json:BRANCH_POSES.json [...]: per pair of session 13 rotloss poses.py outputs (one run of main,
one of the branch, same tree and row), the operations whose picked proposal overlaps the true car at mask IoU < 0.3
(the census' "pick misses the car"), over all entries and over the entries 3D-SDN loses to the 2D paste (PSNR all), the
entries whose picks differ, and the losers' causes by session 13's causes.py rules (count, summed dB). Pooled last."""
import importlib.util
import json
import os
import sys
from collections import defaultdict

spec = importlib.util.spec_from_file_location("causes", "/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/causes.py")
causes = importlib.util.module_from_spec(spec)
spec.loader.exec_module(causes)


def misses(rows: list[dict]) -> tuple[int, int]:
    ops = [o for r in rows for o in r["ops"] if "mask_iou" in o]
    return sum(o["mask_iou"] < 0.3 for o in ops), len(ops)


def census(rows: list[dict]) -> dict[str, list]:
    by: dict[str, list] = defaultdict(lambda: [0, 0.0])
    for r in rows:
        if r["d_all"] < 0:
            c = causes.cause(r)
            by[c][0] += 1
            by[c][1] += r["d_all"]
    return by


def report(label: str, main_rows: list[dict], branch_rows: list[dict]) -> None:
    m, b = {r["index"]: r for r in main_rows}, {r["index"]: r for r in branch_rows}
    common = sorted(set(m) & set(b))
    mm, bb = [m[i] for i in common], [b[i] for i in common]
    changed = sum(any(x.get("mask_iou") != y.get("mask_iou") for x, y in zip(m[i]["ops"], b[i]["ops"], strict=False)) for i in common)
    print(f"== {label}: {len(common)} entries in both (main {len(m)}, branch {len(b)}); entries whose picks' IoU changed: {changed}")
    for name, rows in (("main", mm), ("branch", bb)):
        k, n = misses(rows)
        lk, ln = misses([r for r in rows if r["d_all"] < 0])
        loss = sum(r["d_all"] for r in rows if r["d_all"] < 0)
        print(f"  {name:6s} picks IoU<0.3: {k}/{n} ops (all entries); {lk}/{ln} ops of the {sum(r['d_all'] < 0 for r in rows)} losing entries (summed loss {loss:+.2f} dB)")
        for c, (cnt, s) in sorted(census(rows).items(), key=lambda kv: kv[1][1]):
            print(f"         {c:34s} n {cnt:3d} {s:+7.2f} dB ({s / loss:5.1%})")


def main(pairs: list[list[str]]) -> None:
    pooled_m: list[dict] = []
    pooled_b: list[dict] = []
    for a, b in pairs:
        ma, mb = json.load(open(a)), json.load(open(b))
        report(f"{os.path.basename(a)} vs {os.path.basename(b)}", ma, mb)
        tag = os.path.basename(a)
        pooled_m += [dict(r, index=f"{tag}:{r['index']}") for r in ma]
        pooled_b += [dict(r, index=f"{tag}:{r['index']}") for r in mb]
    if len(pairs) > 1:
        report("pooled", pooled_m, pooled_b)


if __name__ == "__main__":
    main([p.split(":") for p in sys.argv[1:]])
