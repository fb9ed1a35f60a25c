"""Fault injection for dataset files (on trees written by ``sdn3d.data.fixtures`` or ``sdn3d.data.synth``).

    corrupt_png(path)                       # a PNG signature and garbage: its header can not be read
    truncated_png(path)                     # a real PNG cut short: the header reads, the pixels do not
    zero_byte(path)                         # an empty file
    wrong_size_png(path, (w, h))            # a valid RGB PNG of another size
    unknown_colour_png(path, (1, 2, 3))     # a colour-coded label PNG with a colour no table lists
    bad_motgt_row(motgt, row, column, value)  # one field of one data row replaced (row 0 = first data row)
    negative_dims(motgt, row, (w3d, h3d, l3d))  # one object's w3d h3d l3d replaced
    vkitti1_frame_files(root)               # {frame: rgb path} of the first sequence of a VKITTI 1 tree

Each returns the path it broke, so a test can check that exactly that file is named.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.data.vkitti1 import MOTGT_HEADER

__all__ = ["corrupt_png", "truncated_png", "zero_byte", "wrong_size_png", "unknown_colour_png", "bad_motgt_row",
           "negative_dims", "vkitti1_frame_files"]

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def corrupt_png(path: Path) -> Path:
    """Replace ``path`` by a PNG signature followed by garbage (no readable header)."""
    path.write_bytes(_PNG_SIGNATURE + b" this is not a PNG any more")
    return path


def truncated_png(path: Path) -> Path:
    """Cut a real PNG to its first half: its header (and size) still read, decoding its pixels fails."""
    data = path.read_bytes()
    path.write_bytes(data[: max(len(data) // 2, 64)])
    return path


def zero_byte(path: Path) -> Path:
    """Empty ``path`` (a download or copy that died before writing anything)."""
    path.write_bytes(b"")
    return path


def wrong_size_png(path: Path, size: tuple[int, int]) -> Path:
    """Replace ``path`` by a valid grey RGB PNG of ``size = (width, height)``."""
    Image.fromarray(np.full((size[1], size[0], 3), 128, np.uint8)).save(path)
    return path


def unknown_colour_png(path: Path, colour: tuple[int, int, int] = (1, 2, 3), pixels: int = 12) -> Path:
    """Paint ``pixels`` pixels of the colour-coded label PNG ``path`` (top-left row) in ``colour``."""
    image = np.asarray(Image.open(path).convert("RGB")).copy()
    image[0, :pixels] = colour
    Image.fromarray(image).save(path)
    return path


def _rewrite_row(path: Path, row: int, change) -> Path:
    lines = path.read_text().splitlines()
    fields = lines[1 + row].split()
    change(fields)
    lines[1 + row] = " ".join(fields)
    path.write_text("\n".join(lines) + "\n")
    return path


def bad_motgt_row(motgt: Path, row: int = 0, column: str = "w3d", value: str = "wide") -> Path:
    """Set ``column`` of data row ``row`` of a motgt file to ``value`` (the file's line is ``row + 2``)."""
    index = MOTGT_HEADER.index(column)

    def change(fields: list[str]) -> None:
        fields[index] = value

    return _rewrite_row(motgt, row, change)


def negative_dims(motgt: Path, row: int = 0, dims: tuple[float, float, float] = (-1.8, 1.5, 4.2)) -> Path:
    """Set ``w3d h3d l3d`` of data row ``row`` of a motgt file to ``dims`` (in the file's order)."""
    start = MOTGT_HEADER.index("w3d")

    def change(fields: list[str]) -> None:
        fields[start:start + 3] = [f"{v:.6f}" for v in dims]

    return _rewrite_row(motgt, row, change)


def vkitti1_frame_files(root: Path) -> dict[int, Path]:
    """``{frame: rgb file}`` of the first sequence (sorted world / variation) of a Virtual KITTI 1.3.1 tree."""
    seq = sorted(p for p in (root / "vkitti_1.3.1_rgb").glob("*/*") if p.is_dir())[0]
    return {int(p.stem): p for p in sorted(seq.glob("*.png"))}
