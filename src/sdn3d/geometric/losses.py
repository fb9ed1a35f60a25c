"""Losses of the geometric branch (3D-SDN, Sec. 3.1): L_pred, L_reproj and the FFD regulariser.

``L_pred`` (paper) sums one term per attribute, each averaged over objects:
``||log s~ - log s||^2 + (1 - (q~ . q)^2) + ||e~ - e||^2 + (log tau~ - log tau)^2``
(squared L2; ``regression="smooth_l1"`` swaps the three regressions for smooth L1). With the ``"multibin"``
rotation (issue 40) the rotation term is the MultiBin loss of the local orientation instead, confidence
cross-entropy plus residual ``1 - cos`` (:func:`sdn3d.geometric.multibin.multibin_losses`).

``L_reproj = |S~ - S|``: the mean absolute difference between the soft silhouette ``S~`` of the
deformed, posed mesh rendered in the crop's camera and the object's visible mask ``S``, over the
crop pixels that are not ignored (pixels of closer objects, which may hide the object, and
pixels outside the image, where the mask is unknown).
"""

from __future__ import annotations

from collections.abc import Mapping

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.geometric.multibin import multibin_losses
from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.math3d.encodings import RotationMode, decode_yaw_quaternion, rotation_loss
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.objects import pose_meshes
from sdn3d.render.settings import SoftSilhouetteSettings
from sdn3d.render.silhouette import silhouette

__all__ = [
    "PRED_KEYS",
    "prediction_losses",
    "prediction_loss",
    "ffd_regularizer",
    "outside_image_mask",
    "reprojection_error",
    "render_silhouettes",
]

#: Per-attribute terms of L_pred, in the order they are logged.
PRED_KEYS = ("scale", "rotation", "offset", "distance")
_REGRESSIONS = ("l2", "smooth_l1")


def _regression(pred: Tensor, target: Tensor, kind: str) -> Tensor:
    """Per-object ``(N,)`` loss summed over components."""
    if pred.shape != target.shape:
        raise ValueError(f"prediction and target shapes differ: {tuple(pred.shape)} vs {tuple(target.shape)}")
    if kind == "l2":
        return (pred - target).square().sum(-1)
    return F.smooth_l1_loss(pred, target, reduction="none").sum(-1)


def prediction_losses(
    raw: Mapping[str, Tensor],
    targets: Mapping[str, Tensor],
    rotation: RotationMode = "yaw_quaternion",
    regression: str = "l2",
    yaw_overlap: float = 0.1,
) -> dict[str, Tensor]:
    """Per-object terms of L_pred, each ``(N,)``: ``scale``, ``rotation``, ``offset``, ``distance``.

    Args:
        raw: network outputs (``log_scale (N, 3)``, ``rotation (N, 4)``, ``offset (N, 2)``,
            ``log_distance (N, 1)``).
        targets: the dataset's ``targets`` of the same keys (:class:`AttributeEncoding` ``encode``).
        rotation: the encoding's rotation mode (the quaternion loss depends on it).
        regression: ``"l2"`` (paper: squared error) or ``"smooth_l1"``.
        yaw_overlap: the MultiBin bins' overlap (``"multibin"``: ``raw`` then also holds ``yaw_bins``,
            ``yaw_residual`` and ``yaw_ray``, and the rotation term is MultiBin's ``conf + loc`` on the true local
            orientation ``ry - yaw_ray``).
    """
    if regression not in _REGRESSIONS:
        raise ValueError(f"regression must be one of {_REGRESSIONS}, got {regression!r}")
    missing = [k for k in ("log_scale", "rotation", "offset", "log_distance") if k not in raw or k not in targets]
    if missing:
        raise ValueError(f"raw and targets must both hold {missing}")
    if rotation == "multibin":
        if any(k not in raw for k in ("yaw_bins", "yaw_residual", "yaw_ray")):
            raise ValueError("the multibin rotation needs raw yaw_bins, yaw_residual and yaw_ray (GeometricNet with "
                             "rotation='multibin')")
        alpha = decode_yaw_quaternion(targets["rotation"]) - raw["yaw_ray"]
        bins = multibin_losses(raw["yaw_bins"], raw["yaw_residual"], alpha, yaw_overlap)
        rot = bins["conf"] + bins["loc"]
    else:
        rot = rotation_loss(raw["rotation"], targets["rotation"], rotation)
    return {
        "scale": _regression(raw["log_scale"], targets["log_scale"], regression),
        "rotation": rot,
        "offset": _regression(raw["offset"], targets["offset"], regression),
        "distance": _regression(raw["log_distance"], targets["log_distance"], regression),
    }


def prediction_loss(terms: Mapping[str, Tensor]) -> Tensor:
    """L_pred: the sum over attributes of the object-averaged terms of :func:`prediction_losses`."""
    return torch.stack([terms[k].mean() for k in PRED_KEYS]).sum()


def ffd_regularizer(phi: Tensor) -> Tensor:
    """``mean(phi^2)``: keeps FFD displacements small (the released 3D-SDN code weights it by 10)."""
    return phi.square().mean()


def outside_image_mask(crop_box: Tensor, image_size: tuple[int, int], crop_size: int) -> Tensor:
    """``(N, 1, S, S)`` float: 1 where a crop pixel samples outside the image.

    Args:
        crop_box: ``(N, 4)`` crop window edges ``(l, t, r, b)`` in image pixels (the dataset's
            ``crop_box``: pixel ``j`` of the crop samples ``u = l + (j + 0.5) (r - l) / S``).
        image_size: ``(W, H)`` of the image.
        crop_size: ``S``.
    """
    if crop_box.dim() != 2 or crop_box.shape[1] != 4:
        raise ValueError(f"crop_box must have shape (N, 4), got {tuple(crop_box.shape)}")
    width, height = (int(v) for v in image_size)
    steps = (torch.arange(crop_size, device=crop_box.device, dtype=crop_box.dtype) + 0.5) / crop_size
    u = crop_box[:, :1] + steps * (crop_box[:, 2:3] - crop_box[:, :1])  # (N, S) sample positions
    v = crop_box[:, 1:2] + steps * (crop_box[:, 3:4] - crop_box[:, 1:2])
    # A sample at u is inside when its nearest pixel centre 0 .. W - 1 is: -0.5 <= u < W - 0.5.
    out_u = (u < -0.5) | (u >= width - 0.5)
    out_v = (v < -0.5) | (v >= height - 0.5)
    return (out_v[:, :, None] | out_u[:, None, :]).unsqueeze(1).to(crop_box.dtype)


def _as_maps(name: str, x: Tensor, shape: tuple[int, ...]) -> Tensor:
    if x.dim() == 4 and x.shape[1] == 1:
        x = x[:, 0]
    if tuple(x.shape) != shape:
        raise ValueError(f"{name} must have shape {shape} or (N, 1, H, W), got {tuple(x.shape)}")
    return x


def reprojection_error(silhouette: Tensor, mask: Tensor, ignore: Tensor | None = None) -> Tensor:
    """Per-object L_reproj ``(N,)``: mean ``|S~ - S|`` over the pixels not ignored.

    Args:
        silhouette: ``(N, H, W)`` soft silhouettes in ``[0, 1]``.
        mask: ``(N, H, W)`` or ``(N, 1, H, W)`` visible masks.
        ignore: same shape, 1 where pixels do not count; None counts every pixel.
    """
    if silhouette.dim() != 3:
        raise ValueError(f"silhouette must have shape (N, H, W), got {tuple(silhouette.shape)}")
    shape = tuple(silhouette.shape)
    mask = _as_maps("mask", mask, shape).to(silhouette.dtype)
    keep = torch.ones_like(mask) if ignore is None else 1.0 - _as_maps("ignore", ignore, shape).to(mask.dtype)
    err = ((silhouette - mask).abs() * keep).flatten(1).sum(1)
    return err / keep.flatten(1).sum(1).clamp_min(1.0)


def render_silhouettes(
    bank: MeshBank,
    template_ids: Tensor,
    dims: Tensor,
    ry: Tensor,
    center: Tensor,
    phi: Tensor | None,
    crop_intrinsics: Tensor,
    settings: SoftSilhouetteSettings | int | tuple[int, int],
    kind: str = "soft",
) -> Tensor:
    """Silhouettes ``(N, H, W)`` of deformed, posed templates in each object's crop camera.

    Differentiable w.r.t. ``dims``, ``ry``, ``center`` and ``phi`` (not the template choice).

    Args:
        bank: mesh templates (on the device of the inputs).
        template_ids: ``(N,)`` mesh ids.
        dims, ry, center: ``(N, 3)``, ``(N,)``, ``(N, 3)`` object placement (camera frame).
        phi: ``(N, 64, 3)`` FFD displacements or None.
        crop_intrinsics: ``(N, 4)`` ``(fx, fy, cx, cy)`` or ``(N, 3, 3)`` of each crop.
        settings: the soft rasterizer's settings, or just the crop size (a side ``S`` or ``(H, W)``) with
            the default settings.
        kind: ``"soft"`` (SoftRas) or ``"straight_through"`` (hard values, soft gradient; unbiased under L1:
            :mod:`sdn3d.render.silhouette`).
    """
    if not isinstance(settings, SoftSilhouetteSettings):
        settings = SoftSilhouetteSettings((settings, settings) if isinstance(settings, int) else tuple(settings))
    verts, faces = pose_meshes(bank, template_ids, dims, ry, center, phi)
    K = as_intrinsics_matrix(crop_intrinsics, dims.shape[0]).to(verts.dtype)
    return silhouette(kind, verts, faces, K, settings)
