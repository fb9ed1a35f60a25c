"""Session 23 front: ``sdn3d-bench`` (its arguments follow) run with the code on PYTHONPATH, recording for every turn
pair of the photo appearance (``photo:rays``) where the car's target-pixel error lies: per (source code of the
per-pixel source map, car part of the part map) the pixel count and the summed squared error (mean over RGB), and
the pair's crops (input, target, picture, source map, part map; uint8 / int8) for figures. Saved with ``torch.save``
to $RECORD at the end (``{pair key: {"source", "bin", "cells": {(code, part): [pixels, sse]}, "crops": {...}}}``).

    cd CODE && RECORD=rec.pt PYTHONPATH=CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \\
        probe.py counterfactual=true data.root=TREE output_dir=OUT examples=0 threads=1 \\
        "counterfactual_kinds=[turn]" "counterfactual_sources=[oracle]" "counterfactual_fills=[rays]"
"""

from __future__ import annotations

import atexit
import os
import runpy

import torch

import sdn3d.editing.appearance as appearance
import sdn3d.evaluation.counterfactual as cf

RECORDS: dict[str, dict] = {}
LAST: dict[str, object] = {}
_render, _score = appearance.render_photo, cf._score_pair


def render(*args, **kwargs):
    """``render_photo``, keeping its result for the pair being scored."""
    result = _render(*args, **kwargs)
    LAST["result"] = result
    return result


def score(result, pair, scene, iid, centre, image, target, masks, *args, **kwargs):
    """``_score_pair``, then the error of the photo appearance's picture by source code and part on the car's pixels."""
    LAST.clear()
    _score(result, pair, scene, iid, centre, image, target, masks, *args, **kwargs)
    drawn = LAST.get("result")
    if pair.kind == "delete" or drawn is None or "photo:rays" not in result.metrics:
        return
    car = masks["target_mask"]
    picture = drawn.image.float().clamp(0, 1)
    err = ((picture - target.float()) ** 2).mean(0)[car]
    codes = drawn.source[car].long()
    parts = (drawn.parts[car].long() if drawn.parts is not None else torch.full_like(codes, -1))
    cells = {}
    for c, p in torch.stack([codes, parts], 1).unique(dim=0).tolist():
        here = (codes == c) & (parts == p)
        cells[(c, p)] = [int(here.sum()), float(err[here].sum())]
    ys, xs = car.nonzero(as_tuple=True)
    y0, y1 = max(0, int(ys.min()) - 12), min(car.shape[0], int(ys.max()) + 13)
    x0, x1 = max(0, int(xs.min()) - 12), min(car.shape[1], int(xs.max()) + 13)

    def crop(t):
        return t[..., y0:y1, x0:x1].clone()

    def u8(t):
        return (crop(t.float()).clamp(0, 1) * 255).round().to(torch.uint8)

    RECORDS[f"{result.source}|{pair.key}"] = {
        "source": result.source, "bin": cf.pair_bin(pair), "cells": cells,
        "psnr": result.metrics["photo:rays"]["car"]["psnr"],
        "crops": {"input": u8(image), "target": u8(target), "picture": u8(picture), "car": crop(car),
                  "source": crop(drawn.source), "parts": crop(drawn.parts) if drawn.parts is not None else None}}


def save() -> None:
    torch.save(RECORDS, os.environ["RECORD"])


appearance.render_photo, cf._score_pair = render, score
atexit.register(save)
runpy.run_module("sdn3d.cli.bench", run_name="__main__")
