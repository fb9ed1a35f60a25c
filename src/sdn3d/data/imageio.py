"""File reading helpers shared by the dataset readers, each failing with a clear error.

Images: PNG/JPG through Pillow. A missing file raises :class:`MissingDataError`
(a ``FileNotFoundError``); an unreadable or truncated one, one with the wrong
pixel format, or one larger than :data:`MAX_IMAGE_PIXELS` (a decompression bomb:
a small file declaring a huge image; refused from its header, before decoding)
raises :class:`DataFormatError`; both name the path.

Colour tables: :class:`ColorEncoding` decodes colour-coded label images (VKITTI
scenegt/classgt) with one ``np.searchsorted`` over packed colours.

Text tables: the whitespace-separated, one-header-line files Virtual KITTI ships
(motgt, extrinsics, bbox, pose, ...). :func:`read_table` checks the header and the
column count of every line and reports the file and line number of the first bad one (or, given
``on_error``, hands each bad line to it and goes on: the skip policy of a training run).

Sequence sizes: :func:`agreed_size` decides a sequence's image size by agreement of its frames' headers,
so one odd frame (even the first) is named instead of every good one.
"""

from __future__ import annotations

import functools
import math
import os
import re
import warnings
import zlib
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from sdn3d.data.errors import DataFormatError, missing
from sdn3d.labels import INSTANCE_DIVISOR

__all__ = [
    "MAX_IMAGE_PIXELS",
    "MAX_FIT_FACTOR",
    "cover_size",
    "check_fit",
    "open_image",
    "image_size",
    "agreed_size",
    "frames_agreed_size",
    "read_rgb",
    "read_index_png",
    "read_uint16_png",
    "read_table",
    "TableRow",
    "pack_rgb",
    "ColorEncoding",
    "build_encoding",
]

#: Single-channel modes whose pixel values are integers (palette images give indices).
_INDEX_MODES = ("L", "P", "I;16", "I;16B", "I;16L", "I")


#: Largest image read, in pixels (100 MP; the largest dataset frames are 2 MP). Pillow's own guard
#: only warns from about 89 MP and stops at about 179 MP; a larger file is refused here from its header,
#: before its pixels are decoded (a few-kB PNG can declare gigabytes of pixels).
MAX_IMAGE_PIXELS = 100_000_000


def _too_large(path: Path, width: int | None = None, height: int | None = None,
               exc: BaseException | None = None) -> DataFormatError:
    if width and height:
        size = f"{width}x{height} = {width * height / 1e6:.0f} MP"
    else:  # Pillow refused it first: its message has the pixel count
        found = re.search(r"\((\d+) pixels\)", str(exc))
        size = f"{int(found.group(1)) / 1e6:.0f} MP" if found else "its declared size"
    return DataFormatError(f"{path}: image too large ({size}, more than the {MAX_IMAGE_PIXELS // 10**6} MP limit "
                           "for input images; a decompression bomb?): refused before decoding; resize it")


def _open_header(path: Path) -> Image.Image:
    """``Image.open(path)`` (the header only), refusing images over :data:`MAX_IMAGE_PIXELS`; errors name ``path``."""
    if not path.is_file():
        raise missing(path, "image file")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # the limit is checked below
            image = Image.open(path)
    except Image.DecompressionBombError as exc:
        raise _too_large(path, exc=exc) from exc
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise DataFormatError(f"{path}: unreadable image ({exc})") from exc
    if image.width * image.height > MAX_IMAGE_PIXELS:
        image.close()
        raise _too_large(path, image.width, image.height)
    return image


def open_image(path: str | os.PathLike) -> Image.Image:
    """Open and fully decode an image; errors name ``path`` (over :data:`MAX_IMAGE_PIXELS`: refused undecoded)."""
    path = Path(path)
    image = _open_header(path)
    try:
        image.load()  # decode now so a truncated file fails here, with its path
    except Image.DecompressionBombError as exc:
        image.close()
        raise _too_large(path, exc=exc) from exc
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        image.close()
        raise DataFormatError(f"{path}: unreadable image ({exc})") from exc
    return image


#: PNG bit depths allowed for each colour type (PNG specification, table 11.1).
_PNG_DEPTHS = {0: (1, 2, 4, 8, 16), 2: (8, 16), 3: (1, 2, 4, 8), 4: (8, 16), 6: (8, 16)}


def _png_size(path: Path) -> tuple[int, int] | None:
    """``(width, height)`` of a PNG from its signature and IHDR chunk (33 bytes, CRC checked); None when the file
    is not such a PNG or is over :data:`MAX_IMAGE_PIXELS` (then Pillow reads it and names what is wrong)."""
    try:
        with open(path, "rb") as file:
            head = file.read(33)
    except OSError:
        return None
    if len(head) != 33 or head[:16] != b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR":
        return None
    width, height = int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
    depth, color, methods = head[24], head[25], head[26:29]
    if (zlib.crc32(head[12:29]) != int.from_bytes(head[29:33], "big") or depth not in _PNG_DEPTHS.get(color, ())
            or methods[:2] != b"\x00\x00" or methods[2] > 1 or not 0 < width * height <= MAX_IMAGE_PIXELS):
        return None
    return width, height


def image_size(path: str | os.PathLike) -> tuple[int, int]:
    """``(width, height)`` read from the header only (no pixel decoding).

    A PNG's size is read straight from its IHDR chunk (:func:`_png_size`, about 10x faster than opening it
    with Pillow: indexing reads the header of every frame); other files, and PNGs whose IHDR is not valid,
    are opened with Pillow, whose errors name the file.
    """
    size = _png_size(Path(path))
    if size is not None:
        return size
    with _open_header(Path(path)) as image:
        return int(image.width), int(image.height)


#: The most pixels an image scaled to cover a working size may have, as a multiple of the working size's: an
#: image of an aspect ratio far from it (10x20000 for 1242x375: 1242x2484000, 18.5 GB) is refused, not scaled.
MAX_FIT_FACTOR = 16


def cover_size(width: int, height: int, size: tuple[int, int]) -> tuple[int, int]:
    """The size a ``width x height`` image has when scaled, keeping its aspect ratio, to cover ``size = (W, H)``
    (then cropped to it): what fitting it to a working size allocates first."""
    scale = max(size[0] / width, size[1] / height)
    return max(size[0], round(width * scale)), max(size[1], round(height * scale))


def check_fit(path: str | os.PathLike, size: tuple[int, int]) -> tuple[int, int]:
    """``(width, height)`` of the image at ``path`` (its header only), refused when scaling it to cover the working
    ``size`` would take more than :data:`MAX_FIT_FACTOR` times the working size's pixels (before decoding it).

    Raises:
        DataFormatError: naming the file, its size and the working size.
    """
    width, height = image_size(path)
    covered = cover_size(width, height, size)
    if covered[0] * covered[1] > MAX_FIT_FACTOR * size[0] * size[1]:
        raise DataFormatError(f"{path}: a {width}x{height} image (aspect ratio {width / height:.3g}) is too far from "
                              f"the working size {size[0]}x{size[1]} ({size[0] / size[1]:.3g}): scaled to cover it, it "
                              f"would be {covered[0]}x{covered[1]} pixels, more than {MAX_FIT_FACTOR} times the "
                              f"working size; crop it closer to {size[0]}:{size[1]}")
    return width, height


@functools.lru_cache(maxsize=1 << 16)
def _cached_size(path: Path, _mtime_ns: int, _size: int) -> tuple[int, int]:
    return image_size(path)


def agreed_size(
    paths: Sequence[Path], what: str, preferred: tuple[int, int] | None = None
) -> tuple[tuple[int, int] | None, dict[Path, DataFormatError]]:
    """The ``(width, height)`` most of ``paths`` have (headers only), and an error for every other file.

    A file whose header can not be read, or whose size differs from the agreed one, gets a
    :class:`DataFormatError` naming it (in ``paths`` order). A tie goes to ``preferred`` (the format's
    known size) when it is one of the tied sizes, else to the size of the earliest file. The size is None
    when no header could be read.

    Args:
        paths: the frames of one sequence (or one city).
        what: the sequence, for messages ("sequence 0001/clone").
        preferred: the format's nominal size, e.g. Virtual KITTI's 1242x375.
    """
    sizes: dict[Path, tuple[int, int]] = {}
    errors: dict[Path, DataFormatError] = {}
    for path in paths:
        try:
            stat = os.stat(path)
        except OSError:
            stat = None
        try:  # headers are read once per file version: each part of a split indexes the whole dataset
            sizes[path] = image_size(path) if stat is None else _cached_size(Path(path), stat.st_mtime_ns,
                                                                            stat.st_size)
        except DataFormatError as exc:
            errors[path] = exc
    if not sizes:
        return None, errors
    counts = Counter(sizes.values())
    top = max(counts.values())
    tied = [s for s, c in counts.items() if c == top]
    size = preferred if preferred in tied else next(s for s in sizes.values() if s in tied)
    for path, got in sizes.items():
        if got != size:
            errors[path] = DataFormatError(
                f"{path}: image is {got[0]}x{got[1]}, but {top} of the {len(paths)} frames of {what} are "
                f"{size[0]}x{size[1]}: this frame is the odd one", path=path)
    return size, {p: errors[p] for p in paths if p in errors}


def frames_agreed_size(paths: Mapping[int, Path], what: str, bad: dict[int, DataFormatError], strict: bool,
                       preferred: tuple[int, int] | None = None) -> tuple[int, int] | None:
    """:func:`agreed_size` of a sequence's frames ``{frame: path}``: a frame of another size (or an unreadable
    header) raises its error when ``strict``, else goes into ``bad`` (``{frame: error}``, first error kept)."""
    size, odd = agreed_size(list(paths.values()), what, preferred)
    for frame, path in paths.items():
        error = odd.get(path)
        if error is not None:
            if strict:
                raise error
            bad.setdefault(frame, error)
    return size


#: Modes :func:`read_rgb` converts with Pillow's own colour conversion (8 bits a channel; alpha dropped).
_RGB8_MODES = ("RGB", "RGBA", "RGBX", "RGBa", "P", "PA", "L", "LA", "La", "1", "CMYK", "YCbCr")
#: 16-bit single-channel modes (grey PNG / TIFF): scaled from [0, 65535].
_GREY16_MODES = ("I;16", "I;16B", "I;16L", "I;16N")


def read_rgb(path: str | os.PathLike) -> np.ndarray:
    """A colour image as ``(H, W, 3)`` uint8, each kind converted from its own range or refused by name.

    - 8-bit RGB, palette (``P``), grey (``L``), bilevel (``1``), CMYK and YCbCr: Pillow's conversion to RGB.
    - Alpha (``RGBA``, ``LA``, ``PA``): dropped; the colour channels are used as stored, not blended over a
      background (a transparent pixel shows the colour it holds).
    - 16-bit grey (``I;16*``): scaled from [0, 65535] to [0, 255] (rounded), repeated in the three channels.
      (Pillow reads 16-bit colour PNGs as 8-bit ``RGB`` / ``RGBA`` itself, keeping the high byte.)
    - 32-bit float grey (``F``, e.g. a float TIFF): values must lie in [0, 1] (intensities), scaled to
      [0, 255]; a non-finite value or one outside [0, 1] (an unnormalised or HDR image) is refused.
    - Any other mode (32-bit integer ``I``, ``LAB``, ``HSV``, ...) is refused: its range is not known.

    Raises:
        DataFormatError: naming ``path`` and the mode (or the float range) and what to do.
    """
    image = open_image(path)
    mode = image.mode
    if mode in _RGB8_MODES:
        if mode != "RGB":
            image = image.convert("RGB")
        return np.asarray(image, dtype=np.uint8).copy()
    if mode in _GREY16_MODES:
        grey = np.asarray(image).astype(np.uint32)
        grey = ((grey * 255 + 32767) // 65535).astype(np.uint8)
    elif mode == "F":
        values = np.asarray(image, dtype=np.float32)
        finite = np.isfinite(values)
        if not finite.all():
            raise DataFormatError(f"{path}: float image (mode 'F') holds {int((~finite).sum())} non-finite value(s) "
                                  "(NaN or infinity): refused; save it as an 8- or 16-bit PNG")
        low, high = (float(values.min()), float(values.max())) if values.size else (0.0, 0.0)
        if low < 0.0 or high > 1.0:
            raise DataFormatError(f"{path}: float image (mode 'F') has values in [{low:.6g}, {high:.6g}]; float images "
                                  "must hold intensities in [0, 1] (an unnormalised or high-dynamic-range image?): "
                                  "refused; scale it to [0, 1] or save it as an 8- or 16-bit PNG")
        grey = np.rint(values * 255.0).astype(np.uint8)
    else:
        raise DataFormatError(f"{path}: image mode {mode!r} is not supported (its value range is not known); "
                              "save it as an 8-bit RGB or grey, a 16-bit grey PNG or a [0, 1] float TIFF")
    return np.repeat(grey[..., None], 3, axis=2)


def read_index_png(path: str | os.PathLike) -> np.ndarray:
    """A single-channel integer image (8/16-bit grey or palette indices) as ``(H, W)`` int64."""
    image = open_image(path)
    if image.mode not in _INDEX_MODES:
        raise DataFormatError(
            f"{path}: expected a single-channel integer image (one of {_INDEX_MODES}), "
            f"got mode {image.mode!r}"
        )
    return np.asarray(image).astype(np.int64)


def read_uint16_png(path: str | os.PathLike) -> np.ndarray:
    """A 16-bit single-channel PNG as ``(H, W)`` uint16 (8-bit images are rejected)."""
    image = open_image(path)
    if image.mode not in ("I;16", "I;16B", "I;16L", "I"):
        raise DataFormatError(f"{path}: expected a 16-bit single-channel PNG, got mode {image.mode!r}")
    array = np.asarray(image)
    if array.dtype != np.uint16:
        if array.size and (array.min() < 0 or array.max() > 65535):
            raise DataFormatError(f"{path}: 16-bit PNG holds values outside [0, 65535]")
        array = array.astype(np.uint16)
    return array


def pack_rgb(rgb: np.ndarray) -> np.ndarray:
    """``(..., 3)`` uint8 colours -> ``(...)`` int64 keys ``r << 16 | g << 8 | b``."""
    rgb = np.asarray(rgb).astype(np.int64)
    return (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]


@dataclass(frozen=True, eq=False)
class ColorEncoding:
    """Colour -> (class id, track id) table of a colour-coded label image.

    ``keys`` are packed colours (see :func:`~sdn3d.data.imageio.pack_rgb`) sorted
    ascending, so decoding is one ``np.searchsorted`` over all pixels.
    ``track_ids`` is -1 for colours that are not instances.
    """

    path: Path
    keys: np.ndarray
    class_ids: np.ndarray
    track_ids: np.ndarray

    def lookup(self, rgb: np.ndarray, image_path: str | os.PathLike) -> np.ndarray:
        """``(H, W, 3)`` uint8 colours -> ``(H, W)`` row indices into the table.

        Raises :class:`DataFormatError` naming both files, the unknown colours and
        their pixel counts if any pixel's colour is not in the table.
        """
        packed = pack_rgb(rgb)
        index = np.searchsorted(self.keys, packed).clip(0, len(self.keys) - 1)
        known = self.keys[index] == packed
        if not known.all():
            colors, counts = np.unique(packed[~known], return_counts=True)
            order = np.argsort(-counts, kind="stable")[:5]
            listed = ", ".join(
                f"rgb({c >> 16}, {(c >> 8) & 255}, {c & 255}) x {n} px"
                for c, n in zip(colors[order].tolist(), counts[order].tolist(), strict=True)
            )
            raise DataFormatError(
                f"{image_path}: {len(colors)} colour(s) not in the class table {self.path}: {listed}"
            )
        return index

    def decode(self, rgb: np.ndarray, image_path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
        """``(semantic, instances)`` int64 maps; instances use ``k = tid + 1`` (0 = none)."""
        index = self.lookup(rgb, image_path)
        semantic = self.class_ids[index]
        tids = self.track_ids[index]
        instances = np.where(tids >= 0, semantic * INSTANCE_DIVISOR + tids + 1, 0)
        return semantic, instances


def build_encoding(
    path: Path, entries: Sequence[tuple[int, tuple[int, int, int], int, int]]
) -> ColorEncoding:
    """Table from ``(lineno, (r, g, b), class_id, track_id)``; duplicate colours are an error."""
    keys = np.array([pack_rgb(np.array(rgb)) for _, rgb, _, _ in entries], dtype=np.int64)
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    duplicate = np.nonzero(np.diff(sorted_keys) == 0)[0]
    if duplicate.size:
        first, second = entries[order[duplicate[0]]], entries[order[duplicate[0] + 1]]
        raise DataFormatError(f"{path}:{second[0]}: colour {second[1]} already used on line {first[0]}")
    class_ids = np.array([e[2] for e in entries], dtype=np.int64)[order]
    track_ids = np.array([e[3] for e in entries], dtype=np.int64)[order]
    return ColorEncoding(path, sorted_keys, class_ids, track_ids)


class TableRow:
    """One data line of a table with typed getters whose errors name the file, the
    line number and the column.

    Columns are addressed by header name or, where names repeat (the constant
    ``0 0 0 1`` row of extrinsics files), by position.
    """

    __slots__ = ("path", "lineno", "header", "tokens")

    def __init__(self, path: Path, lineno: int, header: tuple[str, ...], tokens: list[str]) -> None:
        self.path = path
        self.lineno = lineno
        self.header = header
        self.tokens = tokens

    def _index(self, column: str | int) -> int:
        return column if isinstance(column, int) else self.header.index(column)

    def _error(self, column: str | int, kind: str) -> DataFormatError:
        index = self._index(column)
        return DataFormatError(
            f"{self.path}:{self.lineno}: column {index + 1} ({self.header[index]!r}): expected {kind}, "
            f"got {self.tokens[index]!r}"
        )

    def text(self, column: str | int) -> str:
        return self.tokens[self._index(column)]

    def number(self, column: str | int) -> float:
        try:
            value = float(self.text(column))
        except ValueError as exc:
            raise self._error(column, "a number") from exc
        if not math.isfinite(value):
            raise self._error(column, "a finite number")
        return value

    def integer(self, column: str | int) -> int:
        value = self.number(column)
        if value != int(value):
            raise self._error(column, "an integer")
        return int(value)

    def flag(self, column: str | int) -> bool:
        text = self.text(column).lower()
        if text in ("1", "true"):
            return True
        if text in ("0", "false"):
            return False
        raise self._error(column, "a boolean (0/1/True/False)")


def read_table(
    path: str | os.PathLike,
    header: Sequence[str],
    what: str,
    on_error: Callable[[DataFormatError, list[str]], None] | None = None,
    named_columns: int | None = None,
) -> list[TableRow]:
    """Read a whitespace-separated table with the header line ``header``.

    Blank lines are skipped; every other line must have ``len(header)`` fields.

    Args:
        path: the text file.
        header: the expected column names, in order.
        what: a short description for error messages ("motgt file", ...).
        on_error: None raises on the first line with the wrong number of fields; otherwise that line is
            left out and ``on_error(error, tokens)`` is called (a missing file or a bad header still raise).
        named_columns: how many leading header words must read exactly as ``header`` (None: all); the
            others only count. Published files word the trailing columns of some headers differently.

    Returns:
        One :class:`TableRow` per data line, in file order.
    """
    path = Path(path)
    if not path.is_file():
        raise missing(path, what)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as exc:
        raise DataFormatError(f"{path}: {what} is not UTF-8 text ({exc})") from exc
    words = lines[0].split() if lines else []
    fixed = len(header) if named_columns is None else named_columns
    if len(words) != len(header) or words[:fixed] != list(header[:fixed]):
        got = lines[0].strip() if lines else "<empty file>"
        expected = " ".join(header) if fixed == len(header) else (
            f"{' '.join(header[:fixed])} followed by {len(header) - fixed} more columns")
        raise DataFormatError(f"{path}:1: {what} header must be {expected!r}, got {got!r}")
    header = tuple(header)
    rows: list[TableRow] = []
    for lineno, line in enumerate(lines[1:], start=2):
        tokens = line.split()
        if not tokens:
            continue
        if len(tokens) != len(header):
            error = DataFormatError(
                f"{path}:{lineno}: {what} line has {len(tokens)} fields, expected {len(header)}: "
                f"{line.strip()!r}", path=path, line=lineno
            )
            if on_error is None:
                raise error
            on_error(error, tokens)
            continue
        rows.append(TableRow(path, lineno, header, tokens))
    return rows
