"""The photo appearance's nearest examples: the grouped scan (``shared_from``) against the flat scan, side by side.

    python benchmarks/nearest_examples.py [--repeats 7] [--threads 1] [--seed 0]

Workloads shaped as the part lookups of the real frame's red car turned -90 degrees at 1242x375 (session 35's dump
of that edit: 80,687 body rows with k = 4 and 39,757 glass rows with k = 16 against 1,500 examples on 43 and 36
template faces; docs/results/2026-12-02_cpu/session35/lead/nearest/): the examples are points of a car's own frame
(:func:`sdn3d.editing.photo.transfer._part_features`' scaling) on a few dozen faces, one normal a face; the queries
are a raster of never-seen pixels in row order, each asked with the normals of the faces around its corners (part
smoothing's lookups), so that neighbouring rows are neighbouring points, as the caller asks them. Each workload is
timed with and without ``shared_from`` in turn (A, B, A, B, ...) after one untimed call of each; prints the minimum
and median wall time of each, their ratio, and whether the two answers agree bit for bit (they must).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import torch

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))


def workload(seed: int, rows: int, faces: int, fan: int, k: int) -> tuple[torch.Tensor, torch.Tensor, int]:
    """``(query (rows * fan, 6), examples (1500, 6), k)`` as described in the module doc."""
    from sdn3d.editing.photo.transfer import PART_LENGTH_WEIGHT, PART_NORMAL_WEIGHT

    g = torch.Generator().manual_seed(seed)
    scale = torch.tensor([PART_LENGTH_WEIGHT, 1.0, 0.5])
    seen = torch.nn.functional.normalize(torch.randn(faces, 3, generator=g), dim=1)
    face = torch.randint(faces, (1500,), generator=g)
    examples = torch.cat([torch.rand(1500, 3, generator=g) * scale, PART_NORMAL_WEIGHT * seen[face]], 1)
    side = int(rows**0.5)
    yy, xx = torch.meshgrid(torch.linspace(0, 1, side), torch.linspace(0, 1, side), indexing="ij")
    where = torch.stack([xx.flatten(), yy.flatten(), torch.full((side * side,), 0.5)], 1) * scale  # row order
    new = torch.nn.functional.normalize(torch.randn(300, 3, generator=g), dim=1)  # the turned car's faces
    own = (where[:, 0] / scale[0] * 14).long() * 20 + (where[:, 1] * 19).long() % 20  # a face per patch of pixels
    asked = (own[:, None] + torch.arange(fan)[None]) % len(new)  # its corners' fans: the faces around it
    query = torch.cat([where.repeat_interleave(fan, 0), PART_NORMAL_WEIGHT * new[asked.flatten()]], 1)
    return query, examples, k


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    from sdn3d.editing.photo.nearest import nearest_examples, nearest_kernel

    torch.set_num_threads(args.threads)
    if nearest_kernel() is None:
        print("no C++ kernel here (no compiler): both run the PyTorch path; nothing to compare")
        return 1
    print(f"nearest_examples, {args.threads} thread(s), {args.repeats} timed calls of each, alternated; wall ms")
    for name, rows, faces, fan, k in (("body, k=4", 17_956, 43, 5, 4), ("glass, k=16", 9_409, 36, 4, 16)):
        query, examples, k = workload(args.seed, rows, faces, fan, k)
        flat = nearest_examples(query, examples, k)
        grouped = nearest_examples(query, examples, k, shared_from=3)
        times: dict[str, list[float]] = {"flat": [], "grouped": []}
        for _ in range(args.repeats):
            for label, shared in (("flat", None), ("grouped", 3)):
                start = time.perf_counter()
                nearest_examples(query, examples, k, shared_from=shared)
                times[label].append(1000 * (time.perf_counter() - start))
        medians = {label: statistics.median(t) for label, t in times.items()}
        print(f"{name}: {len(query)} rows x {len(examples)} examples; flat min {min(times['flat']):.1f} median "
              f"{medians['flat']:.1f}; grouped min {min(times['grouped']):.1f} median {medians['grouped']:.1f}; "
              f"grouped / flat {medians['grouped'] / medians['flat']:.2f}; same answer: {torch.equal(flat, grouped)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
