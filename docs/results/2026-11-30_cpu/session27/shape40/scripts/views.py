"""Template accuracy and length error of pose_table.py's objects split by view (end on, oblique, side).

    python views.py MAIN.json [MAIN2.json ...] [--branch BR.json ...] [--rows ...] [--out table.md]

The view of each object is the angle between its true axis and the camera ray through its true centre (the
truth, an oracle, only scores): end on within ``END`` degrees, side beyond ``SIDE``, oblique between. Per row and
view: objects, template accuracy (%), median length error (m), and for end-on objects of ``gt_fit`` where the
winning template came from (the fine hypothesis: the prediction's template or a search start's). With
``--branch`` (the same trees in the same order) the paired differences branch - main per view: template accuracy
(pp) and length error (m, mean), 10,000-resample paired bootstrap 95 % interval (seed 0), wins/losses; on the
predicted row the objects matched in both.
"""

from __future__ import annotations

import argparse
import json
import math
from collections import Counter

import numpy as np

END, SIDE = 25.0, 65.0
NAMES = ("sedan", "hatchback", "wagon", "suv", "pickup", "van", "minibus", "bus")
ROWS = {"gt_branch": "branch, oracle: ground-truth masks", "gt_fit": "fit, oracle: ground-truth masks + boxes",
        "pred_fit": "fit, predicted proposals"}


def view_angle(o: dict) -> float:
    """Degrees between the object's axis (heading ``(cos ry, -sin ry)`` in x, z) and the ray through its centre."""
    x, z = o["true_xz"]
    ry = o["true_ry"]
    c = abs(math.cos(ry) * x - math.sin(ry) * z) / math.hypot(x, z)
    return math.degrees(math.acos(min(1.0, c)))


def view(o: dict) -> str:
    a = view_angle(o)
    return "end on" if a <= END else "side" if a >= SIDE else "oblique"


def load(paths: list[str]) -> dict[str, list[dict]]:
    out: dict[str, list[dict]] = {}
    for p in paths:
        objects = json.load(open(p))["objects"]
        tree = p.split("/")[-1]
        for name, rows in objects.items():
            out.setdefault(name, []).extend({**r, "tree": tree} for r in rows)
    return out


def boot(d: np.ndarray, seed: int = 0) -> tuple[float, float]:
    if len(d) == 0:
        return (math.nan, math.nan)
    rng = np.random.default_rng(seed)
    means = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return float(np.percentile(means, 2.5)), float(np.percentile(means, 97.5))


def level_table(data: dict[str, list[dict]], label: str) -> list[str]:
    lines = [f"### {label}", "", "| row | view | objects | template acc % | majority floor % | length err median m |"
             " length err mean m | flips % |", "|---|---|---|---|---|---|---|---|"]
    for name in ROWS.values():
        rows = data.get(name)
        if not rows:
            continue
        for v in ("end on", "oblique", "side", "all"):
            sel = [r for r in rows if v == "all" or view(r) == v]
            if not sel:
                continue
            floor = 100 * max(Counter(r["true_template"] for r in sel).values()) / len(sel)
            lines.append(f"| {name} | {v} | {len(sel)} | {100 * np.mean([r['template_ok'] for r in sel]):.1f} | "
                         f"{floor:.1f} | {np.median([r['length'] for r in sel]):.3f} | "
                         f"{np.mean([r['length'] for r in sel]):.3f} | "
                         f"{100 * np.mean([r['yaw_deg'] > 90 for r in sel]):.1f} |")
    return lines + [""]


def sources(data: dict[str, list[dict]]) -> list[str]:
    """End-on gt_fit objects: where the winning template came from, against the branch's template and the truth."""
    fit, branch = data.get(ROWS["gt_fit"]), data.get(ROWS["gt_branch"])
    if not fit:
        return []
    lines = ["### End-on cars, fit on ground-truth masks + boxes (oracle): where the template came from", "",
             "| winner | objects | fit template right | branch template right |", "|---|---|---|---|"]
    groups: dict[str, list[tuple[dict, dict | None]]] = {}
    for j, r in enumerate(fit):
        if view(r) != "end on":
            continue
        b = branch[j] if branch else None
        h = r.get("hypothesis")
        g = ("not fitted" if h is None or h.startswith("not") else "search" if h.startswith("search")
             else "prediction, its flip or mirror")
        groups.setdefault(g, []).append((r, b))
    for g, items in sorted(groups.items()):
        br = [b["template_ok"] for _, b in items if b is not None]
        lines.append(f"| {g} | {len(items)} | {sum(r['template_ok'] for r, _ in items)} | "
                     f"{sum(br) if br else '-'} |")
    conf = Counter((NAMES[r["true_template"]], NAMES[r["template"]] if r["template"] >= 0 else "none")
                   for r in fit if view(r) == "end on")
    lines += ["", "End on, truth -> fit template (count): " + ", ".join(f"{a}->{b} {n}" for (a, b), n in
                                                                         conf.most_common())]
    return lines + [""]


def paired(main: dict[str, list[dict]], branch: dict[str, list[dict]]) -> list[str]:
    lines = ["### Paired, branch - main (per object; predicted: matched in both)", "",
             "| row | view | objects | template acc pp [95 %] | wins/losses | length err mean m [95 %] |"
             " better/worse (>1 cm) | flips main -> branch |", "|---|---|---|---|---|---|---|---|"]
    for key, name in ROWS.items():
        if key == "gt_branch" or name not in main or name not in branch:
            continue
        m, b = main[name], branch[name]
        assert all(x["id"] == y["id"] and x["frame"] == y["frame"] for x, y in zip(m, b, strict=True))
        for v in ("end on", "oblique", "side", "all"):
            pairs = [(x, y) for x, y in zip(m, b, strict=True) if (v == "all" or view(x) == v)
                     and (key != "pred_fit" or (x["matched"] and y["matched"]))]
            if not pairs:
                continue
            dt = np.array([float(y["template_ok"]) - float(x["template_ok"]) for x, y in pairs])
            dl = np.array([y["length"] - x["length"] for x, y in pairs])
            lo, hi = boot(dt)
            llo, lhi = boot(dl)
            flips = (sum(x["yaw_deg"] > 90 for x, _ in pairs), sum(y["yaw_deg"] > 90 for _, y in pairs))
            lines.append(f"| {name} | {v} | {len(pairs)} | {100 * dt.mean():+.1f} [{100 * lo:+.1f}, {100 * hi:+.1f}]"
                         f" | {int((dt > 0).sum())}/{int((dt < 0).sum())} | {dl.mean():+.3f} [{llo:+.3f}, {lhi:+.3f}]"
                         f" | {int((dl < -0.01).sum())}/{int((dl > 0.01).sum())} | {flips[0]} -> {flips[1]} |")
    return lines + [""]


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("main", nargs="+")
    p.add_argument("--branch", nargs="*", default=None)
    p.add_argument("--out", default=None)
    p.add_argument("--changed", default=None, help="write the cars whose template changed (per row) here")
    a = p.parse_args()
    m = load(a.main)
    lines = level_table(m, "main") + sources(m)
    if a.branch:
        b = load(a.branch)
        lines += level_table(b, "branch") + sources(b) + paired(m, b)
        if a.changed:
            with open(a.changed, "w") as f:
                for name in (ROWS["gt_fit"], ROWS["pred_fit"]):
                    for x, y in zip(m.get(name, []), b.get(name, []), strict=True):
                        if x["template"] != y["template"]:
                            f.write(f"{name} | {x['tree']} {x['frame']} {x['id']} | {view(x)} | truth "
                                    f"{NAMES[x['true_template']]} | main {NAMES[x['template']]} | branch "
                                    f"{NAMES[y['template']]} | box {x['box']} | {x['pixels']} px\n")
    text = "\n".join(lines)
    print(text)
    if a.out:
        open(a.out, "w").write(text + "\n")


if __name__ == "__main__":
    main()
