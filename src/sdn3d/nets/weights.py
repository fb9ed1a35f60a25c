"""Optional pretrained weights from a local file (no downloads: CI and this machine are offline).

Checkpoints use torchvision's parameter names (``conv1.weight``, ``layer1.0.bn1.running_mean``,
``features.0.weight`` ...), so a file saved from ``torchvision.models.resnet18(weights=...)``
.state_dict() loads as is. Loading is never silently partial: every expected key of the selected
part must be present with the right shape, and unexpected keys are an error unless the caller
lists the prefixes it drops (e.g. the ImageNet classifier ``fc.``).
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping
from pathlib import Path

import torch
from torch import Tensor, nn

from sdn3d.errors import UserInputError
from sdn3d.io import describe_load_failure

__all__ = ["PretrainedWeightsError", "load_pretrained", "read_state_dict"]

log = logging.getLogger(__name__)


class PretrainedWeightsError(UserInputError):
    """A weights file is missing, unreadable or does not match the network."""


def read_state_dict(path: str | Path) -> dict[str, Tensor]:
    """The tensors of a local ``.pth``/``.pt`` file (a state dict, or a Lightning checkpoint).

    Loaded with ``weights_only=True``: a weights file can not run code.
    """
    path = Path(path).expanduser()
    if not path.is_file():
        raise PretrainedWeightsError(f"pretrained weights file {str(path)!r} does not exist")
    try:
        state = torch.load(path, map_location="cpu", weights_only=True)
    except Exception as exc:  # whatever unpickling the user's file raises (IndexError, KeyError, ...), it is bad
        raise PretrainedWeightsError(f"could not read pretrained weights {str(path)!r}: "
                                     f"{describe_load_failure(exc)}") from exc
    if isinstance(state, Mapping) and "state_dict" in state and isinstance(state["state_dict"], Mapping):
        state = state["state_dict"]
    if not isinstance(state, Mapping) or not all(isinstance(v, Tensor) for v in state.values()):
        raise PretrainedWeightsError(f"{str(path)!r} does not hold a state dict of tensors")
    return dict(state)


def load_pretrained(
    module: nn.Module,
    path: str | Path | None,
    *,
    what: str = "network",
    strip_prefix: str = "",
    ignore_prefixes: Iterable[str] = (),
) -> bool:
    """Load ``path`` into ``module`` strictly; ``None`` keeps the random initialisation and says so.

    Args:
        module: the network (its ``state_dict`` names are the torchvision names).
        path: local weights file, or None.
        what: name used in messages (e.g. ``'ResNet-18 backbone'``).
        strip_prefix: removed from the file's keys first (e.g. ``'module.'``).
        ignore_prefixes: file keys starting with these are dropped (e.g. ``('fc.',)``).

    Returns:
        True when weights were loaded, False when ``path`` is None.
    """
    if path is None or str(path) == "":
        log.warning("%s: no pretrained weights file given; training from random initialisation", what)
        return False
    state = read_state_dict(path)
    ignore = tuple(ignore_prefixes)
    cleaned = {}
    for key, value in state.items():
        if strip_prefix and key.startswith(strip_prefix):
            key = key[len(strip_prefix):]
        if ignore and key.startswith(ignore):
            continue
        cleaned[key] = value
    expected = module.state_dict()
    # BatchNorm's num_batches_tracked counter (PyTorch >= 0.4.1) is absent from older published checkpoints
    # (e.g. DRN 2017); it only matters for momentum=None, so a missing one keeps its initial value.
    missing = sorted(k for k in set(expected) - set(cleaned) if not k.endswith("num_batches_tracked"))
    unexpected = sorted(set(cleaned) - set(expected))
    wrong = sorted(k for k in set(expected) & set(cleaned) if expected[k].shape != cleaned[k].shape)
    if missing or unexpected or wrong:
        def head(keys: list[str]) -> str:
            return ", ".join(keys[:5]) + (f" (+{len(keys) - 5} more)" if len(keys) > 5 else "")

        parts = []
        if missing:
            parts.append(f"missing keys: {head(missing)}")
        if unexpected:
            parts.append(f"unexpected keys: {head(unexpected)}")
        if wrong:
            parts.append("shape mismatch: " + head(
                [f"{k} {tuple(cleaned[k].shape)} vs {tuple(expected[k].shape)}" for k in wrong]))
        raise PretrainedWeightsError(f"{what}: weights file {str(path)!r} does not match; " + "; ".join(parts))
    for key in set(expected) - set(cleaned):  # only num_batches_tracked here (checked above)
        cleaned[key] = expected[key]
    module.load_state_dict(cleaned, strict=True)
    log.info("%s: loaded pretrained weights from %s", what, path)
    return True
