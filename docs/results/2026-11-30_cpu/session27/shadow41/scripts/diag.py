"""diag.py OUT_DIR BENCH_ARGS...: sdn3d-bench's counterfactual benchmark (as cf_bench.sh runs it: pass the same
overrides) with hooks that save, per delete pair and source scene, what the photo removal did (``fill='rays'``):
the input, the target (exact render without the car), photo:rays' output, the pair's masks (true shadow band, road
ring, vacated region, the car's true mask: ground truth, an oracle, used only to diagnose), the removed proposal's
mask, the hole before and after the shadow joined it, the shadow pieces, the search region (fitted footprint grown)
and the shadowed-road map. One ``OUT_DIR/<source>_<key>.npz`` per pair. Run with the code tree's src on PYTHONPATH,
OMP_NUM_THREADS=1, from that tree's root, e.g.
``PYTHONPATH=$T/src python diag.py /tmp/x counterfactual=true data.root=... counterfactual_sources=[semantic] ...``."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np
import torch

import sdn3d.editing.photo.transfer as tr
import sdn3d.evaluation.counterfactual as cf

OUT = Path(sys.argv[1])
OUT.mkdir(parents=True, exist_ok=True)
sys.argv = ["sdn3d-bench", *sys.argv[2:]]
CTX: dict = {}


def _np(x):
    return x.detach().cpu().numpy() if isinstance(x, torch.Tensor) else x


_vacated_hole = tr.vacated_hole


def vacated_hole(ids, gone, keep, settings):
    hole = _vacated_hole(ids, gone, keep, settings)
    if CTX.get("on") and "proposal" not in CTX["grab"]:
        CTX["grab"]["proposal"] = _np(tr.isin_ids(ids, gone) & (ids != 0))
        CTX["grab"]["hole_base"] = _np(hole)
    return hole


_rays = tr._rays_with_effects


def rays_with_effects(image, hole, objects_px, search, ring, road, settings, vanishing, ground_row=None, lab=None):
    if CTX.get("on") and "search" not in CTX["grab"]:
        CTX["grab"]["search"] = _np(search)
        CTX["grab"]["hole_in"] = _np(hole)
        CTX["grab"]["objects_px"] = _np(objects_px)
    return _rays(image, hole, objects_px, search, ring, road, settings, vanishing, ground_row, lab)


_pieces = tr.shadow_pieces


def shadow_pieces(dark, hole, reach, ground):
    out = _pieces(dark, hole, reach, ground)
    if CTX.get("on") and "pieces" not in CTX["grab"]:
        CTX["grab"]["dark"] = _np(dark)
        CTX["grab"]["hole_own"] = _np(hole)
        CTX["grab"]["pieces"] = _np(out)
    return out


_dark = cf.darkening


def darkening(image, band, ring):
    if CTX.get("on"):
        CTX["pictures"].append(_np(image))
        if len(CTX["pictures"]) == 3:  # target, source, then the first method (photo:rays): stop grabbing
            CTX["on"] = False
    return _dark(image, band, ring)


_score = cf._score_pair


def score_pair(result, pair, scene, iid, centre, image, target, masks, renderers, states, names, settings, road,
               cars, ring_px, models):
    delete = pair.kind == "delete"
    CTX.clear()
    CTX.update(on=delete, grab={}, pictures=[])
    _score(result, pair, scene, iid, centre, image, target, masks, renderers, states, names, settings, road, cars,
           ring_px, models)
    CTX["on"] = False
    if not delete or len(CTX["pictures"]) < 3:
        return
    band = masks["shadow"] & road
    ring = cf.road_ring(masks["shadow"], masks["vacated"], road, cars, ring_px)
    arrays = {k: v for k, v in CTX["grab"].items()}
    arrays |= {"target": CTX["pictures"][0], "input": CTX["pictures"][1], "output": CTX["pictures"][2],
               "band": _np(band), "ring": _np(ring), "vacated": _np(masks["vacated"]),
               "car": _np(masks["target_mask"]), "road": _np(road)}
    np.savez_compressed(OUT / f"{result.source}_{result.key}.npz".replace("/", "+").replace(" ", "_"), **arrays)


tr.vacated_hole = vacated_hole
tr._rays_with_effects = rays_with_effects
tr.shadow_pieces = shadow_pieces
cf.darkening = darkening
cf._score_pair = score_pair
runpy.run_module("sdn3d.cli.bench", run_name="__main__")
