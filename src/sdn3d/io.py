"""Atomic output writing: every file sdn3d writes goes to a temporary file in the
target directory first and is renamed into place, so a crash or a bad input never
leaves a half-written output or replaces a good one with a broken one.

Whole output directories (``sdn3d-edit``, ``sdn3d-bench``, ``sdn3d-synth``) are staged the same way:
everything goes into a temporary sibling directory that replaces the output directory only once
everything is written, so a failure leaves no partial output and an old result intact. An existing
non-empty directory is only replaced when it holds the tool's ``marker`` file (it is a previous result
of the same tool), never an unrelated folder."""

from __future__ import annotations

import io
import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from sdn3d.errors import UserInputError

__all__ = [
    "atomic_write", "write_bytes_atomic", "write_text_atomic", "write_json_atomic", "write_png_atomic",
    "check_output_dir", "staged_directory", "swap_into_place",
]


def atomic_write(path: str | os.PathLike, writer: Callable[[io.BufferedWriter], None]) -> Path:
    """Call ``writer(file)`` on a temporary file next to ``path``, then rename it onto ``path``.

    The temporary file is removed if ``writer`` raises; ``path`` keeps its old content.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            writer(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


def write_bytes_atomic(path: str | os.PathLike, data: bytes) -> Path:
    return atomic_write(path, lambda f: f.write(data))


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    return write_bytes_atomic(path, text.encode("utf-8"))


def write_json_atomic(path: str | os.PathLike, obj: Any, indent: int = 2) -> Path:
    return write_text_atomic(path, json.dumps(obj, indent=indent, sort_keys=False) + "\n")


def write_png_atomic(path: str | os.PathLike, array: np.ndarray) -> Path:
    """Write a ``(H, W)`` or ``(H, W, 3)`` uint8/uint16 array as PNG, atomically.

    PNG metadata is fixed (no timestamps), so the same array always gives the same bytes.
    """
    from PIL import Image

    array = np.ascontiguousarray(array)
    if array.dtype == np.uint16 and array.ndim == 2:
        image = Image.fromarray(array)
    elif array.dtype == np.uint8:
        image = Image.fromarray(array)
    else:
        raise ValueError(f"write_png_atomic: {path}: expected uint8 or 2-D uint16 array, got {array.dtype}")

    def _write(handle: io.BufferedWriter) -> None:
        image.save(handle, format="PNG", optimize=False)

    return atomic_write(path, _write)


def load_lightning_checkpoint(path: str | os.PathLike, map_location: Any = "cpu",
                              required: tuple[str, ...] = ("state_dict",)) -> dict:
    """A Lightning checkpoint read with ``torch.load(weights_only=True)`` (no code from the file runs).

    Raises:
        UserInputError (a ValueError): naming the file: missing, unreadable (truncated, not a torch file,
            or holding objects ``weights_only`` refuses), or not a mapping with the ``required`` keys.
    """
    import pickle
    import zipfile

    import torch

    path = Path(path).expanduser()
    if not path.is_file():
        raise UserInputError(f"checkpoint {str(path)!r} does not exist")
    try:
        ckpt = torch.load(path, map_location=map_location, weights_only=True)
    except (pickle.UnpicklingError, RuntimeError, EOFError, zipfile.BadZipFile, OSError) as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UserInputError(f"could not read checkpoint {str(path)!r}: {first}") from exc
    if not isinstance(ckpt, dict) or any(k not in ckpt for k in required):
        raise UserInputError(f"{str(path)!r} is not a Lightning checkpoint (needs {', '.join(map(repr, required))})")
    return ckpt


def swap_into_place(tmp: Path, out: Path) -> None:
    """Rename the finished tree ``tmp`` onto ``out``; an old ``out`` is moved aside first, then deleted."""
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        os.rename(out, old / "tree")
    os.rename(tmp, out)
    if old is not None:
        shutil.rmtree(old)


def check_output_dir(out: str | os.PathLike, marker: str, overwrite: bool) -> Path:
    """Raise ``FileExistsError`` if ``out`` may not be (re)written; returns it resolved."""
    out = Path(out).expanduser().resolve()
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"output_dir {str(out)!r} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()):
        if not overwrite:
            raise FileExistsError(f"output_dir {str(out)!r} is not empty (set overwrite=true to replace it)")
        if not (out / marker).is_file():
            raise FileExistsError(f"output_dir {str(out)!r} is not empty and holds no {marker} (not an earlier "
                                  "output of this tool): refusing to replace it; choose another output_dir")
    return out


@contextmanager
def staged_directory(out: str | os.PathLike, marker: str, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary directory; on success it becomes ``out`` (write ``marker`` in it), on error it goes."""
    out = check_output_dir(out, marker, overwrite)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    try:
        yield tmp
        if not (tmp / marker).is_file():
            raise RuntimeError(f"staged output misses its marker file {marker}")
        swap_into_place(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
