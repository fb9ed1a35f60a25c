"""rule.py MAIN_RUN:BRANCH_RUN [...] ROW: the merge rule of this folder's README on Table 1 photo runs (results.json of
session 11 semrain's dbench.py, paired per entry as session 18 pick's compare.py pairs them): per kind and pooled,
3D-SDN's PSNR all, branch minus main, mean to 5 decimals, 10,000-resample paired bootstrap 95 % interval (seed 0), and
whether the kind passes (ROW 'semantic': occluder removed needs mean > 0 and the interval not wholly below 0, every
other kind and the pooled all-kind figure the interval not wholly below 0 and the mean not below 0; ROW 'gt': the
latter test everywhere). Run with /work/main/.venv/bin/python."""
import json
import sys

import numpy as np


def load(run: str) -> dict:
    r = json.load(open(f"{run}/results.json"))
    out = {}
    for e in list(r["entries"].values())[0]:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m and "all" in m["3d-sdn"]:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"]["all"]["psnr"])
    return out


def main(pairs: list[list[str]], row: str) -> bool:
    diffs: dict[str, list[float]] = {"ALL": []}
    for base, new in pairs:
        a, b = load(base), load(new)
        for i in sorted(set(a) & set(b)):
            d = b[i][1] - a[i][1]
            diffs["ALL"].append(d)
            diffs.setdefault(a[i][0], []).append(d)
    ok = True
    for kind, values in diffs.items():
        d = np.asarray(values)
        boot = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
        lo, hi = np.percentile(boot, [2.5, 97.5])
        if row == "semantic" and kind == "occluder_removed":
            passed = d.mean() > 0 and hi >= 0
        else:
            passed = d.mean() >= 0 and hi >= 0
        ok &= bool(passed)
        print(f"{row} {kind:16s} mean {d.mean():+.5f} [{lo:+.5f}, {hi:+.5f}] {int((d > 1e-9).sum())}/"
              f"{int((d < -1e-9).sum())} (n {len(d)}) {'pass' if passed else 'FAIL'}")
    print(f"{row}: {'rule holds' if ok else 'rule fails'}")
    return ok


if __name__ == "__main__":
    main([p.split(":") for p in sys.argv[1:-1]], sys.argv[-1])
