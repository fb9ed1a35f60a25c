"""Evaluation metrics of the geometric branch (3D-SDN, Table 2), functional and as torchmetrics.

- orientation similarity ``(1 + cos theta) / 2``, ``theta`` the geodesic angle between the
  predicted and true rotations (``cos theta = (tr(R~^T R) - 1) / 2``, so the similarity is
  ``(tr(R~^T R) + 1) / 4``); 1 is perfect, 0 is a half turn;
- distance error ``|log t - log t~|`` with ``t = |c|`` the distance of the box centre;
- scale error ``||s - s~||_2`` with ``s = (l, h, w)`` in metres;
- reprojection error: mean ``|S~ - S|`` over all non-ignored crop pixels (pooled over objects);
- mesh-selection accuracy over objects whose true template is known (``template_id >= 0``).

Each metric is a sum and a count (``dist_reduce_fx="sum"``), so DDP reduction is exact.
"""

from __future__ import annotations

from collections.abc import Mapping

import torch
import torch.nn.functional as F
from kornia.geometry.conversions import quaternion_to_rotation_matrix
from torch import Tensor, nn
from torchmetrics import Metric

from sdn3d.math3d.encodings import RotationMode
from sdn3d.math3d.rotations import roty

__all__ = [
    "orientation_similarity",
    "distance_error",
    "scale_error",
    "predicted_rotation",
    "OrientationSimilarity",
    "DistanceErrorMetric",
    "ScaleErrorMetric",
    "ReprojectionErrorMetric",
    "MeshSelectionAccuracy",
    "GeometricMetrics",
    "METRIC_NAMES",
]

#: Metric names as logged (``val/<name>``, ``test/<name>``).
METRIC_NAMES = ("orientation_similarity", "distance_error", "scale_error", "reprojection_error", "mesh_accuracy")


def _check_rot(name: str, rot: Tensor) -> None:
    if rot.dim() != 3 or rot.shape[1:] != (3, 3):
        raise ValueError(f"{name} must have shape (N, 3, 3), got {tuple(rot.shape)}")


def orientation_similarity(pred_rot: Tensor, target_rot: Tensor) -> Tensor:
    """``(1 + cos theta) / 2`` per object, ``(N,)``, for ``(N, 3, 3)`` rotation matrices."""
    _check_rot("pred_rot", pred_rot)
    _check_rot("target_rot", target_rot)
    trace = (pred_rot * target_rot).sum(dim=(-2, -1))  # tr(A^T B) = sum_ij A_ij B_ij
    return ((trace + 1.0) / 4.0).clamp(0.0, 1.0)


def distance_error(pred_center: Tensor, target_center: Tensor) -> Tensor:
    """``|log |c~| - log |c||`` per object, ``(N,)``, for ``(N, 3)`` box centres."""
    if pred_center.shape != target_center.shape or pred_center.shape[-1] != 3:
        raise ValueError(
            f"centres must both be (N, 3), got {tuple(pred_center.shape)} and {tuple(target_center.shape)}"
        )
    return (pred_center.norm(dim=-1).log() - target_center.norm(dim=-1).log()).abs()


def scale_error(pred_dims: Tensor, target_dims: Tensor) -> Tensor:
    """``||s~ - s||_2`` per object, ``(N,)``, for ``(N, 3)`` dimensions ``(l, h, w)``."""
    if pred_dims.shape != target_dims.shape or pred_dims.shape[-1] != 3:
        raise ValueError(f"dims must both be (N, 3), got {tuple(pred_dims.shape)} and {tuple(target_dims.shape)}")
    return (pred_dims - target_dims).norm(dim=-1)


def predicted_rotation(rotation: Tensor, ry: Tensor, mode: RotationMode = "yaw_quaternion") -> Tensor:
    """``(N, 3, 3)`` predicted rotation: ``R_y(ry)`` for yaw quaternions, the normalised full quaternion otherwise.

    The full-quaternion ablation is scored on its whole rotation (tilt included), as predicted.
    """
    if mode == "yaw_quaternion":
        return roty(ry)
    return quaternion_to_rotation_matrix(F.normalize(rotation, dim=-1, eps=1e-8))


class _SumCount(Metric):
    """Mean of per-item values as a sum and a count."""

    full_state_update = False

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.add_state("total", default=torch.zeros((), dtype=torch.float64), dist_reduce_fx="sum")
        self.add_state("count", default=torch.zeros((), dtype=torch.float64), dist_reduce_fx="sum")

    def _add(self, values: Tensor, count: Tensor | float | None = None) -> None:
        self.total += values.detach().double().sum()
        self.count += values.numel() if count is None else count

    def compute(self) -> Tensor:
        """The mean; NaN before any update (or, for mesh accuracy, without any labelled object)."""
        return (self.total / self.count).float() if self.count > 0 else torch.tensor(float("nan"))


class OrientationSimilarity(_SumCount):
    """Mean ``(1 + cos theta) / 2``; ``update(pred_rot (N, 3, 3), target_rot (N, 3, 3))``."""

    higher_is_better = True

    def update(self, pred_rot: Tensor, target_rot: Tensor) -> None:
        self._add(orientation_similarity(pred_rot, target_rot))


class DistanceErrorMetric(_SumCount):
    """Mean ``|log t - log t~|``; ``update(pred_center (N, 3), target_center (N, 3))``."""

    higher_is_better = False

    def update(self, pred_center: Tensor, target_center: Tensor) -> None:
        self._add(distance_error(pred_center, target_center))


class ScaleErrorMetric(_SumCount):
    """Mean ``||s - s~||_2``; ``update(pred_dims (N, 3), target_dims (N, 3))``."""

    higher_is_better = False

    def update(self, pred_dims: Tensor, target_dims: Tensor) -> None:
        self._add(scale_error(pred_dims, target_dims))


class ReprojectionErrorMetric(_SumCount):
    """Per-pixel mean ``|S~ - S|`` over non-ignored pixels; ``update(silhouette (N, H, W), mask, ignore=None)``.

    ``mask`` and ``ignore`` are ``(N, H, W)`` or ``(N, 1, H, W)``; ignored pixels (value 1) do not count.
    """

    higher_is_better = False

    def update(self, silhouette: Tensor, mask: Tensor, ignore: Tensor | None = None) -> None:
        if silhouette.dim() != 3:
            raise ValueError(f"silhouette must have shape (N, H, W), got {tuple(silhouette.shape)}")
        mask = mask.reshape(silhouette.shape).to(silhouette.dtype)
        keep = torch.ones_like(mask) if ignore is None else 1.0 - ignore.reshape(silhouette.shape).to(mask.dtype)
        self._add((silhouette - mask).abs() * keep, keep.detach().double().sum())


class MeshSelectionAccuracy(_SumCount):
    """Fraction of objects with a known template (``target >= 0``) whose predicted template is right.

    ``update(pred_ids (N,), target_ids (N,))``; ``compute()`` is NaN when no object was labelled.
    """

    higher_is_better = True

    def update(self, pred_ids: Tensor, target_ids: Tensor) -> None:
        if pred_ids.shape != target_ids.shape or pred_ids.dim() != 1:
            raise ValueError(f"ids must both be (N,), got {tuple(pred_ids.shape)} and {tuple(target_ids.shape)}")
        known = target_ids >= 0
        self._add((pred_ids.to(target_ids.device) == target_ids) & known, known.sum())


class GeometricMetrics(nn.Module):
    """The five metrics of Table 2 together.

    ``update(pred, target, silhouette=None, ignore=None)`` with ``pred`` from
    :func:`~sdn3d.geometric.predict.decode_outputs` plus ``rot (N, 3, 3)`` (see
    :func:`predicted_rotation`) and ``target`` a dataset batch (``ry``, ``center``, ``dims``,
    ``template_id``, ``mask``); the reprojection error is updated only with a silhouette.
    """

    def __init__(self) -> None:
        super().__init__()
        self.metrics = nn.ModuleDict({
            "orientation_similarity": OrientationSimilarity(),
            "distance_error": DistanceErrorMetric(),
            "scale_error": ScaleErrorMetric(),
            "reprojection_error": ReprojectionErrorMetric(),
            "mesh_accuracy": MeshSelectionAccuracy(),
        })

    def __getitem__(self, name: str) -> Metric:
        return self.metrics[name]

    def update(
        self,
        pred: Mapping[str, Tensor],
        target: Mapping[str, Tensor],
        silhouette: Tensor | None = None,
        ignore: Tensor | None = None,
    ) -> None:
        m = self.metrics
        m["orientation_similarity"].update(pred["rot"], roty(target["ry"].to(pred["rot"].dtype)))
        m["distance_error"].update(pred["center"], target["center"])
        m["scale_error"].update(pred["dims"], target["dims"])
        m["mesh_accuracy"].update(pred["template_id"], target["template_id"])
        if silhouette is not None:
            m["reprojection_error"].update(silhouette, target["mask"], ignore)

    def compute(self) -> dict[str, Tensor]:
        return {name: metric.compute() for name, metric in self.metrics.items()}

    def reset(self) -> None:
        for metric in self.metrics.values():
            metric.reset()
