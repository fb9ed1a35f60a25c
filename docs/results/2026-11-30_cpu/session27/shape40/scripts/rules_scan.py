"""rules_scan.py PREFIX SEEDS: offline scan of template rules among the fine fits spy.sh recorded (main's fits, fit on
ground-truth masks + boxes, an oracle; the truth only scores): for each tie width and weight, among the fits within
the tie of the best loss facing the recorded winner's way (within 30 degrees, same border test), the one with the
lowest ``loss / best + k * mismatch`` (``k`` 1e9: the mismatch alone), the mismatch the summed ``|log d - log d_t|``
over the dimensions named (1, 2: height and width; 0, 1, 2: with the length). Branch-like minus main template
accuracy per view, paired bootstrap 95 % interval. Run with main's library on PYTHONPATH:

    PYTHONPATH=CODE/src python rules_scan.py /tmp/s27data/shape40/spy_main 31,33,35,37
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np

from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS, TEMPLATE_NAMES

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from views import boot, view  # noqa: E402

TYP = np.log(np.array([TEMPLATE_DIMENSIONS[n] for n in TEMPLATE_NAMES]))


def load(prefix: str, seeds: list[str]) -> list[tuple[dict, dict]]:
    data = []
    for s in seeds:
        table = json.load(open(f"{prefix}_{s}.json"))["objects"]["fit, oracle: ground-truth masks + boxes"]
        records = json.load(open(f"{prefix}_{s}.spy.json"))["records"]
        data += [(o, r) for o, r in zip(table, records, strict=True) if r["fitted"]]
    return data


def rule(data, tie: float, k: float, dims: tuple[int, ...]) -> list[tuple[str, float]]:
    out = []
    for o, r in data:
        i = r["won"]
        loss, ry, inward = np.array(r["loss"]), np.array(r["ry"]), np.array(r["inward"])
        template, d = np.array(r["template"]), np.log(np.array(r["dims"]))
        finite = np.isfinite(loss)
        best = loss[finite].min()
        ok = finite & (np.cos(ry - ry[i]) > math.cos(math.radians(30))) & (inward == inward[i])
        ok &= loss <= best * (1 + tie)
        ok[i] = True
        c = np.where(ok)[0]
        mismatch = sum(np.abs(d[c, q] - TYP[template[c], q]) for q in dims)
        score = mismatch if k >= 1e9 else loss[c] / best + k * mismatch
        j = c[np.argmin(score)]
        out.append((view(o), float(template[j] == o["true_template"]) - float(template[i] == o["true_template"])))
    return out


def main() -> None:
    data = load(sys.argv[1], sys.argv[2].split(","))
    print("| tie | k | dims | end on pp [95 %] | oblique | side | all |")
    print("|---|---|---|---|---|---|---|")
    for tie in (0.1, 0.2, 0.3, 0.5):
        for k in (0.5, 1.0, 2.0, 1e9):
            for dims in ((1, 2), (0, 1, 2)):
                res = rule(data, tie, k, dims)
                cells = []
                for v in ("end on", "oblique", "side", "all"):
                    d = np.array([x for vv, x in res if v == "all" or vv == v])
                    lo, hi = boot(d)
                    cells.append(f"{100 * d.mean():+.1f} [{100 * lo:+.1f}, {100 * hi:+.1f}]")
                print(f"| {tie} | {'alone' if k >= 1e9 else k} | {dims} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
