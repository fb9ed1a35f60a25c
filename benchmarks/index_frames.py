"""Indexing a Virtual KITTI 1.3.1 tree of the real size with ``vkitti1.read_frames``; prints JSON.

    python benchmarks/index_frames.py [--objects 8] [--runs 3] [--scale 1.0] [--keep DIR]

Builds, in a temporary directory, the annotation tree of the full Virtual KITTI 1.3.1 release: 5 worlds x
10 variations with the real per-world lengths (0001: 447, 0002: 233, 0006: 270, 0018: 339, 0020: 837
frames; 21,260 frames in all). What :func:`~sdn3d.data.vkitti1.read_frames` opens is real:

- ``vkitti_1.3.1_rgb/<world>/<variation>/%05d.png``: one valid 1242x375 RGB PNG per frame (the same small
  file, hard-linked when the file system allows it), since indexing reads every frame's PNG header (a
  sequence's size is the one its frames agree on, and an odd frame is named at once);
- ``vkitti_1.3.1_motgt/<world>_<variation>.txt``: ``--objects`` rows per frame in the real column layout
  (the published files hold about 5-15 cars per frame);
- ``vkitti_1.3.1_extrinsicsgt/<world>_<variation>.txt``: one matrix row per frame, the published header;
- ``vkitti_1.3.1_scenegt`` and ``vkitti_1.3.1_depthgt``: the sequence folders and the scenegt colour
  encoding files (indexing only checks that they exist; it opens no scenegt or depth PNG).

Reported: ``first_s``, the first ``read_frames`` call of this process (nothing cached; the files were
just written, so the operating system's page cache is warm, as on a machine that read the data before),
and ``repeat_s``, the median of ``--runs`` further calls (headers are cached per file version, text
tables are parsed again). ``--scale`` shrinks the sequences (0.1: 2,126 frames) for a quick look.
"""

from __future__ import annotations

import argparse
import io
import json
import math
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.data.vkitti1 import (
    ENCODING_HEADER,
    MOTGT_HEADER,
    PUBLISHED_EXTRINSICS_HEADER,
    VKITTI_VARIATIONS,
    read_frames,
)
from sdn3d.labels import VKITTI_CLASSES

#: Frames per sequence of each Virtual KITTI 1.3.1 world (every variation of a world has them all).
WORLD_FRAMES = {"0001": 447, "0002": 233, "0006": 270, "0018": 339, "0020": 837}


def _png_bytes(width: int = 1242, height: int = 375) -> bytes:
    rgb = np.zeros((height, width, 3), dtype=np.uint8)
    rgb[: height // 2] = (90, 140, 200)
    rgb[height // 2 :] = (100, 100, 100)
    buffer = io.BytesIO()
    Image.fromarray(rgb).save(buffer, format="PNG")
    return buffer.getvalue()


def _motgt_rows(frames: int, objects: int, rng: np.random.Generator) -> list[str]:
    """``objects`` cars per frame, values in the ranges of the real files."""
    rows = []
    for f in range(frames):
        for tid in range(objects):
            x, z = rng.uniform(-12, 12), rng.uniform(6, 80)
            ry = rng.uniform(-math.pi, math.pi)
            u = 725.0 * x / z + 620.5
            half = 725.0 * 2.0 / z
            l, r = max(0, int(u - half)), min(1241, int(u + half))
            t, b = int(187 + 725.0 * 0.1 / z), int(187 + 725.0 * 1.65 / z)
            alpha = math.remainder(ry - math.atan2(x, z), 2 * math.pi)
            rows.append(f"{f} {tid} Car 0 0 {alpha:.6f} {l} {t} {max(r, l + 1)} {min(b, 374)} 1.800000 1.500000 "
                        f"4.200000 {x:.6f} 1.650000 {z:.6f} {ry:.6f} 0.000000 0.000000 0.000000 0.812345 "
                        f"Car 1 Sedan4Door Black")
    return rows


def _extrinsics_rows(frames: int) -> list[str]:
    rows = []
    for f in range(frames):
        c, s = math.cos(0.01 * f), math.sin(0.01 * f)
        matrix = (c, 0.0, -s, 0.8 * f * s, 0.0, 1.0, 0.0, 0.0, s, 0.0, c, -0.8 * f * c)
        rows.append(f"{f} " + " ".join(f"{v:.9f}" for v in matrix) + " 0 0 0 1")
    return rows


def _write(path: Path, header: tuple[str, ...], rows: list[str]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join([" ".join(header), *rows]) + "\n", encoding="utf-8")


def build_tree(root: Path, objects: int, scale: float = 1.0) -> int:
    """Write the annotation tree (module doc) under ``root``; returns its frame count."""
    root.mkdir(parents=True, exist_ok=True)
    png = root / "frame.png"
    png.write_bytes(_png_bytes())
    encoding = [f"{c.name} {' '.join(map(str, c.color))}" for c in VKITTI_CLASSES if not c.has_instances]
    encoding += [f"Car:{tid} {tid * 20 % 256} 200 {tid * 7 % 256}" for tid in range(objects)]
    rng = np.random.default_rng(0)
    total = 0
    for world, length in WORLD_FRAMES.items():
        frames = max(1, round(length * scale))
        motgt = _motgt_rows(frames, objects, rng)
        extrinsics = _extrinsics_rows(frames)
        for variation in VKITTI_VARIATIONS:
            rgb_dir = root / "vkitti_1.3.1_rgb" / world / variation
            rgb_dir.mkdir(parents=True)
            for f in range(frames):
                try:
                    os.link(png, rgb_dir / f"{f:05d}.png")
                except OSError:
                    (rgb_dir / f"{f:05d}.png").write_bytes(png.read_bytes())
            for kind in ("scenegt", "depthgt"):
                (root / f"vkitti_1.3.1_{kind}" / world / variation).mkdir(parents=True)
            name = f"{world}_{variation}"
            _write(root / "vkitti_1.3.1_scenegt" / f"{name}_scenegt_rgb_encoding.txt", ENCODING_HEADER, encoding)
            _write(root / "vkitti_1.3.1_motgt" / f"{name}.txt", MOTGT_HEADER, motgt)
            _write(root / "vkitti_1.3.1_extrinsicsgt" / f"{name}.txt", PUBLISHED_EXTRINSICS_HEADER, extrinsics)
            total += frames
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=8, help="motgt rows per frame")
    parser.add_argument("--runs", type=int, default=3, help="repeated calls after the first")
    parser.add_argument("--scale", type=float, default=1.0, help="share of each sequence's real length")
    parser.add_argument("--keep", type=Path, default=None, help="build the tree here and keep it")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="sdn3d-index-bench-") as tmp:
        root = args.keep if args.keep is not None else Path(tmp)
        start = time.perf_counter()
        frames = build_tree(root, args.objects, args.scale)
        build_s = time.perf_counter() - start
        load_before = os.getloadavg()
        start = time.perf_counter()
        records = read_frames(root)
        first = time.perf_counter() - start
        repeat = []
        for _ in range(args.runs):
            start = time.perf_counter()
            read_frames(root)
            repeat.append(time.perf_counter() - start)
        if len(records) != frames or sum(len(r.objects) for r in records) != frames * args.objects:
            raise SystemExit(f"read_frames returned {len(records)} records, expected {frames}")
        print(json.dumps({
            "frames": frames,
            "sequences": len(WORLD_FRAMES) * len(VKITTI_VARIATIONS),
            "motgt_rows": frames * args.objects,
            "build_s": round(build_s, 2),
            "first_s": round(first, 3),
            "repeat_s": round(statistics.median(repeat), 3) if repeat else None,
            "repeat_all_s": [round(v, 3) for v in repeat],
            "cpu_count": os.cpu_count(),
            "loadavg_before": [round(v, 2) for v in load_before],
            "loadavg_after": [round(v, 2) for v in os.getloadavg()],
        }, indent=2))


if __name__ == "__main__":
    main()
