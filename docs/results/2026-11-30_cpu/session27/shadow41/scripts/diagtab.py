"""diagtab.py DIR [DIR ...] > table.md: where the residual darkening of predicted deletes lies (diag.py's dumps).

Per pair: the shadow band's darkening of the output minus the target's (the exact render without the car), summed
per band pixel (``(1 - Y/ring mean)/|band|``, output minus target: the shares add up to the difference) and split by
where the pixel lies, in this order: ``hole`` (main's hole before the shadow joined: the proposal's pixels grown and
the band below them, filled by the rays), ``own`` (the shadow the search region found, joined to the hole), ``pieces``
(shadow pieces past the hole, Telea), ``object`` (another object's mask: kept), ``dark out`` (shadowed road by the
rays' test, outside the search region: not looked for), ``light in`` / ``light out`` (not shadowed road by that test,
inside / outside the search region grown by 3 px). Also: the share of the band inside the grown search region, the
proposal's missing bottom rows (median over the car's columns of the true car's lowest row minus the proposal's;
true car = the pair's vacated mask, ground truth, an oracle used only to diagnose) and the proposal's IoU with it.
Figures in darkening points (%)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.ndimage import binary_dilation

LUMA = np.array([0.2126, 0.7152, 0.0722])
CATS = ("hole", "own", "pieces", "object", "dark out", "light in", "light out")


def luma(img: np.ndarray) -> np.ndarray:
    return np.tensordot(LUMA, np.clip(img, 0, 1), axes=(0, 0))


def grow(mask: np.ndarray, r: int) -> np.ndarray:
    return binary_dilation(mask, np.ones((2 * r + 1, 2 * r + 1), bool))


def analyse(path: Path) -> dict | None:
    z = np.load(path)
    if "search" not in z or "pieces" not in z:
        return None
    band, ring = z["band"], z["ring"]
    if not band.any() or not ring.any():
        return None
    yo, yt = luma(z["output"]), luma(z["target"])
    n = band.sum()
    exc = ((1 - yo / yo[ring].mean()) - (1 - yt / yt[ring].mean())) / n
    search = grow(z["search"], 3)
    left = band.copy()
    out = {"key": path.stem, "n": int(n), "dark": float((1 - yo[band].mean() / yo[ring].mean()) * 100),
           "truth": float((1 - yt[band].mean() / yt[ring].mean()) * 100)}
    masks = {"hole": z["hole_base"], "own": z["hole_own"], "pieces": z["pieces"], "object": z["objects_px"],
             "dark out": z["dark"] & ~search, "light in": search, "light out": np.ones_like(band)}
    for cat in CATS:
        take = left & masks[cat]
        out[cat] = float(exc[take].sum() * 100)
        out[cat + " px"] = int(take.sum())
        left &= ~take
    out["in search"] = float((band & search).sum() / n)
    car, prop = z["vacated"], z["proposal"]
    cols = np.nonzero(car.any(0) & prop.any(0))[0]
    h = car.shape[0]
    rows = np.arange(h)[:, None]
    low_car = np.where(car, rows, -1).max(0)
    low_prop = np.where(prop, rows, -1).max(0)
    out["miss rows"] = float(np.median(low_car[cols] - low_prop[cols])) if len(cols) else float("nan")
    out["car h"] = int(car.any(1).sum())
    out["iou"] = float((car & prop).sum() / max((car | prop).sum(), 1))
    # The band's pixels that lie below the proposal's lowest row in their column, or in columns it does not reach.
    below = band & ((rows > low_prop[None]) | (low_prop[None] < 0))
    out["band below prop"] = float(below.sum() / n)
    return out


def main() -> int:
    rows = [r for d in sys.argv[1:] for p in sorted(Path(d).glob("*.npz")) if (r := analyse(p))]
    head = ["pair", "band px", "darkening", "truth's", "excess"] + list(CATS) + [
        "band in search", "band below proposal", "missed bottom rows / car h", "IoU"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    tot = {c: 0.0 for c in CATS}
    for r in rows:
        ex = sum(r[c] for c in CATS)
        for c in CATS:
            tot[c] += r[c] / len(rows)
        cells = [r["key"], str(r["n"]), f"{r['dark']:.2f}", f"{r['truth']:.2f}", f"{ex:+.2f}"]
        cells += [f"{r[c]:+.2f} ({r[c + ' px']})" for c in CATS]
        cells += [f"{r['in search']:.2f}", f"{r['band below prop']:.2f}", f"{r['miss rows']:.0f} / {r['car h']}",
                  f"{r['iou']:.2f}"]
        print("| " + " | ".join(cells) + " |")
    mean_ex = sum(tot.values())
    print("| **mean** | | " + f"{np.mean([r['dark'] for r in rows]):.2f} | {np.mean([r['truth'] for r in rows]):.2f} | "
          f"{mean_ex:+.2f} | " + " | ".join(f"{tot[c]:+.2f}" for c in CATS) + " | | | | |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
