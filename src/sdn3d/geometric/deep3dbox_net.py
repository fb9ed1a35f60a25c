"""An independent Deep3DBox baseline (Mousavian et al., CVPR 2017) for Table 2: its own ResNet-18 on the
geometric branch's masked object crops, MultiBin orientation and dimension residuals, and the 2D-box
translation fit of :mod:`sdn3d.geometric.deep3dbox`.

Heads (each a two-layer MLP on the pooled ResNet-18 features; the crop alone, no box features, as in the
paper, which regresses only what the crop's appearance determines):

- ``conf_logits (N, B)`` and ``residual (N, B, 2)`` (unit ``(cos, sin)``): MultiBin
  (:mod:`sdn3d.geometric.multibin`) of the *local* orientation ``alpha = wrap(ry - theta_ray)``,
  ``theta_ray = atan2((u - cx) / fx, 1)`` the azimuth of the ray through the 2D box centre ``u``
  (:func:`ray_angle`). Training and decoding use the same ray, so a perfect ``alpha`` gives the exact yaw.
  (KITTI's stored alpha uses the ray through the 3D centre, unknown at test time; the two differ by the
  offset between the 2D box centre and the projected 3D centre.)
- ``dims_residual (N, 3)``: ``(l, h, w) - mean_dims``, metres; ``mean_dims`` is a persistent buffer (the
  class mean, set from the training part's targets with :meth:`Deep3DBoxNet.set_mean_dims`, so
  checkpoints carry it). The geometric branch sees one class (vehicles), hence one mean.

:func:`decode_deep3dbox` turns the outputs into ``dims``, ``ry`` and the box centre from
:func:`~sdn3d.geometric.deep3dbox.solve_translation` (the 3D box's projection fitted to the 2D box). The
silhouette of this baseline is one mesh template without FFD (``templates``, ``use_ffd = False``: the
attributes :class:`~sdn3d.geometric.model.GeometricNet` exposes to the renderer).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import torch
from torch import Tensor, nn

from sdn3d.geometric.deep3dbox import solve_translation
from sdn3d.geometric.multibin import decode_multibin, normalize_residual
from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.math3d.rotations import wrap_angle
from sdn3d.math3d.transforms import center_to_bottom
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.nets.resnet import resnet18
from sdn3d.nets.vgg import IMAGENET_MEAN, IMAGENET_STD

__all__ = ["Deep3DBoxNet", "ray_angle", "local_yaw", "global_yaw", "pinhole_center", "decode_deep3dbox",
           "DEEP3DBOX_OUTPUT_KEYS", "MIN_DIM"]

#: Keys of :meth:`Deep3DBoxNet.forward`'s output.
DEEP3DBOX_OUTPUT_KEYS = ("conf_logits", "residual", "dims_residual")
#: Decoded dimensions are clamped to at least this many metres (the box fit needs positive sizes).
MIN_DIM = 0.05


def _check_boxes(box: Tensor, intrinsics: Tensor) -> None:
    if box.dim() != 2 or box.shape[1] != 4:
        raise ValueError(f"box must have shape (N, 4) as (l, t, r, b), got {tuple(box.shape)}")
    if intrinsics.shape != box.shape:
        raise ValueError(f"intrinsics must have shape ({box.shape[0]}, 4) as (fx, fy, cx, cy), got "
                         f"{tuple(intrinsics.shape)}")


def ray_angle(box: Tensor, intrinsics: Tensor) -> Tensor:
    """``(N,)`` azimuth ``atan2(x, z)`` of the ray through the centres of ``(N, 4)`` boxes ``(l, t, r, b)``.

    ``intrinsics``: ``(N, 4)`` ``(fx, fy, cx, cy)`` of the image the boxes are in.
    """
    _check_boxes(box, intrinsics)
    u = 0.5 * (box[:, 0] + box[:, 2])
    return torch.atan2((u - intrinsics[:, 2]) / intrinsics[:, 0], torch.ones_like(u))


def local_yaw(ry: Tensor, box: Tensor, intrinsics: Tensor) -> Tensor:
    """``(N,)`` local orientation ``wrap(ry - ray_angle(box))``: the target of the MultiBin head."""
    return wrap_angle(ry - ray_angle(box, intrinsics))


def global_yaw(alpha: Tensor, box: Tensor, intrinsics: Tensor) -> Tensor:
    """``(N,)`` yaw ``wrap(alpha + ray_angle(box))``: the inverse of :func:`local_yaw`."""
    return wrap_angle(alpha + ray_angle(box, intrinsics))


def pinhole_center(box: Tensor, dims: Tensor, intrinsics: Tensor) -> Tensor:
    """``(N, 3)`` box centre on the ray through the 2D box centre at the depth ``z = fy h / (b - t)``.

    The fallback where the box fit has no candidate in front of the camera.
    """
    _check_boxes(box, intrinsics)
    fx, fy, cx, cy = intrinsics.unbind(1)
    z = fy * dims[:, 1] / (box[:, 3] - box[:, 1]).clamp_min(1e-3)
    u, v = 0.5 * (box[:, 0] + box[:, 2]), 0.5 * (box[:, 1] + box[:, 3])
    return torch.stack([(u - cx) / fx * z, (v - cy) / fy * z, z], dim=1)


class Deep3DBoxNet(nn.Module):
    """ResNet-18 crop encoder + MultiBin and dimension-residual heads (see the module doc).

    Args:
        num_bins: MultiBin bins (paper: 2).
        hidden: width of each head's hidden layer.
        template: the one mesh id (index into :data:`~sdn3d.meshes.templates.TEMPLATE_NAMES`) its silhouette uses.
        pretrained: optional local ResNet-18 weights file (torchvision names; ``fc.`` dropped).
        mean_dims: initial class-mean ``(l, h, w)`` in metres, until :meth:`set_mean_dims` sets it from data.
    """

    use_ffd = False

    def __init__(
        self,
        num_bins: int = 2,
        hidden: int = 256,
        template: int = TEMPLATE_NAMES.index("sedan"),
        pretrained: str | Path | None = None,
        mean_dims: Sequence[float] = (4.0, 1.6, 1.8),
    ) -> None:
        super().__init__()
        if num_bins < 1 or hidden <= 0:
            raise ValueError(f"need num_bins >= 1 and hidden > 0, got {num_bins} and {hidden}")
        if not 0 <= int(template) < len(TEMPLATE_NAMES):
            raise ValueError(f"template must be a mesh id in [0, {len(TEMPLATE_NAMES)}), got {template}")
        self.num_bins = int(num_bins)
        self.register_buffer("templates", torch.tensor([int(template)], dtype=torch.long), persistent=False)
        self.register_buffer("mean_dims", self._checked_dims(torch.as_tensor(mean_dims, dtype=torch.float32)))
        self.register_buffer("mean", torch.tensor(IMAGENET_MEAN).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("std", torch.tensor(IMAGENET_STD).view(1, 3, 1, 1), persistent=False)
        self.backbone = resnet18(num_classes=None, pretrained=pretrained)
        features = self.backbone.num_features

        def head(out: int) -> nn.Sequential:
            return nn.Sequential(nn.Linear(features, hidden), nn.ReLU(inplace=True), nn.Linear(hidden, out))

        self.heads = nn.ModuleDict({"conf_logits": head(num_bins), "residual": head(2 * num_bins),
                                    "dims_residual": head(3)})
        with torch.no_grad():  # start at the class mean
            nn.init.zeros_(self.heads["dims_residual"][-1].weight)
            nn.init.zeros_(self.heads["dims_residual"][-1].bias)

    @property
    def num_templates(self) -> int:
        return int(self.templates.numel())

    @staticmethod
    def _checked_dims(mean: Tensor) -> Tensor:
        if mean.shape != (3,) or not bool(torch.isfinite(mean).all()) or bool((mean <= 0).any()):
            raise ValueError(f"mean_dims must be three positive lengths (l, h, w), got {mean.tolist()}")
        return mean

    @torch.no_grad()
    def set_mean_dims(self, dims: Tensor) -> None:
        """Set the class mean from ``(M, 3)`` training dimensions ``(l, h, w)`` (``M >= 1``)."""
        if dims.dim() != 2 or dims.shape[1] != 3 or dims.shape[0] == 0:
            raise ValueError(f"dims must have shape (M, 3) with M >= 1, got {tuple(dims.shape)}")
        self.mean_dims.copy_(self._checked_dims(dims.double().mean(0).float()))

    def forward(self, crop: Tensor) -> dict[str, Tensor]:
        """Raw outputs for ``(N, 3, S, S)`` masked crops in ``[0, 1]``: ``conf_logits (N, B)``, ``residual
        (N, B, 2)`` (unit vectors) and ``dims_residual (N, 3)``."""
        if crop.dim() != 4 or crop.shape[1] != 3:
            raise ValueError(f"crop must have shape (N, 3, S, S), got {tuple(crop.shape)}")
        feats = self.backbone((crop - self.mean) / self.std)
        residual = self.heads["residual"](feats).view(crop.shape[0], self.num_bins, 2)
        return {"conf_logits": self.heads["conf_logits"](feats), "residual": normalize_residual(residual),
                "dims_residual": self.heads["dims_residual"](feats)}


def decode_deep3dbox(
    out: Mapping[str, Tensor],
    mean_dims: Tensor,
    box: Tensor,
    intrinsics: Tensor,
    box_pad: float = 0.5,
    sides: Tensor | None = None,
) -> dict[str, Tensor]:
    """Object attributes from :meth:`Deep3DBoxNet.forward` outputs (no gradients through the translation).

    Args:
        out: the net's outputs for ``N`` objects.
        mean_dims: ``(3,)`` class-mean ``(l, h, w)`` the residuals are relative to.
        box: ``(N, 4)`` 2D boxes ``(l, t, r, b)`` in pixels of the image ``intrinsics`` describe.
        intrinsics: ``(N, 4)`` ``(fx, fy, cx, cy)``.
        box_pad: pixels added on every side of ``box`` before the fit (a box through pixel centres is half a
            native pixel smaller than the object's projection).
        sides: optional ``(N, 4)`` bool box sides to fit (:func:`~sdn3d.geometric.deep3dbox.border_sides`).

    Returns:
        ``alpha (N,)``, ``ry (N,)``, ``dims (N, 3)`` (at least :data:`MIN_DIM`), ``center (N, 3)`` box centre and
        ``location (N, 3)`` bottom-face centre (camera frame), ``fit_valid (N,)`` bool (False: no fitted
        candidate lay in front of the camera; the centre is :func:`pinhole_center`'s) and ``fit_iou (N,)``.
    """
    _check_boxes(box, intrinsics)
    alpha = decode_multibin(out["conf_logits"], out["residual"])
    ry = global_yaw(alpha, box, intrinsics)
    dims = (mean_dims.to(out["dims_residual"].dtype) + out["dims_residual"]).clamp_min(MIN_DIM)
    padded = box + box.new_tensor([-box_pad, -box_pad, box_pad, box_pad])
    solution = solve_translation(padded, dims.detach(), ry.detach(), as_intrinsics_matrix(intrinsics, box.shape[0]),
                                 sides=sides)
    center = torch.where(solution.valid[:, None], solution.center.to(dims.dtype),
                         pinhole_center(padded, dims.detach(), intrinsics).to(dims.dtype))
    return {"alpha": alpha, "ry": ry, "dims": dims, "center": center, "location": center_to_bottom(center, dims[:, 1]),
            "fit_valid": solution.valid, "fit_iou": solution.iou}
