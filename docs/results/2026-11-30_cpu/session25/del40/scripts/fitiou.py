"""fitiou.py CACHE RUN [CACHE RUN ...]: per delete / occluder-removed entry of each Table 1 photo run (dbench.py's
results.json and .dump npz), 3D-SDN minus 2D PSNR 'all' and the picked object's fit record (meta['fits']: the fit's
silhouette IoU with its mask, poor) from the run's de-render cache; then the mean difference by fit-IoU band.
Run with PYTHONPATH=<code>/src."""
import glob
import json
import sys

import numpy as np
import torch
from perentry import ci


def fits_of(cache: str) -> dict[tuple[str, str], dict[int, dict]]:
    out = {}
    for path in glob.glob(f"{cache}/*.pt"):
        scene = torch.load(path, weights_only=False)
        src = scene.meta.get("source", "").split("/")
        out[("/".join(src[1:3]) + " " + src[3], scene.meta.get("proposals"))] = {
            f["id"]: f for f in scene.meta.get("fits", [])}
    return out


def main(pairs: list[tuple[str, str]]) -> None:
    bands: dict[str, list[float]] = {}
    for cache, run in pairs:
        fits = fits_of(cache)
        proposals = "semantic" if run.endswith("semantic") else "gt"
        for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
            m = (e.get("metrics") or {}).get("photo") or {}
            if e["edit_kind"] not in ("delete", "occluder_removed") or "3d-sdn" not in m:
                continue
            d = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"]
            picks = np.load(f"{run}.dump/{e['index']:04d}.npz")["picks"].tolist()
            rec = fits.get((e["key"].split("->")[0], proposals), {})
            ious = [rec.get(p, {}).get("fit_iou") for p in picks]
            iou = min((i for i in ious if i is not None), default=None)
            band = "none" if iou is None else ("<0.6" if iou < 0.6 else "0.6-0.7" if iou < 0.7 else
                                              "0.7-0.8" if iou < 0.8 else ">=0.8")
            bands.setdefault(band, []).append(d)
            print(f"{run.split('/')[-1]:20s} {e['index']:4d} {e['edit_kind'][:8]:8s} d {d:+.3f} picks {picks} "
                  f"iou {ious}")
    for band, vals in sorted(bands.items()):
        print(f"== fit IoU {band}: 3D-2D PSNR all {ci(vals)}")


if __name__ == "__main__":
    main(list(zip(sys.argv[1::2], sys.argv[2::2], strict=True)))
