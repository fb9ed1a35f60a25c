"""Table-2 metrics of the geometric branch: functional forms, the image-pixel reprojection error against a dense
full-frame count, the mesh-choice figures (regret, floors, ceiling) and torchmetrics accumulation."""

from __future__ import annotations

import math
import sys

import pytest
import torch
from kornia.geometry.conversions import axis_angle_to_rotation_matrix

from sdn3d.data.frames import intrinsics_vector
from sdn3d.geometric import render_silhouettes, reprojection_error
from sdn3d.geometric.metrics import (
    DistanceErrorMetric,
    GeometricMetrics,
    MeshSelectionAccuracy,
    OrientationSimilarity,
    ReprojectionErrorMetric,
    TemplateCounts,
    crop_sample_pixels,
    distance_error,
    image_reprojection_error,
    mesh_floors,
    orientation_similarity,
    predicted_rotation,
    scale_error,
    selection_regret,
    template_reprojection_errors,
    window_silhouettes,
)
from sdn3d.image_ops import crop_windows, square_crop_window
from sdn3d.math3d.camera import Intrinsics, as_intrinsics_matrix
from sdn3d.math3d.encodings import encode_full_quaternion
from sdn3d.math3d.rotations import roty
from sdn3d.meshes.bank import MeshBank
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes


def test_orientation_similarity_is_half_one_plus_cos_of_the_geodesic_angle():
    ry = torch.tensor([0.0, 1.0, -2.0, 3.0])
    delta = torch.tensor([0.0, math.pi / 2, math.pi, 0.3])
    sim = orientation_similarity(roty(ry + delta), roty(ry))
    torch.testing.assert_close(sim, (1 + torch.cos(delta)) / 2, atol=1e-6, rtol=0)
    # Any axis: a tilt of theta about x scores (1 + cos theta) / 2 as well.
    tilt = axis_angle_to_rotation_matrix(torch.tensor([[0.4, 0.0, 0.0]]))
    torch.testing.assert_close(orientation_similarity(tilt @ roty(ry[:1]), roty(ry[:1])),
                               torch.tensor([(1 + math.cos(0.4)) / 2]), atol=1e-6, rtol=0)
    with pytest.raises(ValueError, match="pred_rot"):
        orientation_similarity(torch.eye(3), roty(ry))


def test_predicted_rotation_per_mode():
    ry = torch.tensor([0.7, -2.0])
    torch.testing.assert_close(predicted_rotation(torch.zeros(2, 4), ry, "yaw_quaternion"), roty(ry))
    q = encode_full_quaternion(ry) * torch.tensor([[3.0], [-0.5]])  # unnormalised, sign flipped
    torch.testing.assert_close(predicted_rotation(q, torch.zeros(2), "full_quaternion"), roty(ry), atol=1e-6,
                               rtol=0)


def test_distance_and_scale_errors():
    c = torch.tensor([[3.0, 1.0, 20.0], [0.0, 1.0, 10.0]])
    torch.testing.assert_close(distance_error(c * torch.tensor([[1.1], [0.5]]), c),
                               torch.tensor([math.log(1.1), math.log(2.0)]))
    d = torch.tensor([[4.0, 1.5, 1.8]])
    torch.testing.assert_close(scale_error(d + torch.tensor([[0.3, 0.0, 0.4]]), d), torch.tensor([0.5]))


def test_metrics_accumulate_over_batches():
    m = DistanceErrorMetric()
    c = torch.tensor([[0.0, 1.0, 10.0]])
    m.update(c * math.e, c)
    m.update(c, c)
    m.update(c, c)
    assert math.isclose(float(m.compute()), 1 / 3, rel_tol=1e-6)
    acc = MeshSelectionAccuracy()
    acc.update(torch.tensor([1, 2, 3]), torch.tensor([1, -1, 4]))  # one right of two labelled
    acc.update(torch.tensor([0]), torch.tensor([0]))
    assert math.isclose(float(acc.compute()), 2 / 3, rel_tol=1e-6)
    empty = MeshSelectionAccuracy()
    empty.update(torch.tensor([1]), torch.tensor([-1]))
    assert math.isnan(float(empty.compute()))  # no object with a known template
    rep = ReprojectionErrorMetric()
    sil = torch.zeros(2, 2, 2)
    mask = torch.ones(2, 1, 2, 2)
    ignore = torch.zeros(2, 1, 2, 2)
    ignore[0, 0, 0] = 1.0  # 6 of 8 pixels count, all wrong by 1
    rep.update(sil, mask, ignore)
    rep.update(torch.ones(1, 2, 2), torch.ones(1, 2, 2))  # 4 more pixels, all right
    assert math.isclose(float(rep.compute()), 6 / 10, rel_tol=1e-6)
    o = OrientationSimilarity()
    o.update(roty(torch.tensor([0.0, math.pi])), roty(torch.zeros(2)))
    assert math.isclose(float(o.compute()), 0.5, abs_tol=1e-6)


def test_geometric_metrics_collection():
    metrics = GeometricMetrics()
    ry = torch.tensor([0.2, -1.0])
    center = torch.tensor([[1.0, 1.0, 10.0], [-2.0, 1.0, 20.0]])
    dims = torch.tensor([[4.0, 1.5, 1.8], [4.2, 1.6, 1.7]])
    target = {"ry": ry, "center": center, "dims": dims, "template_id": torch.tensor([3, -1]),
              "mask": torch.ones(2, 1, 4, 4)}
    pred = {"rot": roty(ry), "center": center, "dims": dims, "template_id": torch.tensor([3, 0])}
    metrics.update(pred, target, crop_silhouette=torch.ones(2, 4, 4), image_error=torch.tensor([1e-3, 3e-3]))
    values = metrics.compute()
    assert math.isclose(float(values["orientation_similarity"]), 1.0, abs_tol=1e-6)
    assert float(values["distance_error"]) < 1e-6 and float(values["scale_error"]) == 0.0
    assert float(values["reprojection_error_crop_soft"]) == 0.0 and float(values["mesh_accuracy"]) == 1.0
    assert math.isclose(float(values["reprojection_error_image"]), 2e-3, rel_tol=1e-6)  # mean over objects
    assert float(values["mesh_uniform_floor"]) == 0.125
    # Figures nothing was measured for are left out (not NaN): selection at validation, the majority floor
    # without training counts.
    assert not {"selection_regret", "mesh_identifiability_ceiling", "mesh_majority_floor"} & set(values)
    errors = torch.tensor([[0.3, 0.1, 0.2], [0.5, 0.4, 0.6]])
    at_truth = torch.tensor([[0.3, 0.2, 0.1], [0.1, 0.2, 0.3]])  # template 2 fits object 0 best
    metrics.update_selection(torch.tensor([1, 2]), errors, at_truth, torch.tensor([2, -1]))
    values = metrics.compute(train_template_counts=torch.tensor([0, 0, 0, 5, 1, 0, 0, 0]))
    assert math.isclose(float(values["selection_regret"]), (0.0 + 0.2) / 2, rel_tol=1e-6)
    assert float(values["mesh_identifiability_ceiling"]) == 1.0  # object 1's template is unknown
    assert float(values["mesh_majority_floor"]) == 1.0
    metrics.reset()
    assert metrics.compute() == {}
    with pytest.warns(UserWarning, match="before the ``update``"):
        assert math.isnan(float(metrics["scale_error"].compute()))


def test_mesh_floors_use_the_training_majority_not_the_test_one():
    test_counts = torch.tensor([6, 1, 3, 0, 0, 0, 0, 0])  # test part: mostly template 0
    train_counts = torch.tensor([2, 0, 9, 0, 0, 0, 0, 1])  # training part: mostly template 2
    floors = mesh_floors(test_counts, train_counts)
    assert math.isclose(float(floors["mesh_majority_floor"]), 3 / 10, rel_tol=1e-6)
    assert float(floors["mesh_uniform_floor"]) == 1 / 8
    assert "mesh_majority_floor" not in mesh_floors(test_counts, None)
    assert "mesh_majority_floor" not in mesh_floors(test_counts, torch.zeros(8, dtype=torch.long))
    assert mesh_floors(torch.zeros(8, dtype=torch.long), train_counts) == {}  # no labelled test object
    counts = TemplateCounts()
    counts.update(torch.tensor([0, 0, 2, -1]))
    counts.update(torch.tensor([2, 0]))
    assert counts.compute().tolist() == [3, 0, 2, 0, 0, 0, 0, 0]


def test_selection_regret_is_zero_for_the_best_template():
    errors = torch.tensor([[0.30, 0.10, 0.20], [0.05, 0.40, 0.50], [0.2, 0.2, 0.2]])
    torch.testing.assert_close(selection_regret(errors, errors.argmin(1)), torch.zeros(3))
    torch.testing.assert_close(selection_regret(errors, torch.tensor([0, 2, 1])), torch.tensor([0.2, 0.45, 0.0]))
    with pytest.raises(ValueError, match="chosen"):
        selection_regret(errors, torch.tensor([0, 1]))


# ----------------------------------------------------------------------------- reprojection in image pixels
W, H = 160, 64
INTR = Intrinsics(fx=140.0, fy=140.0, cx=79.5, cy=31.5, width=W, height=H)
TRUE_POSE = (0, [4.0, 1.5, 1.8], 0.6, [1.0, 0.5, 12.0])


def _image_silhouette(bank, template, dims, ry, center) -> torch.Tensor:
    """The dense reference's silhouette: ``(H, W)`` over the whole frame."""
    verts, faces = pose_meshes(bank, torch.tensor([template]), torch.tensor([dims]), torch.tensor([ry]),
                               torch.tensor([center]))
    return rasterize_meshes(verts, faces, INTR.matrix()[None], RasterSettings((H, W))).mask[0]


def _figure(bank, pose, mask, ignore, crop_box) -> float:
    """The metric's own path: window silhouette at image resolution, then the count."""
    template, dims, ry, center = pose
    sil = window_silhouettes(bank, torch.tensor([template]), torch.tensor([dims]), torch.tensor([ry]),
                             torch.tensor([center]), None, intrinsics_vector(INTR)[None], crop_box, (W, H))
    return float(image_reprojection_error(sil, mask, ignore, crop_box, (W, H))[0])


def _dataset_crop(mask_img, ignore_img, crop_size):
    """What GeometricDataset does: the square window around the mask's box, nearest-resampled masks."""
    ys, xs = mask_img.nonzero(as_tuple=True)
    box = torch.tensor([xs.min(), ys.min(), xs.max(), ys.max()]).float()
    left, top, side = square_crop_window(box, 0.1)
    window = torch.tensor([[left, top, side]], dtype=torch.float32)
    crops = crop_windows(torch.stack([mask_img, ignore_img]).float(), window, crop_size, "nearest")
    crop_box = torch.tensor([[left - 0.5, top - 0.5, left + side - 0.5, top + side - 0.5]])
    crop_intr = intrinsics_vector(INTR.cropped(left, top, side, side).resized(crop_size, crop_size))[None]
    return crops[:, :1], crops[:, 1:], crop_box, crop_intr, side


@pytest.fixture(scope="module")
def bank():
    return MeshBank.templates()


def _window(crop_box: torch.Tensor) -> torch.Tensor:
    """``(H, W)`` bool: the image pixels of the crop window."""
    left, top, right, bottom = (int(v + 0.5) for v in crop_box[0].tolist())
    window = torch.zeros(H, W, dtype=torch.bool)
    window[max(top, 0):max(bottom, 0), max(left, 0):max(right, 0)] = True
    return window


@pytest.mark.parametrize("pred_pose", [TRUE_POSE, (3, [4.2, 1.6, 1.8], 0.9, [1.3, 0.5, 11.5]),
                                       (0, [4.0, 1.5, 1.8], 0.6, [3.0, 0.5, 12.0])],  # partly beyond the window
                         ids=["true", "other_template_and_pose", "shifted"])
def test_image_reprojection_error_against_a_dense_full_frame_count(bank, pred_pose):
    mask_img = _image_silhouette(bank, *TRUE_POSE)
    ignore_img = torch.zeros(H, W, dtype=torch.bool)
    ignore_img[30:40, 60:70] = True  # a closer object over part of the car
    pred_img = _image_silhouette(bank, *pred_pose)
    side = _dataset_crop(mask_img, ignore_img, 8)[-1]
    window = _window(_dataset_crop(mask_img, ignore_img, 8)[2])
    dense = float(((pred_img != mask_img) & ~ignore_img & window).sum()) / (W * H)  # scored: the window's pixels
    for crop_size in (side, side + 7, 2 * side):  # every image pixel of the window sampled: exact
        mask, ignore, crop_box, _, _ = _dataset_crop(mask_img, ignore_img, crop_size)
        assert _figure(bank, pred_pose, mask, ignore, crop_box) == pytest.approx(dense, abs=1e-12), crop_size
    for crop_size in (side // 2, side // 3 + 1):  # a sub-grid of the window, scaled: close
        mask, ignore, crop_box, _, _ = _dataset_crop(mask_img, ignore_img, crop_size)
        assert _figure(bank, pred_pose, mask, ignore, crop_box) == pytest.approx(dense, rel=0.12, abs=1e-12)
    if pred_pose == TRUE_POSE:
        assert dense == 0.0
    # Ignoring nothing counts the closer object's pixels too.
    mask, ignore, crop_box, _, _ = _dataset_crop(mask_img, ignore_img, side)
    plain = float(((pred_img != mask_img) & window).sum()) / (W * H)
    assert _figure(bank, pred_pose, mask, None, crop_box) == pytest.approx(plain, abs=1e-12)


def test_occluded_parts_beyond_the_visible_box_are_not_charged(bank):
    """The window is the visible part's box (grown by the margin): at the true pose, the silhouette of a partly
    hidden car reaches past it under the occluder, which the paper ignores. The full-frame count, ignoring the
    occluder, is 0, and so is the figure."""
    silhouette = _image_silhouette(bank, *TRUE_POSE)
    occluder = torch.zeros(H, W, dtype=torch.bool)
    columns = silhouette.any(0).nonzero()[:, 0]
    occluder[:, int(columns.float().mean()):] = True  # hides the right half of the car
    mask_img = silhouette & ~occluder
    mask, ignore, crop_box, _, side = _dataset_crop(mask_img, occluder & ~mask_img, 64)
    assert bool((silhouette & ~_window(crop_box)).any())  # the silhouette reaches past the window
    assert float(((silhouette != mask_img) & ~occluder).sum()) == 0.0
    assert _figure(bank, TRUE_POSE, mask, ignore, crop_box) == 0.0


def test_counting_at_crop_resolution_is_not_the_image_pixel_figure(bank):
    """The alternative: hard silhouette in the crop camera, mismatches scaled by (side / S)^2. Even at the true
    pose it finds mismatches along the boundary (its samples are not the mask's pixels), where the image-pixel
    count finds none."""
    mask_img = _image_silhouette(bank, *TRUE_POSE)
    ignore_img = torch.zeros(H, W, dtype=torch.bool)
    side = _dataset_crop(mask_img, ignore_img, 8)[-1]
    crop_size = side * 3 // 2 + 1
    mask, ignore, crop_box, crop_intr, _ = _dataset_crop(mask_img, ignore_img, crop_size)
    template, dims, ry, center = TRUE_POSE
    verts, faces = pose_meshes(bank, torch.tensor([template]), torch.tensor([dims]), torch.tensor([ry]),
                               torch.tensor([center]))
    K = as_intrinsics_matrix(crop_intr)
    crop_sil = rasterize_meshes(verts, faces, K, RasterSettings((crop_size, crop_size))).mask
    scaled = float((crop_sil != (mask[:, 0] > 0.5)).sum()) * (side / crop_size) ** 2 / (W * H)
    assert scaled > 1e-3
    assert _figure(bank, TRUE_POSE, mask, ignore, crop_box) == 0.0


def test_crop_sample_pixels_are_the_pixels_the_crop_holds():
    image = torch.rand(2, 37, 53)
    windows = torch.tensor([[-5.0, 3.0, 20.0], [40.0, 20.0, 7.0], [10.0, -2.0, 32.0]])  # leaving the image too
    for size in (16, 13, 40):
        crops = crop_windows(image, windows, size, "nearest")
        crop_box = torch.cat([windows[:, :2] - 0.5, windows[:, :2] + windows[:, 2:] - 0.5], 1)
        rows, cols = crop_sample_pixels(crop_box, size, (53, 37))
        inside = (rows >= 0)[:, :, None] & (cols >= 0)[:, None, :]
        gathered = image[:, rows.clamp(min=0)[:, :, None], cols.clamp(min=0)[:, None, :]].permute(1, 0, 2, 3)
        torch.testing.assert_close(torch.where(inside[:, None], gathered, 0.0), crops, atol=0, rtol=0)
        assert bool((crops[~inside[:, None].expand_as(crops)] == 0).all())


def test_template_reprojection_errors_match_the_training_loss(bank, monkeypatch):
    mask_img = _image_silhouette(bank, *TRUE_POSE)
    ignore_img = torch.zeros(H, W, dtype=torch.bool)
    mask, ignore, _, crop_intr, _ = _dataset_crop(mask_img, ignore_img, 32)
    _, dims, ry, center = TRUE_POSE
    pose = torch.tensor([dims] * 2), torch.tensor([ry, ry + 0.5]), torch.tensor([center] * 2)
    mask, ignore, crop_intr = mask.expand(2, -1, -1, -1), ignore.expand(2, -1, -1, -1), crop_intr.expand(2, 4)
    phi = torch.randn(2, 64, 3) * 0.05
    errors = template_reprojection_errors(bank, *pose, phi, crop_intr, mask, ignore, 32)
    assert errors.shape == (2, len(bank))
    for template in (0, 5):
        ids = torch.full((2,), template)
        sil = render_silhouettes(bank, ids, *pose, phi, crop_intr, 32)
        torch.testing.assert_close(errors[:, template], reprojection_error(sil, mask, ignore))
    undeformed = template_reprojection_errors(bank, *pose, None, crop_intr, mask, ignore, 32)
    assert float(undeformed[1, 0]) > float(undeformed[0, 0])  # the true template turned by 0.5 rad
    # Chunked: the same figures one object at a time.
    metrics_module = sys.modules[template_reprojection_errors.__module__]
    monkeypatch.setattr(metrics_module, "_MAX_SOFT_PIXELS", 1)
    torch.testing.assert_close(template_reprojection_errors(bank, *pose, None, crop_intr, mask, ignore, 32),
                               undeformed)


def test_window_silhouettes_of_different_sizes_in_one_batch(bank):
    """Objects share one canvas (the largest window): each reads its own window, as when alone."""
    poses = [TRUE_POSE, (5, [4.5, 2.0, 1.9], -0.4, [-4.0, 0.6, 25.0])]
    crops, figures = [], []
    for pose in poses:
        mask_img = _image_silhouette(bank, *pose)
        crop = _dataset_crop(mask_img, torch.zeros(H, W, dtype=torch.bool), 24)
        crops.append(crop)
        figures.append(_figure(bank, poses[1] if pose is TRUE_POSE else TRUE_POSE, *crop[:3]))
    assert crops[0][-1] > crops[1][-1] and min(figures) > 0  # different sides; each mask scored by the other pose
    swapped = poses[::-1]
    mask, ignore, crop_box = (torch.cat([c[i] for c in crops]) for i in range(3))
    sil = window_silhouettes(bank, torch.tensor([p[0] for p in swapped]), torch.tensor([p[1] for p in swapped]),
                             torch.tensor([p[2] for p in swapped]), torch.tensor([p[3] for p in swapped]), None,
                             intrinsics_vector(INTR)[None].expand(2, 4), crop_box, (W, H))
    assert sil.shape[0] == 2 and max(sil.shape[1:]) <= crops[0][-1]
    torch.testing.assert_close(image_reprojection_error(sil, mask, ignore, crop_box, (W, H)),
                               torch.tensor(figures, dtype=torch.float64), atol=1e-12, rtol=0)


def test_a_window_leaving_the_image(bank):
    """A car cut by the image border: its window leaves the frame; pixels outside the image never count."""
    truncated = (0, [4.0, 1.5, 1.8], 0.3, [-6.5, 0.5, 11.0])
    mask_img = _image_silhouette(bank, *truncated)
    assert bool(mask_img[:, 0].any())  # cut by the left border
    pred = (0, [4.2, 1.5, 1.8], 0.5, [-6.2, 0.5, 11.5])
    side = _dataset_crop(mask_img, torch.zeros(H, W, dtype=torch.bool), 8)[-1]
    mask, ignore, crop_box, _, _ = _dataset_crop(mask_img, torch.zeros(H, W, dtype=torch.bool), side + 3)
    assert float(crop_box[0, 0]) < 0  # the window starts left of the image
    dense = float(((_image_silhouette(bank, *pred) != mask_img) & _window(crop_box)).sum()) / (W * H)
    assert dense > 0 and _figure(bank, pred, mask, ignore, crop_box) == pytest.approx(dense, abs=1e-12)
