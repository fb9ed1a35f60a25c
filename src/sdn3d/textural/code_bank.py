"""The code bank file: texture codes of the training regions with their mean colours, and named colours.

``sdn3d-train branch=textural`` writes one bank next to each checkpoint it keeps (best and last):
``<checkpoint stem>.code_bank.json`` (:func:`code_bank_path`), built by :func:`build_code_bank` with that
checkpoint's encoder E over the training part. The file is plain JSON (exact float reprs, no pickle)::

    {"format": "sdn3d-code-bank", "version": 1, "code_dim": 5, "color_space": "sRGB [0, 1]",
     "checkpoint": "last.ckpt", "classes": {"12": {"codes": [[...5 floats], ...], "colors": [[r, g, b], ...]}, ...}}

one row per training region: objects (instance ids) and background classes, grouped by semantic class; the
colour is the region's mean RGB in the training image. An edit then picks a code by colour name
(:func:`named_color`, :meth:`~sdn3d.textural.codes.CodeBank.nearest`: the code whose region's mean colour is
nearest in CIE Lab, :func:`~sdn3d.textural.codes.rgb_to_lab`) or draws one
(:meth:`~sdn3d.textural.codes.CodeBank.sample`).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.io import write_json_atomic
from sdn3d.nets.pix2pixhd import TextureEncoder, instance_mean
from sdn3d.textural.codes import CodeBank

__all__ = ["BANK_FORMAT", "NAMED_COLORS", "CodeBankFileError", "build_code_bank", "code_bank_path",
           "load_code_bank", "named_color", "save_code_bank"]

BANK_FORMAT = "sdn3d-code-bank"
BANK_VERSION = 1

#: Colour names a user may type (``recolor: {color: red}``) -> sRGB in [0, 1]. Values are typical painted
#: car bodies as a street photograph shows them (not the saturated primaries), so "red" finds red cars
#: rather than the orange ones.
NAMED_COLORS: dict[str, tuple[float, float, float]] = {
    "red": (0.70, 0.08, 0.08),
    "orange": (0.90, 0.45, 0.08),
    "yellow": (0.90, 0.80, 0.15),
    "green": (0.15, 0.50, 0.20),
    "blue": (0.10, 0.25, 0.70),
    "dark blue": (0.05, 0.10, 0.35),
    "purple": (0.45, 0.15, 0.55),
    "brown": (0.45, 0.28, 0.12),
    "beige": (0.80, 0.72, 0.55),
    "white": (0.92, 0.92, 0.90),
    "silver": (0.70, 0.71, 0.73),
    "grey": (0.42, 0.43, 0.44),
    "black": (0.06, 0.06, 0.07),
}
_ALIASES = {"gray": "grey", "navy": "dark blue", "violet": "purple"}


class CodeBankFileError(UserInputError):
    """A code bank file that is missing, not JSON or not a code bank (the message names the file)."""


def named_color(name: str, what: str = "color") -> tuple[float, float, float]:
    """sRGB ``(r, g, b)`` in [0, 1] of a colour name (case and ``_`` / ``-`` / space insensitive).

    Raises:
        UserInputError: an unknown name; the message names ``what`` and lists the known names.
    """
    key = "".join(str(name).lower().replace("_", " ").replace("-", " ").split())
    names = {n.replace(" ", ""): n for n in NAMED_COLORS} | {a: n for a, n in _ALIASES.items()}
    if key not in names:
        raise UserInputError(f"{what}: unknown colour {name!r}; known colours: {', '.join(NAMED_COLORS)} "
                             f"(and {', '.join(_ALIASES)})")
    return NAMED_COLORS[names[key]]


@torch.no_grad()
def build_code_bank(encoder: TextureEncoder, batches: Iterable[Mapping[str, Tensor]]) -> CodeBank:
    """Codes and mean colours of every region of ``batches`` (the training part), grouped by class.

    Args:
        encoder: the texture encoder E (its own device; put in eval mode here).
        batches: mappings with ``image (B, 3, H, W)`` in [0, 1] and ``instance_label_map (B, H, W)``.
    """
    encoder.eval()
    device = next(encoder.parameters()).device
    codes, colors, ids = [], [], []
    for batch in batches:
        image = batch["image"].to(device, torch.float32)
        L = batch["instance_label_map"].to(device)
        _, means, _, region_ids = encoder.encode(image * 2 - 1, L)
        _, region_colors, _, _ = instance_mean(image, L)
        codes.append(means.float().cpu())
        colors.append(region_colors.float().cpu())
        ids.append(region_ids.cpu())
    if not codes:
        return CodeBank({}, {})
    return CodeBank.from_regions(torch.cat(ids), torch.cat(codes), torch.cat(colors))


def code_bank_path(checkpoint: str | os.PathLike) -> Path:
    """The bank file that belongs to a textural checkpoint: ``<dir>/<stem>.code_bank.json``."""
    checkpoint = Path(checkpoint)
    return checkpoint.with_name(f"{checkpoint.stem}.code_bank.json")


def save_code_bank(bank: CodeBank, path: str | os.PathLike, checkpoint: str | None = None) -> Path:
    """Write ``bank`` as JSON, atomically (``checkpoint``: the file name of the weights it was encoded with)."""
    if bank.colors is None:
        raise ValueError("a code bank file keeps the regions' colours: build the bank with colours")
    classes = {str(c): {"codes": bank.codes[c].tolist(), "colors": bank.colors[c].tolist()} for c in bank.classes}
    return write_json_atomic(path, {"format": BANK_FORMAT, "version": BANK_VERSION, "code_dim": bank.code_dim,
                                    "color_space": "sRGB [0, 1]", "checkpoint": checkpoint, "classes": classes},
                             indent=None)


def _matrix(value: Any, width: int | None, where: str) -> Tensor:
    if not isinstance(value, list) or not value or not all(isinstance(r, list) for r in value):
        raise CodeBankFileError(f"{where} must be a non-empty list of rows")
    widths = {len(r) for r in value}
    if len(widths) != 1 or (width is not None and widths != {width}):
        raise CodeBankFileError(f"{where} rows must all have {width or 'the same number of'} values, "
                                f"got {sorted(widths)}")
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for r in value for x in r):
        raise CodeBankFileError(f"{where} must hold finite numbers only")
    return torch.tensor(value, dtype=torch.float32)


def load_code_bank(path: str | os.PathLike, what: str = "code_bank") -> CodeBank:
    """Read a bank written by :func:`save_code_bank`; every field is checked.

    Raises:
        CodeBankFileError: naming ``what`` and the file (missing, not JSON, not a bank, bad rows).
    """
    path = Path(path).expanduser()
    where = f"{what} {str(path)!r}"
    if not path.is_file():
        raise CodeBankFileError(f"{where} not found (sdn3d-train branch=textural writes <checkpoint>.code_bank.json "
                                "next to each checkpoint)")
    try:
        data = json.loads(path.read_bytes().decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise CodeBankFileError(f"{where} is not a code bank JSON file ({type(exc).__name__}: {exc})") from None
    if not isinstance(data, dict) or data.get("format") != BANK_FORMAT or data.get("version") != BANK_VERSION:
        raise CodeBankFileError(f"{where} is not a code bank (format {BANK_FORMAT!r}, version {BANK_VERSION})")
    dim, classes = data.get("code_dim"), data.get("classes")
    if isinstance(dim, bool) or not isinstance(dim, int) or dim < 1 or not isinstance(classes, dict) or not classes:
        raise CodeBankFileError(f"{where}: needs an integer code_dim >= 1 and a non-empty 'classes' mapping")
    codes, colors = {}, {}
    for key, entry in classes.items():
        if not key.isdigit() or not isinstance(entry, dict):
            raise CodeBankFileError(f"{where}: classes must map class ids to {{codes, colors}}, got key {key!r}")
        codes[int(key)] = _matrix(entry.get("codes"), dim, f"{where}: classes.{key}.codes")
        colors[int(key)] = _matrix(entry.get("colors"), 3, f"{where}: classes.{key}.colors")
        if codes[int(key)].shape[0] != colors[int(key)].shape[0]:
            raise CodeBankFileError(f"{where}: classes.{key} has {codes[int(key)].shape[0]} codes but "
                                    f"{colors[int(key)].shape[0]} colours")
    return CodeBank(codes, colors)
