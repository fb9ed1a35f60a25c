"""Evaluation metrics of the geometric branch (3D-SDN, Table 2), functional and as torchmetrics.

Pose and size, means over objects:

- orientation similarity ``(1 + cos theta) / 2``, ``theta`` the geodesic angle between the
  predicted and true rotations (``cos theta = (tr(R~^T R) - 1) / 2``, so the similarity is
  ``(tr(R~^T R) + 1) / 4``); 1 is perfect, 0 is a half turn;
- distance error ``|log t - log t~|`` with ``t = |c|`` the distance of the box centre;
- scale error ``||s - s~||_2`` with ``s = (l, h, w)`` in metres.

Reprojection, two figures:

- ``reprojection_error_image`` (the paper's, Table 2's last column): per object, the image pixels where the
  **hard** silhouette of the predicted mesh (template, FFD, size, pose) and the visible mask disagree,
  pixels of closer objects and outside the image left out, over the ``W x H`` pixels of the whole frame
  (the working size: 624x192 on Virtual KITTI, as in the paper); the mean over objects. Pixels are
  scored inside the crop window, the visible box grown by the crop margin (:func:`image_reprojection_error`
  says how the counts are taken from the dataset's crops, and why not beyond);
- ``reprojection_error_crop_soft``: mean ``|S~ - S|`` of the **soft** silhouette (the training loss
  L_reproj) over the non-ignored pixels of the object crops, pooled over objects. The object fills most
  of its crop, and the soft edge alone costs about half of it at the true pose, so this figure is an
  order of magnitude above the paper's and says little about the differences between models.

Mesh selection (objects whose true template is known, ``template_id >= 0``):

- ``mesh_accuracy``: the chosen (argmax) template is the true one;
- floors: ``mesh_uniform_floor`` = 1/8 (a uniform guess) and ``mesh_majority_floor`` (always the most
  frequent template of the *training* part, scored on the same objects; :func:`mesh_floors`);
- ``mesh_identifiability_ceiling``: share of objects whose true template has the lowest soft L_reproj at
  the ground-truth pose without FFD: what a reward-maximising choice reaches with a perfect pose
  (``benchmarks/mesh_identifiability.py`` measures the same per crop size);
- ``selection_regret`` (all objects): soft L_reproj of the chosen template minus the lowest over the 8
  templates, both at the predicted pose with the predicted FFD and at the crop's scale: the training
  loss, i.e. the reward REINFORCE maximises, so 0 means the policy picks the template that reward
  prefers given the rest of the prediction (:func:`selection_regret`).

Each metric is a sum and a count (``dist_reduce_fx="sum"``), so DDP reduction is exact.
"""

from __future__ import annotations

from collections.abc import Mapping

import torch
import torch.nn.functional as F
from kornia.geometry.conversions import quaternion_to_rotation_matrix
from torch import Tensor, nn
from torchmetrics import Metric

from sdn3d.geometric.losses import render_silhouettes, reprojection_error
from sdn3d.image_ops import crop_windows
from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.math3d.encodings import RotationMode
from sdn3d.math3d.rotations import roty
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.render.objects import pose_meshes
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings, SoftSilhouetteSettings

__all__ = [
    "orientation_similarity",
    "distance_error",
    "scale_error",
    "predicted_rotation",
    "crop_sample_pixels",
    "window_silhouettes",
    "image_reprojection_error",
    "template_reprojection_errors",
    "selection_regret",
    "mesh_floors",
    "OrientationSimilarity",
    "DistanceErrorMetric",
    "ScaleErrorMetric",
    "ReprojectionErrorMetric",
    "ImageReprojectionErrorMetric",
    "SelectionRegretMetric",
    "MeshSelectionAccuracy",
    "TemplateCounts",
    "GeometricMetrics",
    "METRIC_NAMES",
]

#: Metric names as logged (``val/<name>``, ``test/<name>``); the last three only at test.
METRIC_NAMES = ("orientation_similarity", "distance_error", "scale_error", "reprojection_error_image",
                "reprojection_error_crop_soft", "mesh_accuracy", "mesh_uniform_floor", "mesh_majority_floor",
                "mesh_identifiability_ceiling", "selection_regret")

#: Pixels rasterized at once by :func:`window_silhouettes` (about 40 bytes each).
_MAX_RASTER_PIXELS = 2_000_000
#: Crop pixels rendered at once by :func:`template_reprojection_errors`.
_MAX_SOFT_PIXELS = 4_000_000


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
    if mode != "full_quaternion":
        return roty(ry)
    return quaternion_to_rotation_matrix(F.normalize(rotation, dim=-1, eps=1e-8))


# --------------------------------------------------------------------------- reprojection in image pixels
def _crop_windows_of(crop_box: Tensor) -> Tensor:
    """``(N, 3)`` float64 ``(left, top, side)`` of the dataset's ``crop_box`` edges ``(l - 0.5, t - 0.5, ...)``."""
    if crop_box.dim() != 2 or crop_box.shape[1] != 4:
        raise ValueError(f"crop_box must have shape (N, 4), got {tuple(crop_box.shape)}")
    box = crop_box.detach().to("cpu", torch.float64)
    return torch.stack([box[:, 0] + 0.5, box[:, 1] + 0.5, box[:, 2] - box[:, 0]], 1).round()


def crop_sample_pixels(crop_box: Tensor, crop_size: int, image_size: tuple[int, int]) -> tuple[Tensor, Tensor]:
    """The image rows ``(N, S)`` and columns ``(N, S)`` whose values a crop's rows and columns hold.

    The dataset resamples masks into ``S x S`` crops with :func:`~sdn3d.image_ops.crop_windows` (nearest);
    an index map resampled the same way, on the CPU as the dataset did, gives the exact pixel each crop
    sample took, rounding ties included. ``-1`` where the sample lies outside the image.

    Args:
        crop_box: ``(N, 4)`` window edges ``(left - 0.5, top - 0.5, left + side - 0.5, top + side - 0.5)``.
        crop_size: ``S``.
        image_size: ``(W, H)`` of the image the crops were cut from.
    """
    width, height = (int(v) for v in image_size)
    columns = torch.arange(1, width + 1, dtype=torch.float32).expand(height, width)
    rows = torch.arange(1, height + 1, dtype=torch.float32)[:, None].expand(height, width)
    sampled = crop_windows(torch.stack([columns, rows]), _crop_windows_of(crop_box).float(), crop_size, "nearest")
    # A sample outside the image reads 0 in both channels: the max over the other axis skips such samples.
    cols = sampled[:, 0].amax(1).round().long() - 1
    rows_out = sampled[:, 1].amax(2).round().long() - 1
    return rows_out.to(crop_box.device), cols.to(crop_box.device)


def _window_in_image(crop_box: Tensor, image_size: tuple[int, int]) -> tuple[Tensor, Tensor]:
    """``(N, 2)`` long image ``(column, row)`` of each window's first pixel inside the image, and ``(N, 2)`` the
    window's extent ``(width, height)`` inside the image (both on the CPU)."""
    window = _crop_windows_of(crop_box).long()
    limit = torch.tensor([int(v) for v in image_size])
    start = window[:, :2].clamp(min=0)
    end = torch.minimum(window[:, :2] + window[:, 2:], limit)
    return start, (end - start).clamp(min=0)


def _axis_weights(index: Tensor, side: Tensor) -> Tensor:
    """``(N, S)`` image pixels each crop row (or column) stands for; 0 outside the image.

    ``side <= S``: every image pixel of the window is sampled, ``m >= 1`` times: ``1 / m`` each (exact).
    ``side > S``: samples are distinct pixels, a sub-grid of the window: ``side / S`` each.
    """
    size = index.shape[1]
    repeats = (index[:, :, None] == index[:, None, :]).sum(-1).double()
    weights = torch.where((side > size)[:, None], (side / size)[:, None].expand_as(repeats), 1.0 / repeats)
    return weights * (index >= 0)


def window_silhouettes(
    bank: MeshBank,
    template_ids: Tensor,
    dims: Tensor,
    ry: Tensor,
    center: Tensor,
    phi: Tensor | None,
    intrinsics: Tensor,
    crop_box: Tensor,
    image_size: tuple[int, int],
) -> Tensor:
    """Hard silhouettes ``(N, Hc, Wc)`` bool of posed, deformed templates over the part of each crop window inside
    the image, at image resolution.

    Pixel ``(i, j)`` of object ``n`` is image pixel ``(top_n + i, left_n + j)`` with ``(left_n, top_n)`` the
    window's first pixel inside the image; ``(Hc, Wc)`` is the largest such part (pixels past an object's own
    part are drawn too, and never read).

    Args:
        bank: mesh templates; template_ids ``(N,)``; dims ``(N, 3)``; ry ``(N,)``; center ``(N, 3)``;
            phi ``(N, 64, 3)`` FFD displacements or None.
        intrinsics: ``(N, 4)`` ``(fx, fy, cx, cy)`` or ``(N, 3, 3)`` of the image (not the crop).
        crop_box: ``(N, 4)`` the dataset's window edges ``(left - 0.5, top - 0.5, left + side - 0.5,
            top + side - 0.5)``.
        image_size: ``(W, H)`` of the image.
    """
    n = template_ids.shape[0]
    start, extent = _window_in_image(crop_box, image_size)
    width, height = (max(1, int(extent[:, i].max())) if n else 1 for i in range(2))
    K = as_intrinsics_matrix(intrinsics, n).to(torch.float64).clone()
    K[:, :2, 2] -= start.to(K)  # the window's first pixel centre inside the image is the origin
    settings = RasterSettings((height, width))
    chunk = max(1, _MAX_RASTER_PIXELS // (width * height))
    masks = [torch.zeros((0, height, width), dtype=torch.bool, device=dims.device)]
    for start in range(0, n, chunk):  # bounds the rasterizer's (chunk, C, C) buffers
        part = slice(start, start + chunk)
        verts, faces = pose_meshes(bank, template_ids[part], dims[part], ry[part], center[part],
                                   None if phi is None else phi[part])
        masks.append(rasterize_meshes(verts, faces, K[part], settings).mask)
    return torch.cat(masks)


def image_reprojection_error(silhouette: Tensor, mask: Tensor, ignore: Tensor | None, crop_box: Tensor,
                             image_size: tuple[int, int]) -> Tensor:
    """Per object ``(N,)``: image pixels of the crop window where the hard silhouette and the mask disagree,
    over the ``W x H`` pixels of the frame.

    The masks exist only as the dataset's ``S x S`` crops of square windows of ``side`` image pixels (the
    object's visible 2D box grown by the crop margin), sampled at the nearest image pixel. The silhouette,
    rasterized over the window at image resolution (:func:`window_silhouettes`), is read at exactly the image
    pixels the crop's mask samples came from (:func:`crop_sample_pixels`), and each mismatch counts for the
    image pixels its crop pixel stands for: with ``side <= S`` every image pixel of the window is sampled
    once or more and the count is exact; with ``side > S`` the samples form a sub-grid of the window, whose
    count is scaled by ``(side / S)^2``.

    Pixels outside the window are not scored: neither the mask nor the occluders are known there, and the
    box is the *visible* part's, so at the true pose a partly hidden object's silhouette reaches past it
    exactly where closer objects cover it (pixels the paper ignores). Counting them all overcharges every
    occluded object; what a prediction draws beyond the margin is left out instead.

    Counting at crop resolution and scaling by ``(side / S)^2`` is not the same figure: the hard silhouette
    read at the crop's sample points, not at the image pixels the mask values came from, is off by up to half
    an image pixel along the whole boundary (mismatches even at a perfect pose).

    Args:
        silhouette: ``(N, Hc, Wc)`` bool window silhouettes (:func:`window_silhouettes`).
        mask: ``(N, S, S)`` or ``(N, 1, S, S)`` crop masks; ignore: same shape, 1 = closer object, or None.
        crop_box: ``(N, 4)`` the dataset's window edges.
        image_size: ``(W, H)`` of the frame (the denominator; crop samples outside it do not count).
    """
    if silhouette.dim() != 3 or silhouette.dtype != torch.bool:
        raise ValueError(f"silhouette must be a (N, Hc, Wc) bool tensor, got {tuple(silhouette.shape)} "
                         f"{silhouette.dtype}")
    width, height = (int(v) for v in image_size)
    n = silhouette.shape[0]
    size = mask.shape[-1]
    mask = mask.reshape(n, size, size) > 0.5
    keep = torch.ones_like(mask) if ignore is None else ignore.reshape(n, size, size) <= 0.5
    rows, cols = crop_sample_pixels(crop_box, size, (width, height))
    side = _crop_windows_of(crop_box)[:, 2].to(silhouette.device)
    weight = _axis_weights(rows, side)[:, :, None] * _axis_weights(cols, side)[:, None, :]
    start = _window_in_image(crop_box, image_size)[0].to(silhouette.device)
    local_rows = (rows - start[:, 1:]).clamp(0, silhouette.shape[1] - 1)  # samples outside the image weigh 0
    local_cols = (cols - start[:, :1]).clamp(0, silhouette.shape[2] - 1)
    sampled = silhouette[torch.arange(n, device=silhouette.device)[:, None, None], local_rows[:, :, None],
                         local_cols[:, None, :]]
    return (((sampled != mask) & keep).double() * weight).sum((1, 2)) / (width * height)


# --------------------------------------------------------------------------- mesh selection
def template_reprojection_errors(
    bank: MeshBank,
    dims: Tensor,
    ry: Tensor,
    center: Tensor,
    phi: Tensor | None,
    crop_intrinsics: Tensor,
    mask: Tensor,
    ignore: Tensor | None,
    settings: SoftSilhouetteSettings | int,
) -> Tensor:
    """``(N, M)`` soft L_reproj (:func:`~sdn3d.geometric.losses.reprojection_error`) of each of the ``M``
    templates of ``bank`` placed at each object's pose.

    Args:
        dims ``(N, 3)``, ry ``(N,)``, center ``(N, 3)``, phi ``(N, 64, 3)`` or None: the pose and FFD, shared by
            all templates of an object; crop_intrinsics ``(N, 4)`` or ``(N, 3, 3)``; mask, ignore ``(N, 1, S, S)``.
        settings: the soft silhouette's settings (the training loss's), or the crop size.
    """
    n, m = dims.shape[0], len(bank)
    size = mask.shape[-1]
    chunk = max(1, _MAX_SOFT_PIXELS // (m * size * size))
    errors = [dims.new_zeros((0, m))]
    for start in range(0, n, chunk):  # bounds the (chunk * M, S, S) silhouettes
        rows = [None if t is None else t[start:start + chunk].repeat_interleave(m, 0)
                for t in (dims, ry, center, phi, crop_intrinsics, mask, ignore)]
        k = rows[0].shape[0] // m
        ids = torch.arange(m, device=dims.device).repeat(k)
        sil = render_silhouettes(bank, ids, *rows[:5], settings)
        errors.append(reprojection_error(sil, rows[5], rows[6]).view(k, m))
    return torch.cat(errors)


def selection_regret(errors: Tensor, chosen: Tensor) -> Tensor:
    """``(N,)`` ``errors[n, chosen[n]] - min_k errors[n, k]`` for ``(N, M)`` per-template errors (>= 0)."""
    if errors.dim() != 2 or chosen.shape != errors.shape[:1]:
        raise ValueError(f"need errors (N, M) and chosen (N,), got {tuple(errors.shape)} and {tuple(chosen.shape)}")
    return errors.gather(1, chosen.long().to(errors.device)[:, None])[:, 0] - errors.amin(1)


def mesh_floors(test_counts: Tensor, train_counts: Tensor | None) -> dict[str, Tensor]:
    """Mesh accuracy of the trivial choices on the labelled test objects (``test_counts (M,)`` per template).

    ``mesh_uniform_floor`` = 1 / M (a uniform guess); ``mesh_majority_floor``: always the most frequent template
    of ``train_counts (M,)`` (the training part; ties: the lower id). Empty without labelled test objects;
    no majority floor without training counts.
    """
    known = test_counts.sum()
    if known <= 0:
        return {}
    floors = {"mesh_uniform_floor": torch.tensor(1.0 / test_counts.numel())}
    if train_counts is not None and train_counts.sum() > 0:
        majority = int(train_counts.argmax())
        floors["mesh_majority_floor"] = (test_counts[majority].double() / known).float().cpu()
    return floors


# --------------------------------------------------------------------------- torchmetrics
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


class _ObjectMean(_SumCount):
    """Mean over objects of a per-object value; ``update(values (N,))``."""

    higher_is_better = False

    def update(self, values: Tensor) -> None:
        if values.dim() != 1:
            raise ValueError(f"values must have shape (N,), got {tuple(values.shape)}")
        self._add(values)


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
    """Soft crop figure: mean ``|S~ - S|`` over non-ignored crop pixels, pooled over objects.

    ``update(silhouette (N, H, W), mask, ignore=None)``; ``mask`` and ``ignore`` are ``(N, H, W)`` or
    ``(N, 1, H, W)``; ignored pixels (value 1) do not count.
    """

    higher_is_better = False

    def update(self, silhouette: Tensor, mask: Tensor, ignore: Tensor | None = None) -> None:
        if silhouette.dim() != 3:
            raise ValueError(f"silhouette must have shape (N, H, W), got {tuple(silhouette.shape)}")
        mask = mask.reshape(silhouette.shape).to(silhouette.dtype)
        keep = torch.ones_like(mask) if ignore is None else 1.0 - ignore.reshape(silhouette.shape).to(mask.dtype)
        self._add((silhouette - mask).abs() * keep, keep.detach().double().sum())


class ImageReprojectionErrorMetric(_ObjectMean):
    """The paper's figure: mean over objects of :func:`image_reprojection_error`; ``update(values (N,))``."""


class SelectionRegretMetric(_ObjectMean):
    """Mean over objects of :func:`selection_regret`; ``update(values (N,))``."""


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


class TemplateCounts(Metric):
    """Objects per true template ``(M,)`` (unknown templates, ``-1``, not counted); ``update(target_ids (N,))``."""

    full_state_update = False

    def __init__(self, num_templates: int = len(TEMPLATE_NAMES), **kwargs) -> None:
        super().__init__(**kwargs)
        self.num_templates = int(num_templates)
        self.add_state("counts", default=torch.zeros(self.num_templates, dtype=torch.long), dist_reduce_fx="sum")

    def update(self, target_ids: Tensor) -> None:
        ids = target_ids[(target_ids >= 0) & (target_ids < self.num_templates)]
        self.counts += torch.bincount(ids, minlength=self.num_templates)

    def compute(self) -> Tensor:
        return self.counts.clone()


class GeometricMetrics(nn.Module):
    """The metrics of Table 2 and of the mesh choice together (the module doc lists them).

    ``update(pred, target, crop_silhouette, crop_ignore, image_error)`` with ``pred`` from
    :func:`~sdn3d.geometric.decode.decode_outputs` plus ``rot (N, 3, 3)`` (:func:`predicted_rotation`),
    ``target`` a dataset batch (``ry``, ``center``, ``dims``, ``template_id``, ``mask``), the soft crop
    silhouettes ``(N, S, S)`` and what they ignore, and :func:`image_reprojection_error`'s ``(N,)`` values;
    the reprojection figures are updated only when given. ``update_selection`` adds the mesh-choice figures.
    """

    def __init__(self, num_templates: int = len(TEMPLATE_NAMES)) -> None:
        super().__init__()
        self.metrics = nn.ModuleDict({
            "orientation_similarity": OrientationSimilarity(),
            "distance_error": DistanceErrorMetric(),
            "scale_error": ScaleErrorMetric(),
            "reprojection_error_image": ImageReprojectionErrorMetric(),
            "reprojection_error_crop_soft": ReprojectionErrorMetric(),
            "mesh_accuracy": MeshSelectionAccuracy(),
            "mesh_identifiability_ceiling": MeshSelectionAccuracy(),
            "selection_regret": SelectionRegretMetric(),
        })
        self.template_counts = TemplateCounts(num_templates)

    def __getitem__(self, name: str) -> Metric:
        return self.metrics[name]

    def update(
        self,
        pred: Mapping[str, Tensor],
        target: Mapping[str, Tensor],
        crop_silhouette: Tensor | None = None,
        crop_ignore: Tensor | None = None,
        image_error: Tensor | None = None,
    ) -> None:
        m = self.metrics
        m["orientation_similarity"].update(pred["rot"], roty(target["ry"].to(pred["rot"].dtype)))
        m["distance_error"].update(pred["center"], target["center"])
        m["scale_error"].update(pred["dims"], target["dims"])
        m["mesh_accuracy"].update(pred["template_id"], target["template_id"])
        self.template_counts.update(target["template_id"])
        if crop_silhouette is not None:
            m["reprojection_error_crop_soft"].update(crop_silhouette, target["mask"], crop_ignore)
        if image_error is not None:
            m["reprojection_error_image"].update(image_error)

    def update_selection(self, chosen: Tensor, errors_at_prediction: Tensor, errors_at_truth: Tensor,
                         target_ids: Tensor) -> None:
        """Regret of ``chosen (N,)`` under ``errors_at_prediction (N, M)``; the identifiability ceiling from
        ``errors_at_truth (N, M)`` (ground-truth pose, no FFD) and the true templates ``target_ids (N,)``."""
        self.metrics["selection_regret"].update(selection_regret(errors_at_prediction, chosen))
        self.metrics["mesh_identifiability_ceiling"].update(errors_at_truth.argmin(1), target_ids)

    def compute(self, train_template_counts: Tensor | None = None) -> dict[str, Tensor]:
        """The figures that saw at least one object (a labelled one for the mesh figures), plus the floors
        (:func:`mesh_floors`; the majority floor needs the training part's ``train_template_counts (M,)``)."""
        values = {name: metric.compute() for name, metric in self.metrics.items() if metric.count > 0}
        if self.template_counts.update_count > 0:
            values.update(mesh_floors(self.template_counts.compute(), train_template_counts))
        return values

    def reset(self) -> None:
        for metric in self.metrics.values():
            metric.reset()
        self.template_counts.reset()
