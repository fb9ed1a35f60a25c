"""Train the photo appearance's learnt fill (``photo.fill=learnt``, :mod:`sdn3d.editing.photo.learnt`) on the
synthetic generator's exact delete pairs, and score it against the rays' fill.

1. ``extract TREE OUT.npz``: every delete pair of a counterfactual tree (``sdn3d-synth counterfactual_cars=N``;
   ground-truth geometry, **oracle**: ``scene_from_frame``, as the counterfactual benchmark's ``oracle`` source) is
   drawn by the photo appearance with ``fill=rays``; what its fill step saw and gave (the picture before the fill,
   the hole, the other objects' pixels, the filled picture), the exact render without the car and the pair's scored
   region (vacated + shadow band) are kept, uint8 / bool, compressed.
2. ``train WEIGHTS.pt A.npz [B.npz ...] [--steps N --width W --seed S --side P]``: crops of the extracted pairs
   (:func:`~sdn3d.editing.photo.learnt.crop_samples`), :func:`~sdn3d.editing.photo.learnt.train_fill_net`, saved
   with :func:`~sdn3d.editing.photo.learnt.save_fill_net` (one thread; deterministic given the seed).
3. ``ensemble WEIGHTS.pt A.pt B.pt [...]``: the nets of the trained files (one working side) in one weights file,
   their corrections averaged (:class:`~sdn3d.editing.photo.learnt.FillEnsemble`); the members' meta kept.
4. ``score WEIGHTS.pt A.npz [...]``: PSNR and L1 on each pair's scored region of the rays' fill and of the learnt
   correction on it (the fill step alone: what the photo appearance draws over the fill afterwards is not redrawn;
   ``sdn3d-bench counterfactual=true counterfactual_fills=[rays,learnt]`` scores the whole picture).

Training data must not come from tuning or held-out seeds (the records use seeds 300-399)::

    PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/learnt_fill.py extract /tmp/tr300 /tmp/tr300.npz
    PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/learnt_fill.py train fill.pt /tmp/tr3*.npz --steps 3000
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import torch


def extract(root: Path, out: Path, limit: int | None = None) -> int:
    """Write ``out`` (module doc, step 1); returns the number of pairs kept."""
    import sdn3d.editing.photo.transfer as transfer
    from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
    from sdn3d.data.vkitti1 import read_frames
    from sdn3d.evaluation import counterfactual as cf
    from sdn3d.evaluation.edit_benchmark import index_records

    index = load_pairs(root)
    records = index_records(read_frames(root))
    settings = cf.CounterfactualSettings(sources=("oracle",), fills=("rays",), baselines=(), kinds=("delete",))
    seen: list[tuple] = []
    original = transfer.fill_hole

    def capture(image, hole, settings, keep_out=None, fill=None, vanishing=None):
        filled = original(image, hole, settings, keep_out, fill, vanishing)
        seen.append((image, hole, keep_out, filled))
        return filled

    arrays: dict[str, list] = {k: [] for k in ("before", "filled", "target", "hole", "keep_out", "scored")}
    keys, psnr = [], []
    transfer.fill_hole = capture
    try:
        pairs = [p for p in index.pairs if p.kind == "delete"][:limit]
        for n, pair in enumerate(pairs):
            record = records.get((pair.world, pair.variation, pair.frame))
            if record is None:
                continue
            seen.clear()
            rows = cf.evaluate_target([pair], record, index, None, settings)
            metrics = rows[0].metrics.get("photo:rays")
            if not seen or metrics is None:
                print(f"[{n + 1}/{len(pairs)}] {pair.key}: skipped ({rows[0].errors})", flush=True)
                continue
            image, hole, keep_out, filled = seen[-1]
            target = load_pair_rgb(root, pair)
            scored = load_pair_mask(root, pair, "vacated") | load_pair_mask(root, pair, "shadow")
            to8 = lambda x: (x.clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5).astype(np.uint8)  # noqa: E731
            arrays["before"].append(to8(image))
            arrays["filled"].append(to8(filled))
            arrays["target"].append(target)
            arrays["hole"].append(hole.numpy())
            arrays["keep_out"].append(np.zeros_like(hole.numpy()) if keep_out is None else keep_out.numpy())
            arrays["scored"].append(scored)
            keys.append(pair.key)
            psnr.append(metrics["hole"]["psnr"])
            print(f"[{n + 1}/{len(pairs)}] {pair.key}: rays {psnr[-1]:.2f} dB", flush=True)
    finally:
        transfer.fill_hole = original
    np.savez_compressed(out, **{k: np.stack(v) for k, v in arrays.items()}, keys=np.asarray(keys),
                        bench_psnr=np.asarray(psnr), root=str(root))
    return len(keys)


def load(paths: list[Path]) -> list[dict]:
    """Every pair of the extracted files: ``{key, filled, target (3, H, W) float, hole, keep_out, scored (H, W)}``."""
    out = []
    for path in paths:
        with np.load(path) as npz:  # each field decompressed once (indexing the file itself decompresses it again)
            data = {k: npz[k] for k in ("keys", "filled", "target", "hole", "keep_out", "scored")}
        f = lambda a: torch.from_numpy(a).permute(2, 0, 1).float() / 255  # noqa: E731
        for i, key in enumerate(data["keys"]):
            out.append({"key": f"{path.stem}:{key}", "filled": f(data["filled"][i]), "target": f(data["target"][i]),
                        "hole": torch.from_numpy(data["hole"][i]), "keep_out": torch.from_numpy(data["keep_out"][i]),
                        "scored": torch.from_numpy(data["scored"][i])})
    return out


def train(weights: Path, paths: list[Path], steps: int, width: int, seed: int, side: int) -> None:
    from sdn3d.editing.photo.learnt import FillSamples, TrainSettings, crop_samples, save_fill_net, train_fill_net

    torch.set_num_threads(1)
    pairs = load(paths)
    samples = FillSamples.cat([crop_samples(p["filled"], p["hole"], p["keep_out"], p["target"], i, side)
                               for i, p in enumerate(pairs)])
    print(f"{len(pairs)} pairs, {len(samples.inputs)} crops", flush=True)
    settings = TrainSettings(width=width, steps=steps, seed=seed)
    t0, c0 = time.perf_counter(), time.process_time()
    net = train_fill_net(samples, settings, lambda s, loss: print(f"step {s} loss {loss:.5f} "
                                                                  f"({time.perf_counter() - t0:.0f} s)", flush=True))
    meta = {"data": [str(p) for p in paths], "pairs": len(pairs), "crops": len(samples.inputs),
            "settings": dict(settings.__dict__), "cpu_s": time.process_time() - c0}
    save_fill_net(net, weights, meta)
    print(json.dumps(meta), flush=True)


def ensemble(weights: Path, members: list[Path]) -> None:
    from sdn3d.editing.photo.learnt import FillEnsemble, load_fill_net, read_fill_meta, save_fill_net

    nets = [net for path in members for net in load_fill_net(path).nets]
    meta = {"members": [{"file": str(path), **read_fill_meta(path)} for path in members]}
    save_fill_net(FillEnsemble(nets), weights, meta)
    print(f"{len(nets)} nets -> {weights}", flush=True)


def score(weights: Path, paths: list[Path]) -> list[dict]:
    from sdn3d.editing.photo.learnt import learnt_fill, load_fill_net

    torch.set_num_threads(1)
    net = load_fill_net(weights)
    rows = []
    for p in load(paths):
        t0 = time.process_time()
        fixed = learnt_fill(p["filled"], p["hole"], net, p["keep_out"])
        ms = 1000 * (time.process_time() - t0)
        row = {"key": p["key"], "ms": ms}
        for name, picture in (("rays", p["filled"]), ("learnt", fixed)):
            diff = (picture - p["target"])[:, p["scored"]]
            row[name] = {"psnr": 10 * math.log10(1 / max(float(diff.square().mean()), 1e-6)),
                         "l1": float(diff.abs().mean())}
        rows.append(row)
    return rows


def main(argv: list[str] | None = None) -> int:
    from sdn3d.editing.photo.learnt import WORK_SIDE

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("extract")
    p.add_argument("tree", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--limit", type=int)
    p = sub.add_parser("train")
    p.add_argument("weights", type=Path)
    p.add_argument("data", type=Path, nargs="+")
    p.add_argument("--steps", type=int, default=3000)
    p.add_argument("--width", type=int, default=16)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--side", type=int, default=WORK_SIDE, help="the net's working side (crops resampled to it)")
    p = sub.add_parser("ensemble")
    p.add_argument("weights", type=Path)
    p.add_argument("members", type=Path, nargs="+")
    p = sub.add_parser("score")
    p.add_argument("weights", type=Path)
    p.add_argument("data", type=Path, nargs="+")
    p.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    if args.command == "extract":
        print(f"kept {extract(args.tree, args.out, args.limit)} pairs")
    elif args.command == "train":
        train(args.weights, args.data, args.steps, args.width, args.seed, args.side)
    elif args.command == "ensemble":
        ensemble(args.weights, args.members)
    else:
        from sdn3d.evaluation.paired import paired_difference

        rows = score(args.weights, args.data)
        mean = lambda xs: sum(xs) / len(xs)  # noqa: E731
        for path in [*args.data, None]:
            mine = [r for r in rows if path is None or r["key"].split(":")[0] == path.stem]
            d = paired_difference([r["learnt"]["psnr"] for r in mine], [r["rays"]["psnr"] for r in mine],
                                  higher_is_better=True)
            rays, learnt = mean([r["rays"]["psnr"] for r in mine]), mean([r["learnt"]["psnr"] for r in mine])
            print(f"{'all' if path is None else path.stem}: n={len(mine)} rays {rays:.3f} dB, learnt {learnt:.3f}"
                  f" dB; learnt - rays {d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] {d.wins}/{d.losses}/{d.ties}; "
                  f"net {mean([r['ms'] for r in mine]):.1f} ms CPU/pair")
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
