"""Code-swap test of a trained textural branch (:mod:`sdn3d.evaluation.code_swap`) and its reconstruction quality.

    python benchmarks/code_swap.py --checkpoint RUN/checkpoints/last.ckpt --data-root DATA [--part test]
                                   [--size 312 96] [--frames N] [--threads 2] [--out result.json]

What it measures, on the frames of ``--part`` (a Virtual KITTI-format folder, e.g. the synthetic one) at
``--size`` (the size the generator was trained at):

- **code swap**: each frame is de-rendered with the ground-truth objects (the editing benchmark's oracle scene,
  :func:`sdn3d.data.scene_gt.scene_from_frame`) and its codes encoded by E (:func:`sdn3d.derender.encode_scene`);
  for pairs of objects A, B of one class with different colours (CIE76 Delta E >= 20 between their real mean
  colours), A gets B's code through the editing path (SetCode, scene_maps, G). Reported: the colour move of A
  towards B's colour (0 = no change, 1 = B's colour), the off-axis colour change, the silhouette change
  (1 - IoU of the pixels that read as A in the two renders), the leak of the change outside A. Means and
  medians over all pairs; the module doc of :mod:`sdn3d.evaluation.code_swap` defines each.
- **reconstruction**: PSNR / SSIM / L1 of G(E(image)) with the frame's ground-truth maps (as the training's
  test step) on whole images and on object pixels (``obj_*``), mean over frames. With ``--semantic`` and
  ``--geometric`` checkpoints also on the maps those branches predict (``reconstruction_predicted``: 3D-SDN's
  inputs, :mod:`sdn3d.predicted_maps`, cached in ``--map-cache``); object pixels are then the predicted objects'.

Prints one JSON object (and writes it to ``--out``). Use the checkpoint you would edit with (``last.ckpt``:
no selection on the test part).
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import torch

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.datasets import TexturalDataset  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import scene_from_frame  # noqa: E402
from sdn3d.data.sources import SourceConfig, load_split  # noqa: E402
from sdn3d.derender import encode_scene  # noqa: E402
from sdn3d.evaluation.code_swap import CodeSwapSettings, code_swap_frame, summarize  # noqa: E402
from sdn3d.evaluation.image_metrics import image_metrics  # noqa: E402
from sdn3d.io import write_json_atomic  # noqa: E402
from sdn3d.labels import INSTANCE_DIVISOR  # noqa: E402
from sdn3d.predicted_maps import build_predicted_maps  # noqa: E402
from sdn3d.textural.renderer import TexturalRenderer  # noqa: E402


def code_swap(renderer: TexturalRenderer, source: SourceConfig, part: str, frames: int | None,
              settings: CodeSwapSettings) -> dict:
    records = [r for r in load_split(source, part) if r.objects][:frames]
    generator = torch.Generator().manual_seed(settings.seed)
    results = []
    for record in records:
        frame = load_frame(record, source.image_size)
        scene = scene_from_frame(record, source.image_size, renderer.spec.code_dim)
        scene = encode_scene(scene, frame.image, renderer)
        results.append(code_swap_frame(scene, frame.image, renderer, settings, generator))
    return {"frames": len(records), **summarize(results, settings)}


@torch.no_grad()
def reconstruction(renderer: TexturalRenderer, source: SourceConfig, part: str, frames: int | None,
                   predicted: tuple[str, str, str] | None = None) -> dict:
    """Mean image metrics of G(E(image)) over ``part``; ``predicted = (semantic, geometric, cache_dir)``: on the
    maps those branches predict instead of the ground truth."""
    if predicted is None:
        dataset = TexturalDataset.from_source(source, part)
    else:
        records = load_split(source, part)
        cache = build_predicted_maps(records, source.image_size, predicted[0], predicted[1], predicted[2], part)
        dataset = TexturalDataset(records, source.image_size, source.class_list, predicted=cache)
    count = len(dataset) if frames is None else min(frames, len(dataset))
    sums: dict[str, list[float]] = {}
    for i in range(count):
        item = dataset[i]
        fake = renderer.reconstruct(item["image"][None], item["label"][None], item["instance_label_map"][None],
                                    item["boundary"][None], item["pose"][None], item["normal"][None]).clamp(0, 1)
        real = item["image"][None]
        metrics = {k: float(v) for k, v in image_metrics(fake, real).items()}
        objects = item["instance_label_map"][None] >= INSTANCE_DIVISOR
        if bool(objects.any()):
            metrics |= {f"obj_{k}": float(v) for k, v in image_metrics(fake, real, objects).items()}
        for k, v in metrics.items():
            sums.setdefault(k, []).append(v)
    return {"frames": count, **{k: sum(v) / len(v) for k, v in sorted(sums.items())}}


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--checkpoint", required=True, help="textural checkpoint (sdn3d-train branch=textural)")
    p.add_argument("--data-root", required=True)
    p.add_argument("--part", default="test", choices=("train", "val", "test"))
    p.add_argument("--size", type=int, nargs=2, default=(312, 96), metavar=("W", "H"))
    p.add_argument("--frames", type=int, default=None, help="first N frames of the part (default: all)")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-pairs", type=int, default=CodeSwapSettings.max_pairs_per_frame)
    p.add_argument("--semantic", default=None, help="with --geometric: also reconstruct from predicted maps")
    p.add_argument("--geometric", default=None)
    p.add_argument("--map-cache", default="outputs/map_cache", help="predicted-map cache directory")
    p.add_argument("--out", default=None)
    args = p.parse_args(argv)
    if (args.semantic is None) != (args.geometric is None):
        p.error("--semantic and --geometric go together")
    torch.set_num_threads(args.threads)
    renderer = TexturalRenderer.from_checkpoint(args.checkpoint)
    source = synth_data_source(args.data_root, args.size)
    settings = CodeSwapSettings(max_pairs_per_frame=args.max_pairs)
    t0 = time.perf_counter()
    swap = code_swap(renderer, source, args.part, args.frames, settings)
    t1 = time.perf_counter()
    recon = reconstruction(renderer, source, args.part, args.frames)
    t2 = time.perf_counter()
    predicted = None
    if args.semantic is not None:
        predicted = reconstruction(renderer, source, args.part, args.frames,
                                   (args.semantic, args.geometric, args.map_cache))
    result = {
        "checkpoint": str(Path(args.checkpoint).resolve()), "data_root": str(Path(args.data_root).resolve()),
        "part": args.part, "size": list(args.size), "code_swap": swap, "reconstruction": recon,
        "reconstruction_predicted": predicted,
        "seconds": {"code_swap": round(t1 - t0, 2), "reconstruction": round(t2 - t1, 2),
                    "reconstruction_predicted": round(time.perf_counter() - t2, 2)},
        "machine": f"{platform.machine()} cpu, {args.threads} threads, torch {torch.__version__}",
        "how": "pairs of same-class objects of one frame with real mean colours >= 20 CIE76 apart; A drawn with "
               "B's code via SetCode + scene_maps + G; colour move = projection of A's rendered mean-colour change "
               "onto (B - A) real mean colours / |B - A|^2; silhouette change = 1 - IoU of the pixels of A's window "
               "nearer A's mean than the surroundings' mean in the two renders (sdn3d.evaluation.code_swap)",
    }
    text = json.dumps(result, indent=2)
    print(text)
    if args.out:
        write_json_atomic(args.out, result)
    return result


if __name__ == "__main__":
    main()
