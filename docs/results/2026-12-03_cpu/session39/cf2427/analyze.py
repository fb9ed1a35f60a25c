# ruff: noqa: INP001, E501
"""Session 39 cf2427: issue 41's turn and delete tables and goals from the counterfactual benchmark's JSONs of the
issue-time code and main (PLAN.md's rules). Run with main's src on PYTHONPATH:

    python analyze.py ISSUE_ORACLE.json MAIN_ORACLE.json [ISSUE_PRED.json MAIN_PRED.json] > tables.md

Every interval is a 95 % bootstrap resampling whole cars (world/instance id; 10,000 draws,
sdn3d.evaluation.paired.paired_difference(..., groups=car)); a run's mean alone is bootstrapped the same way (its
values against zeros). Differences are over the pairs both runs scored; wins/losses count pairs.
"""

from __future__ import annotations

import gzip
import json
import math
import sys

import numpy as np

from sdn3d.evaluation.paired import paired_difference

BINS = ("turn 15", "turn 45", "turn 90", "turn 180")
LABELS = {"oracle": "oracle: ground-truth geometry",
          "gt": "ground-truth masks, the geometric branch's poses (main: + the test-time fit; the issue-time code has none here)",
          "semantic": "predicted: the semantic branch's masks, the geometric branch's poses (main: + the test-time fit; issue-time: none)"}
ISSUE_TURN, MAIN_TURN = "photo:auto", "photo:rays"
OLD_FILLS = ("photo:auto", "photo:telea", "photo:patchmatch", "generator")


def load(path: str) -> dict:
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return json.load(f)


def car_of(pair: dict) -> str:
    if "car" in pair:
        return pair["car"]
    world = pair["key"].split("/")[0]
    return f"{world}/{pair['key'].split()[0].rsplit('_', 1)[1]}"


def values(report: dict, source: str, bin_: str, method: str, region: str, metric: str) -> dict[str, tuple[float, str]]:
    """{pair key: (value, car)} of the scored pairs."""
    out = {}
    for p in report["pairs"]:
        if p["source"] != source or p["bin"] != bin_:
            continue
        v = ((p.get("metrics") or {}).get(method) or {}).get(region, {}).get(metric)
        if isinstance(v, (int, float)) and math.isfinite(v):
            out[p["key"]] = (float(v), car_of(p))
    return out


def missed(report: dict, source: str, bin_: str) -> int:
    return sum(1 for p in report["pairs"] if p["source"] == source and p["bin"] == bin_ and p["errors"].get("pair"))


def total(report: dict, source: str, bin_: str) -> int:
    return sum(1 for p in report["pairs"] if p["source"] == source and p["bin"] == bin_)


def mean_ci(v: dict[str, tuple[float, str]], scale: float = 1.0, digits: int = 2) -> str:
    if not v:
        return "–"
    a = [x * scale for x, _ in v.values()]
    d = paired_difference(a, [0.0] * len(a), True, groups=[c for _, c in v.values()])
    return f"{d.mean:.{digits}f} [{d.low:.{digits}f}, {d.high:.{digits}f}]"


def diff(a: dict, b: dict, scale: float = 1.0, digits: int = 2, higher: bool = True):
    keys = sorted(set(a) & set(b))
    if not keys:
        return None, "–"
    d = paired_difference([a[k][0] * scale for k in keys], [b[k][0] * scale for k in keys], higher,
                          groups=[a[k][1] for k in keys])
    return d, f"{d.mean:+.{digits}f} [{d.low:+.{digits}f}, {d.high:+.{digits}f}] {d.wins}/{d.losses}"


def n_str(v: dict) -> str:
    return f"{len(v)} ({len({c for _, c in v.values()})})"


def turns(issue: dict, main: dict, source: str, goals: list[str]) -> list[str]:
    lines = [f"### Turns, {LABELS[source]} (`{source}`)", "",
             f"Car PSNR (dB), L1 and flat colour (%) on the car's target pixels; issue-time `{ISSUE_TURN}`, main "
             f"`{MAIN_TURN}` (main `photo:auto` beside it). n = pairs scored (distinct cars); missed = pairs whose "
             "source scene had no object matching the target car (IoU < 0.5).", "",
             "| bin | n issue | n main | missed issue / main | PSNR issue-time | PSNR main | PSNR main photo:auto "
             "| main - issue PSNR [car CI] w/l | L1 issue-time | L1 main | main - issue L1 [car CI] w/l "
             "| flat % issue-time | flat % main | main - issue flat (points) |",
             "|" + "---|" * 14]
    for b in BINS:
        pi, pm = values(issue, source, b, ISSUE_TURN, "car", "psnr"), values(main, source, b, MAIN_TURN, "car", "psnr")
        pa = values(main, source, b, "photo:auto", "car", "psnr")
        li, lm = values(issue, source, b, ISSUE_TURN, "car", "l1"), values(main, source, b, MAIN_TURN, "car", "l1")
        fi, fm = values(issue, source, b, ISSUE_TURN, "car", "flat"), values(main, source, b, MAIN_TURN, "car", "flat")
        d, ds = diff(pm, pi)
        _, dl = diff(lm, li, digits=4, higher=False)
        _, df = diff(fm, fi, scale=100, digits=1, higher=False)
        lines.append(f"| {b} | {n_str(pi)} | {n_str(pm)} | {missed(issue, source, b)} / {missed(main, source, b)} "
                     f"| {mean_ci(pi)} | {mean_ci(pm)} | {mean_ci(pa)} | {ds} | {mean_ci(li, digits=4)} "
                     f"| {mean_ci(lm, digits=4)} | {dl} | {mean_ci(fi, 100, 1)} | {mean_ci(fm, 100, 1)} | {df} |")
        if source == "oracle" and b != "turn 15":
            ok = d is not None and d.mean >= 2.0 and d.low > 0
            goals.append(f"| turn PSNR, {b}, oracle: main - issue-time >= +2 dB, interval excludes 0 | "
                         f"{ds} (lower bound {d.low:+.2f}) | **{'met' if ok else 'not met'}** |")
            over = sum(1 for x, _ in fm.values() if x >= 0.10)
            fmean = 100 * float(np.mean([x for x, _ in fm.values()]))
            goals.append(f"| flat colour, {b}, oracle: main < 10 % | {fmean:.1f} % (issue-time "
                         f"{100 * float(np.mean([x for x, _ in fi.values()])):.1f} %); {over} of {len(fm)} pairs "
                         f">= 10 % | **{'met' if fmean < 10.0 else 'not met'}** |")
    lines += ["", "Context: the 2D paste (`2d`) minus each run's car PSNR (same pairs), and the whole change "
              "(car + vacated + shadow) PSNR:", "",
              "| bin | 2d - issue-time | 2d - main | changed PSNR issue-time | changed PSNR main | main - issue changed |",
              "|---|---|---|---|---|---|"]
    for b in BINS:
        pi, pm = values(issue, source, b, ISSUE_TURN, "car", "psnr"), values(main, source, b, MAIN_TURN, "car", "psnr")
        qi, qm = values(issue, source, b, "2d", "car", "psnr"), values(main, source, b, "2d", "car", "psnr")
        ci, cm = (values(issue, source, b, ISSUE_TURN, "changed", "psnr"),
                  values(main, source, b, MAIN_TURN, "changed", "psnr"))
        lines.append(f"| {b} | {diff(qi, pi)[1]} | {diff(qm, pm)[1]} | {mean_ci(ci)} | {mean_ci(cm)} "
                     f"| {diff(cm, ci)[1]} |")
    return lines + [""]


def deletes(issue: dict, main: dict, source: str, goals: list[str]) -> list[str]:
    b = "delete"
    lines = [f"### Deletes, {LABELS[source]} (`{source}`)", "",
             "PSNR and L1 on the vacated region plus the shadow band; darkening = 1 - mean luma of the shadow band's "
             "road / mean luma of the surrounding road ring (the method's picture), in %.", ""]
    ref = {}
    for p in main["pairs"]:
        if p["source"] == source and p["bin"] == b and p.get("reference"):
            ref[p["key"]] = p["reference"]
    if ref:
        t = [r["target"] for r in ref.values() if r["target"] is not None and math.isfinite(r["target"])]
        s = [r["source"] for r in ref.values() if r["source"] is not None and math.isfinite(r["source"])]
        lines += [f"Target render's darkening {100 * np.mean(t):.1f} %; the input's (shadow still there) "
                  f"{100 * np.mean(s):.1f} % (means over the {len(t)} of {len(ref)} pairs whose shadow band has road "
                  "pixels and a ring; darkening is undefined for the others and left out of every darkening mean).", ""]
    lines += ["| code | method | n (cars) | missed | PSNR | L1 | darkening % | n darkening |", "|---|---|---|---|---|---|---|---|"]
    methods_i = [m for m in OLD_FILLS if values(issue, source, b, m, "hole", "psnr")]
    methods_m = [m for m in ("photo:auto", "photo:telea", "photo:patchmatch", "generator", "photo:rays",
                             "photo:learnt", "2d") if values(main, source, b, m, "hole", "psnr")]
    for code, rep, ms in (("issue-time", issue, methods_i), ("main", main, methods_m)):
        for m in ms:
            v = values(rep, source, b, m, "hole", "psnr")
            lines.append(f"| {code} | {m} | {n_str(v)} | {missed(rep, source, b)} | {mean_ci(v)} "
                         f"| {mean_ci(values(rep, source, b, m, 'hole', 'l1'), digits=4)} "
                         f"| {mean_ci(values(rep, source, b, m, 'hole', 'darkening'), 100, 1)} "
                         f"| {len(values(rep, source, b, m, 'hole', 'darkening'))} |")
    if not methods_i:
        return lines + [""]
    best = max(methods_i, key=lambda m: np.mean([x for x, _ in values(issue, source, b, m, "hole", "psnr").values()]))
    bv = values(issue, source, b, best, "hole", "psnr")
    lines += ["", f"Best issue-time fill here: `{best}` ({np.mean([x for x, _ in bv.values()]):.2f} dB).", "",
              "| main method | - best issue-time fill, PSNR [car CI] w/l | - issue-time photo:auto | - issue-time "
              "photo:telea | - issue-time photo:patchmatch | darkening main - issue-time photo:auto (points) |",
              "|---|---|---|---|---|---|"]
    for m in methods_m:
        mv = values(main, source, b, m, "hole", "psnr")
        d, ds = diff(mv, bv)
        row = [m, ds] + [diff(mv, values(issue, source, b, o, "hole", "psnr"))[1]
                         for o in ("photo:auto", "photo:telea", "photo:patchmatch")]
        row.append(diff(values(main, source, b, m, "hole", "darkening"),
                        values(issue, source, b, "photo:auto", "hole", "darkening"), 100, 1, higher=False)[1])
        lines.append("| " + " | ".join(row) + " |")
        if source == "oracle" and m in ("photo:rays", "photo:learnt"):
            ok = d is not None and d.mean >= 2.0 and d.low > 0
            goals.append(f"| delete PSNR, oracle: main `{m}`{' (default)' if m == 'photo:rays' else ' (option)'} - best "
                         f"issue-time fill (`{best}`) >= +2 dB, interval excludes 0 | {ds} | **{'met' if ok else 'not met'}** |")
            dk = values(main, source, b, m, "hole", "darkening")
            dm = 100 * float(np.mean([x for x, _ in dk.values()]))
            goals.append(f"| residual darkening, oracle: main `{m}` < 5 % | {dm:.1f} % [car CI {mean_ci(dk, 100, 1)}] "
                         f"| **{'met' if dm < 5.0 else 'not met'}** |")
    return lines + [""]


def main_() -> int:
    reports = [load(p) for p in sys.argv[1:]]
    goals = ["| goal | measured | verdict |", "|---|---|---|"]
    out = []
    pairs = [(reports[0], reports[1])] + ([(reports[2], reports[3])] if len(reports) == 4 else [])
    for issue, main in pairs:
        for source in main["info"]["sources"]:
            if source not in issue["info"]["sources"]:
                continue
            out += [f"## Source scene `{source}`: {LABELS[source]}", ""]
            out += turns(issue, main, source, goals)
            out += deletes(issue, main, source, goals)
    print("\n".join(["## Goals (oracle, PLAN.md's rules)", "", *goals, "", *out]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main_())
