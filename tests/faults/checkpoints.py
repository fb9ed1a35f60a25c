"""Fault injection for checkpoints and run configs: files a user might pass where a trained branch's
Lightning checkpoint is expected.

    random_bytes(path, seed)                  # noise (torch's loader fails in many different ways on it)
    truncated_copy(src, dst, keep=0.5)        # a real checkpoint cut short (an interrupted copy)
    foreign_zip(path)                         # a zip archive that is not a torch file
    code_running_pickle(path, marker, ...)    # unpickled unsafely it would create ``marker``
    wrong_branch_cases(paths)                 # each branch's checkpoint as every other branch
    hydra_config_with_target(path, marker)    # a run config.yaml with a non-project ``_target_``

:data:`RANDOM_SEEDS` are ``random_bytes`` seeds among which torch 2.x's weights-only loader raises
``UnpicklingError``, ``IndexError``, ``KeyError`` and ``UnicodeDecodeError`` (only the first was reported
clearly before issue 20).
"""

from __future__ import annotations

import io
import pickle
import zipfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import torch

__all__ = ["RANDOM_SEEDS", "BRANCHES", "WRONG_BRANCH_PAIRS", "random_bytes", "truncated_copy", "foreign_zip",
           "code_running_pickle", "wrong_branch_cases", "hydra_config_with_target"]

#: Seeds of :func:`random_bytes` (256 bytes) covering the loader's failure types (see the module doc).
RANDOM_SEEDS = (0, 1, 17, 21, 54, 62, 66, 76)
BRANCHES = ("semantic", "geometric", "textural")
#: ``(held, expected)``: the checkpoint of branch ``held`` given where ``expected``'s is wanted.
WRONG_BRANCH_PAIRS = tuple((held, expected) for held in BRANCHES for expected in BRANCHES if held != expected)


def random_bytes(path: Path, seed: int, size: int = 256) -> Path:
    """``size`` random bytes (``numpy.random.default_rng(seed)``) written to ``path``."""
    path.write_bytes(np.random.default_rng(seed).bytes(size))
    return path


def truncated_copy(src: Path, dst: Path, keep: float = 0.5) -> Path:
    """The first ``keep`` fraction of ``src``'s bytes, written to ``dst``."""
    data = src.read_bytes()
    dst.write_bytes(data[: max(1, int(len(data) * keep))])
    return dst


def foreign_zip(path: Path) -> Path:
    """A valid zip archive (a text file and a nested folder) that is not a torch checkpoint."""
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("readme.txt", "not a checkpoint")
        archive.writestr("weights/data.pkl", b"\x80\x02}q\x00.")
    return path


class _CreatesFile:
    """Unpickled, calls ``open(marker, 'w')``: the file appearing proves the pickle's code ran."""

    def __init__(self, marker: Path) -> None:
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


def code_running_pickle(path: Path, marker: Path, zipped: bool = False) -> Path:
    """A checkpoint-shaped pickle (``{'state_dict': ..., 'hyper_parameters': ...}``) holding an object
    whose unpickling creates ``marker``.

    ``zipped``: inside torch's zip format (``torch.save``'s layout, its ``data.pkl`` replaced), else a
    plain pickle (protocol 2, what torch's legacy format reads).
    """
    payload = {"state_dict": {"net.seg.weight": _CreatesFile(marker)}, "hyper_parameters": {"classes": "vkitti"}}
    evil = pickle.dumps(payload, protocol=2)
    if not zipped:
        path.write_bytes(evil)
        return path
    buffer = io.BytesIO()
    torch.save({"state_dict": {}}, buffer)
    buffer.seek(0)
    with zipfile.ZipFile(buffer) as src, zipfile.ZipFile(path, "w") as dst:
        for item in src.infolist():
            data = evil if item.filename.endswith("/data.pkl") else src.read(item.filename)
            dst.writestr(item, data)
    return path


def wrong_branch_cases(paths: Mapping[str, Path]) -> list[tuple[str, str, Path]]:
    """``(held, expected, path)`` for each branch's checkpoint ``paths[held]`` given as every other branch."""
    return [(held, expected, paths[held]) for held, expected in WRONG_BRANCH_PAIRS]


def hydra_config_with_target(path: Path, marker: Path, crop_size: int = 48, margin: float = 0.2) -> Path:
    """A run ``config.yaml`` (``datamodule.crop_size`` / ``margin``) that also names a non-project
    ``_target_``: instantiating it (Hydra) would create ``marker``; reading it must not."""
    path.write_text(
        "datamodule:\n"
        f"  crop_size: {crop_size}\n"
        f"  margin: {margin}\n"
        "callbacks:\n"
        "  evil:\n"
        "    _target_: builtins.open\n"
        f"    file: {str(marker)!r}\n"
        "    mode: w\n"
        "model:\n"
        "  _target_: os.system\n"
        f"  command: touch {marker}\n"
    )
    return path
