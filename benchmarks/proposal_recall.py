"""Recall of the semantic branch's object proposals on a synthetic (Virtual KITTI-format) part (issue 18).

    python benchmarks/proposal_recall.py --semantic RUN/checkpoints/last.ckpt --data-root DATA [--part test]
                                         [--work-size 312 96] [--threads 2] [--out result.json]

What it measures, on every frame of ``--part`` (default ``test``; nothing here selects anything):

- each frame is read at the data's own size (624x192 for the synthetic data); the semantic branch runs at
  ``--work-size`` (default 312x96: the size the demo and its editing benchmark de-render at, and the demo
  recipes' training size) and its instance map is brought back to the frame's size (nearest neighbour);
- the evaluated objects are the frame's annotated Car and Van instances with more than 256 visible pixels
  (the paper's filter, at 624x192; :data:`sdn3d.evaluation.proposal_recall.PAPER_MIN_PIXELS`);
- an object is found when a proposal covers it with IoU >= 0.5 (one proposal finds one object):
  ``recall`` (any class), ``recall_class_aware``, per class, ``precision`` and the mean IoU of found objects
  (:mod:`sdn3d.evaluation.proposal_recall`).

Two references are measured on the same objects, so the figure has a floor and a ceiling beside it:

- ``components_predicted``: connected components of the branch's own Car / Van *semantic* pixels, one
  proposal per component (what the semantic map gives without the instance head);
- ``components_gt``: connected components of the ground-truth Car / Van pixels (an oracle: the best a
  method that cannot split touching vehicles could do; below 1 where vehicles touch or occlude each other).
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
import torch
from scipy import ndimage

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.evaluation.proposal_recall import PAPER_MIN_PIXELS, predictor_recall  # noqa: E402
from sdn3d.io import write_json_atomic  # noqa: E402
from sdn3d.labels import INSTANCE_DIVISOR  # noqa: E402
from sdn3d.semantic.predict import SemanticPredictor  # noqa: E402


def components(label: torch.Tensor, things: list[int]) -> torch.Tensor:
    """``(H, W)`` instance map: one id per 8-connected component of each thing class's pixels."""
    out = np.zeros(tuple(label.shape), dtype=np.int64)
    lab = label.numpy()
    for c in things:
        comp, n = ndimage.label(lab == c, structure=np.ones((3, 3)))
        out[comp > 0] = c * INSTANCE_DIVISOR + comp[comp > 0]
    return torch.from_numpy(out)


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--semantic", required=True, help="semantic checkpoint or inference export")
    p.add_argument("--data-root", required=True)
    p.add_argument("--part", default="test", choices=("train", "val", "test"))
    p.add_argument("--work-size", type=int, nargs=2, default=(312, 96), metavar=("W", "H"),
                   help="size the branch runs at (default: sdn3d-demo's render_size)")
    p.add_argument("--min-pixels", type=int, default=PAPER_MIN_PIXELS)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--out", default=None)
    args = p.parse_args(argv)
    torch.set_num_threads(args.threads)
    predictor = SemanticPredictor.from_checkpoint(args.semantic, image_size=tuple(args.work_size))
    source = synth_data_source(args.data_root)
    things = [c.id for c in source.class_list if c.has_instances]
    names = {c.id: c.name for c in source.class_list}
    records = load_split(source, args.part)
    t0 = time.perf_counter()

    def references(label: torch.Tensor, gt_semantic: torch.Tensor) -> dict:
        return {"components_predicted": components(label, things),
                "components_gt (oracle)": components(gt_semantic, things)}

    branch, refs = predictor_recall(records, predictor, args.min_pixels, references)
    result = {
        "semantic": str(Path(args.semantic).resolve()), "data_root": str(Path(args.data_root).resolve()),
        "part": args.part, "frames": len(records), "work_size_wh": list(predictor.image_size),
        "min_pixels": args.min_pixels, "instance_head": branch.summary(names),
        **{name: counts.summary(names) for name, counts in refs.items()},
        "seconds": round(time.perf_counter() - t0, 1),
        "machine": f"{platform.machine()} cpu, {args.threads} threads, torch {torch.__version__}",
        "how": "annotated Car/Van instances with > min_pixels visible pixels at the frame's size; found = a "
               "proposal with IoU >= 0.5 (greedy one-to-one); the branch runs at work_size_wh, its instance map "
               "resized back (nearest); sdn3d.evaluation.proposal_recall",
    }
    print(json.dumps(result, indent=2))
    if args.out:
        write_json_atomic(args.out, result)
    return result


if __name__ == "__main__":
    main()
