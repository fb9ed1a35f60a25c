"""The textural branch at inference: encode an image's regions into texture codes, render with the
trained generator (the codes themselves: :mod:`sdn3d.textural.codes`).

:class:`TexturalRenderer` is the inference API of the textural branch (no Lightning)::

    r = TexturalRenderer.from_checkpoint("outputs/train/textural/<run>/checkpoints/last.ckpt")
    codes = r.encode(image, L)                    # image (B, 3, H, W) in [0, 1], L (B, H, W)
    out = r.render(label, L, codes=codes, pose=pose, normal=normal)   # (B, 3, H, W) in [0, 1]
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import torch
from torch import Tensor, nn

from sdn3d.errors import UserInputError
from sdn3d.image_ops import boundary_map
from sdn3d.labels import class_list
from sdn3d.nets.pix2pixhd import TexturalSpec
from sdn3d.textural import codes as texture_codes
from sdn3d.textural.codes import TextureCodes

if TYPE_CHECKING:
    from sdn3d.io import TorchFiles

__all__ = ["TexturalRenderer"]


class TexturalRenderer(nn.Module):
    """Trained generator G + encoder E of the textural branch, for inference.

    Args:
        spec: network layout (see :class:`~sdn3d.nets.pix2pixhd.TexturalSpec`).
    """

    def __init__(self, spec: TexturalSpec) -> None:
        super().__init__()
        self.spec = spec
        self.generator = spec.generator()
        self.encoder = spec.encoder()
        self.eval()

    @classmethod
    def from_checkpoint(cls, path: str | Path, map_location: str | torch.device = "cpu",
                        files: TorchFiles | None = None) -> TexturalRenderer:
        """Load G and E from a ``TexturalModule`` Lightning checkpoint or its inference export
        (:mod:`sdn3d.inference_export`; ``torch.load(weights_only=True)``; through ``files`` where given,
        :func:`~sdn3d.inference_export.load_branch_weights`)."""
        from sdn3d.inference_export import load_branch_weights

        weights = load_branch_weights(path, "textural", map_location, files)
        if "classes" not in weights.hyper_parameters:
            raise UserInputError(f"textural checkpoint {str(weights.path)!r} does not name its class list "
                                 "(hyper-parameter 'classes')")
        return cls.from_state_dict(weights.state_dict, weights.hyper_parameters)

    @classmethod
    def from_state_dict(cls, state: Mapping[str, Tensor], hparams: Mapping[str, Any]) -> TexturalRenderer:
        """From a ``TexturalModule`` state dict (keys ``generator.*``, ``encoder.*``) and its hyper-parameters."""
        if "classes" not in hparams:
            raise ValueError("hparams must name the class list ('classes')")
        spec = TexturalSpec.from_mapping(hparams, num_classes=len(class_list(str(hparams["classes"]))))
        renderer = cls(spec)
        for name in ("generator", "encoder"):
            part = {k[len(name) + 1:]: v for k, v in state.items() if k.startswith(name + ".")}
            getattr(renderer, name).load_state_dict(part, strict=True)
        return renderer.eval()

    @property
    def device(self) -> torch.device:
        return next(self.parameters()).device

    @torch.no_grad()
    def encode(self, image: Tensor, L: Tensor) -> TextureCodes:
        """Codes of every region of ``L (B, H, W)`` from ``image (B, 3, H, W)`` in ``[0, 1]``."""
        if image.dim() != 4 or image.shape[1] != 3:
            raise ValueError(f"image must be (B, 3, H, W), got {tuple(image.shape)}")
        _, means, batch, ids = self.encoder.encode(image * 2 - 1, L)
        return TextureCodes(batch, ids, means)

    @torch.no_grad()
    def render(self, label: Tensor, L: Tensor, boundary: Tensor | None = None, codes: TextureCodes | None = None,
               code_map: Tensor | None = None, pose: Tensor | None = None, normal: Tensor | None = None) -> Tensor:
        """Draw ``(B, 3, H, W)`` images in ``[0, 1]``.

        Args:
            label: ``(B, H, W)`` semantic classes (instance classes win; 255 = none).
            L: ``(B, H, W)`` instance label map.
            boundary: ``(B, 1, H, W)``; None computes :func:`sdn3d.image_ops.boundary_map` of ``L``.
            codes / code_map: region codes, or an explicit ``(B, code_dim, H, W)`` map (one is required
                when the generator uses codes; regions without a code get zeros).
            pose: ``(B, 24, H, W)`` one-hot pose bins; normal: ``(B, 3, H, W)``; None = zeros.
        """
        if label.dim() != 3 or L.shape != label.shape:
            raise ValueError(f"label and L must both be (B, H, W), got {tuple(label.shape)} and {tuple(L.shape)}")
        if boundary is None:
            boundary = boundary_map(L)
        if self.spec.use_codes and code_map is None:
            if codes is None:
                raise ValueError("render needs codes or code_map: this generator was trained with texture codes")
            code_map = texture_codes.code_map(codes, L)
        cond = self.spec.condition(label, boundary)
        x = self.spec.generator_input(cond, code_map, pose, normal)
        return (self.generator(x) + 1) / 2

    @torch.no_grad()
    def reconstruct(self, image: Tensor, label: Tensor, L: Tensor, boundary: Tensor | None = None,
                    pose: Tensor | None = None, normal: Tensor | None = None) -> Tensor:
        """``render`` with the image's own codes (the branch's reconstruction)."""
        return self.render(label, L, boundary, codes=self.encode(image, L), pose=pose, normal=normal)
