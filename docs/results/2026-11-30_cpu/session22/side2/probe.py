"""Session 22 side2: ``sdn3d-bench`` (its arguments follow) run with the code on PYTHONPATH, recording each car's body
examples as the photo appearance's paint decision sees them (``transfer._part_examples``): per target car of the
tree and car of its scene, once, the examples' CIE Lab, their :func:`transfer._part_features` and their lamp part
(``_lamp_band(..., corners=False)``), saved with ``torch.save`` to $RECORD at the end. With $KEYS (comma-separated
substrings of pair keys) only those pairs are run; with $CAPTURE the turn pairs' pictures of ``photo:rays`` (uint8)
and targets are saved there too.

    cd CODE && RECORD=rec.pt KEYS=0018/clone/00024_13007 CAPTURE=pics.pt PYTHONPATH=CODE/src OMP_NUM_THREADS=1 \\
        /work/main/.venv/bin/python probe.py counterfactual=true data.root=TREE output_dir=OUT examples=0 threads=1 \\
        "counterfactual_kinds=[turn]" "counterfactual_sources=[oracle]" "counterfactual_fills=[rays]"
"""

from __future__ import annotations

import atexit
import dataclasses
import os
import runpy
import sys

import torch

import sdn3d.editing.photo.transfer as T
import sdn3d.evaluation.counterfactual as cf
from sdn3d.editing.photo.recolor import srgb_to_lab
from sdn3d.meshes.parts import Part

KEYS = [k for k in os.environ.get("KEYS", "").split(",") if k]
RECORDS: dict[str, dict] = {}
PICTURES: dict[str, dict] = {}
CURRENT: dict = {}
_part_examples, _run, _evaluate, _score, _psnr = (T._part_examples, cf.run_counterfactual, cf.evaluate_target,
                                                  cf._score_pair, cf._psnr_l1)


def part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, *rest):
    """``transfer._part_examples``, recording the body examples it decides the paint on."""
    name = f"{CURRENT.get('target')}|{CURRENT.get('source')}|{int(before.instance_id[b])}"
    settings = rest[-1]  # main's code passes (settings), the branch's (road, settings)
    ex = visible_px[(src.frags.mesh_at(visible_px) == s_mesh) & (parts_src[visible_px] >= 0)]
    if name not in RECORDS and len(ex):
        _, vid, bary, normal = T._surface(src, ex)
        tri = src.verts[torch.full((len(ex),), s_mesh, dtype=torch.long)[:, None], vid]
        point = T.sum3(bary[..., None] * tri, 1)
        good = T._view_cos(point, normal) >= settings.min_view_cos
        body = good & (parts_src[ex] == int(Part.BODY))
        feature = T._part_features(before, b, point[body], normal[body])
        RECORDS[name] = {"lab": srgb_to_lab(img_flat[ex[body]].double().float()), "feature": feature,
                         "band": T._lamp_band(before, b, feature, corners=False), "px": ex[body],
                         "template": int(before.template_id[b]), "visible": visible_px.clone(),
                         "image": (img_flat.clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8)}
    return _part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, *rest)


def run(index, records, models, settings, progress=None):
    if KEYS:
        index = dataclasses.replace(index, pairs=tuple(p for p in index.pairs if any(k in p.key for k in KEYS)))
    return _run(index, records, models, settings, progress)


def evaluate(pairs, record, index, models, settings):
    CURRENT.update(target=pairs[0].key.split()[0], source=",".join(settings.sources))
    return _evaluate(pairs, record, index, models, settings)


def score(result, pair, scene, iid, centre, image, target, masks, *a, **k):
    CURRENT.update(pair=pair.key, target_image=target, masks=masks, image=image)
    return _score(result, pair, scene, iid, centre, image, target, masks, *a, **k)


def psnr(pred, target, mask):
    key = CURRENT.get("pair")
    if os.environ.get("CAPTURE") and key is not None and key not in PICTURES:
        PICTURES[key] = {"picture": (pred.clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8),
                         "target": (CURRENT["target_image"].clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8),
                         "input": (CURRENT["image"].clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8),
                         "car": CURRENT["masks"]["target_mask"].bool()}
    return _psnr(pred, target, mask)


def save() -> None:
    torch.save(RECORDS, os.environ["RECORD"])
    if os.environ.get("CAPTURE"):
        torch.save(PICTURES, os.environ["CAPTURE"])


atexit.register(save)
T._part_examples, cf.run_counterfactual, cf.evaluate_target, cf._score_pair, cf._psnr_l1 = (
    part_examples, run, evaluate, score, psnr)
sys.argv = ["sdn3d-bench", *sys.argv[1:]]
runpy.run_module("sdn3d.cli.bench", run_name="__main__")
