"""Tiny random-weight branch networks and fake Lightning checkpoints (editing / benchmark tests).

Checkpoints have the layout the predictors read (``{'state_dict': ..., 'hyper_parameters': ...}``,
``net.`` / ``generator.`` / ``encoder.`` prefixes), so tests exercise the real loading code
without any training.
"""

from __future__ import annotations

from pathlib import Path

import torch

from sdn3d.geometric.model import GeometricNet
from sdn3d.nets.drn import DRNSeg
from sdn3d.nets.pix2pixhd import TexturalSpec

SEMANTIC_HP = {"classes": "vkitti", "arch": "drn_d_22", "channels": [4, 4, 8, 8, 16, 16, 16, 16],
               "instance_head": True, "head_channels": 8, "min_area": 1}
GEOMETRIC_HP = {"rotation": "yaw_quaternion", "distance": "log_tau", "hidden": 16}
TEXTURAL_HP = {"classes": "vkitti", "code_dim": 5, "ngf": 4, "n_downsampling": 2, "n_blocks": 1, "nef": 4,
               "n_downsampling_encoder": 2, "ndf": 4}


def semantic_net() -> DRNSeg:
    return DRNSeg(14, channels=SEMANTIC_HP["channels"], head_channels=SEMANTIC_HP["head_channels"]).eval()


def geometric_net() -> GeometricNet:
    return GeometricNet(hidden=GEOMETRIC_HP["hidden"]).eval()


def textural_spec() -> TexturalSpec:
    return TexturalSpec.from_mapping(TEXTURAL_HP, num_classes=14)


def write_checkpoints(folder: Path, seed: int = 0) -> dict[str, Path]:
    """Save ``semantic.ckpt``, ``geometric.ckpt`` and ``textural.ckpt`` with random weights into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(seed)
    paths = {name: folder / f"{name}.ckpt" for name in ("semantic", "geometric", "textural")}
    torch.save({"state_dict": {f"net.{k}": v for k, v in semantic_net().state_dict().items()},
                "hyper_parameters": dict(SEMANTIC_HP)}, paths["semantic"])
    torch.save({"state_dict": {f"net.{k}": v for k, v in geometric_net().state_dict().items()},
                "hyper_parameters": dict(GEOMETRIC_HP)}, paths["geometric"])
    spec = textural_spec()
    state = {f"generator.{k}": v for k, v in spec.generator().state_dict().items()}
    state |= {f"encoder.{k}": v for k, v in spec.encoder().state_dict().items()}
    torch.save({"state_dict": state, "hyper_parameters": dict(TEXTURAL_HP)}, paths["textural"])
    return paths
