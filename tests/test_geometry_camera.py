"""Tests of the existing camera model (camera.py) and y rotations (rotations.py)."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.math3d import (
    NUM_POSE_BINS,
    VKITTI_INTRINSICS,
    Intrinsics,
    alpha_bins,
    intrinsics_matrix,
    observation_angle,
    project_points,
    roty,
    unproject_pixels,
    wrap_angle,
)


def devkit_roty(t: float) -> torch.Tensor:
    """KITTI devkit ``roty`` written out by hand."""
    c, s = math.cos(t), math.sin(t)
    return torch.tensor([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]], dtype=torch.float64)


def random_points(n: int, dtype: torch.dtype = torch.float64) -> torch.Tensor:
    x = torch.empty(n, dtype=dtype).uniform_(-15, 15)
    y = torch.empty(n, dtype=dtype).uniform_(-2, 3)
    z = torch.empty(n, dtype=dtype).uniform_(2, 80)
    return torch.stack([x, y, z], -1)


def test_roty_matches_devkit_formula() -> None:
    angles = [-math.pi, -2.5, -1.0, 0.0, 0.3, math.pi / 2, 3.0]
    got = roty(torch.tensor(angles, dtype=torch.float64))
    expected = torch.stack([devkit_roty(t) for t in angles])
    assert got.shape == (len(angles), 3, 3)
    torch.testing.assert_close(got, expected, atol=1e-12, rtol=0)


def test_roty_is_rotation_and_keeps_front_along_x_at_zero() -> None:
    ry = torch.empty(2, 5, dtype=torch.float64).uniform_(-math.pi, math.pi)
    rot = roty(ry)
    assert rot.shape == (2, 5, 3, 3)
    eye = torch.eye(3, dtype=torch.float64).expand(2, 5, 3, 3)
    torch.testing.assert_close(rot @ rot.transpose(-1, -2), eye, atol=1e-12, rtol=0)
    torch.testing.assert_close(torch.linalg.det(rot), torch.ones(2, 5, dtype=torch.float64))
    front = roty(torch.zeros(1, dtype=torch.float64))[0] @ torch.tensor([1.0, 0, 0], dtype=torch.float64)
    torch.testing.assert_close(front, torch.tensor([1.0, 0, 0], dtype=torch.float64))
    # Positive yaw turns the front from +x towards -z (devkit sign), i.e. away from the camera axis.
    front = roty(torch.tensor([math.pi / 2], dtype=torch.float64))[0, :, 0]
    torch.testing.assert_close(front, torch.tensor([0.0, 0, -1], dtype=torch.float64), atol=1e-12, rtol=0)


def test_project_matches_pinhole_formula_and_unproject_round_trip() -> None:
    K = VKITTI_INTRINSICS.matrix(torch.float64)
    pts = random_points(100)
    uv = project_points(pts, K)
    expected = torch.stack([725.0 * pts[:, 0] / pts[:, 2] + 620.5, 725.0 * pts[:, 1] / pts[:, 2] + 187.0], -1)
    torch.testing.assert_close(uv, expected, atol=1e-9, rtol=0)
    back = unproject_pixels(uv, pts[:, 2], K)
    torch.testing.assert_close(back, pts, atol=1e-9, rtol=0)
    back_keepdim = unproject_pixels(uv, pts[:, 2:], K)
    torch.testing.assert_close(back_keepdim, pts, atol=1e-9, rtol=0)


def test_batched_intrinsics_matrix_projection() -> None:
    fx = torch.tensor([700.0, 362.0], dtype=torch.float64)
    fy = torch.tensor([710.0, 364.0], dtype=torch.float64)
    cx = torch.tensor([620.0, 311.0], dtype=torch.float64)
    cy = torch.tensor([187.0, 95.0], dtype=torch.float64)
    K = intrinsics_matrix(fx, fy, cx, cy)
    assert K.shape == (2, 3, 3)
    pts = random_points(2)
    uv = project_points(pts, K)
    torch.testing.assert_close(uv[:, 0], fx * pts[:, 0] / pts[:, 2] + cx)
    torch.testing.assert_close(uv[:, 1], fy * pts[:, 1] / pts[:, 2] + cy)


def test_vkitti_principal_point_is_image_centre() -> None:
    # Pixel centres at integers: the image spans [-0.5, W - 0.5], centre (W - 1) / 2.
    assert VKITTI_INTRINSICS.cx == (VKITTI_INTRINSICS.width - 1) / 2
    assert VKITTI_INTRINSICS.size == (375, 1242)


@pytest.mark.parametrize("size", [(624, 192), (512, 256), (2484, 750)])
def test_resized_keeps_projections_consistent_under_anisotropic_resize(size: tuple[int, int]) -> None:
    width, height = size
    small = VKITTI_INTRINSICS.resized(width, height)
    sx, sy = width / VKITTI_INTRINSICS.width, height / VKITTI_INTRINSICS.height
    assert sx != sy or size == (2484, 750)
    pts = random_points(50)
    uv = project_points(pts, VKITTI_INTRINSICS.matrix(torch.float64))
    uv_small = project_points(pts, small.matrix(torch.float64))
    # Pixel edges scale: u' + 0.5 = (u + 0.5) * sx.
    torch.testing.assert_close(uv_small[:, 0] + 0.5, (uv[:, 0] + 0.5) * sx, atol=1e-9, rtol=0)
    torch.testing.assert_close(uv_small[:, 1] + 0.5, (uv[:, 1] + 0.5) * sy, atol=1e-9, rtol=0)
    # Image corners map to image corners.
    assert small.cx == pytest.approx((width - 1) / 2)
    assert small.width == width and small.height == height


def test_cropped_shifts_principal_point() -> None:
    crop = VKITTI_INTRINSICS.cropped(100.0, 50.0, 300, 200)
    pts = random_points(10)
    uv = project_points(pts, VKITTI_INTRINSICS.matrix(torch.float64))
    uv_crop = project_points(pts, crop.matrix(torch.float64))
    torch.testing.assert_close(uv_crop, uv - torch.tensor([100.0, 50.0], dtype=torch.float64))


def test_intrinsics_reject_bad_values() -> None:
    with pytest.raises(ValueError, match="focal"):
        Intrinsics(0.0, 1.0, 0.0, 0.0, 10, 10)
    with pytest.raises(ValueError, match="size"):
        Intrinsics(1.0, 1.0, 0.0, 0.0, 0, 10)
    with pytest.raises(ValueError, match="finite"):
        Intrinsics(1.0, 1.0, float("nan"), 0.0, 10, 10)


def test_observation_angle_known_values() -> None:
    ry = torch.tensor([0.0, 0.0, 1.0, -3.0, 3.0], dtype=torch.float64)
    x = torch.tensor([0.0, 5.0, -5.0, 2.0, -2.0], dtype=torch.float64)
    z = torch.tensor([10.0, 5.0, 5.0, 10.0, 10.0], dtype=torch.float64)
    alpha = observation_angle(ry, x, z)
    expected = [0.0, -math.pi / 4, 1.0 + math.pi / 4, -3.0 - math.atan2(2, 10) + 2 * math.pi,
                3.0 + math.atan2(2, 10) - 2 * math.pi]
    torch.testing.assert_close(alpha, torch.tensor(expected, dtype=torch.float64), atol=1e-12, rtol=0)
    assert bool(((alpha >= -math.pi) & (alpha < math.pi)).all())


def test_observation_angle_is_yaw_relative_to_viewing_ray() -> None:
    # A car whose front points along the ray from the camera has alpha = -pi/2 wherever it is.
    xz = torch.empty(20, 2, dtype=torch.float64).uniform_(1, 30)
    theta = torch.atan2(xz[:, 0], xz[:, 1])  # ray angle from +z towards +x
    # Front direction (cos ry, -sin ry) in (x, z) equal to the ray (sin theta, cos theta): ry = theta - pi/2.
    alpha = observation_angle(theta - math.pi / 2, xz[:, 0], xz[:, 1])
    torch.testing.assert_close(alpha, torch.full_like(alpha, -math.pi / 2), atol=1e-12, rtol=0)


def test_wrap_angle_range_and_identity() -> None:
    a = torch.linspace(-20, 20, 1001, dtype=torch.float64)
    w = wrap_angle(a)
    assert bool(((w >= -math.pi) & (w < math.pi)).all())
    torch.testing.assert_close(torch.sin(w), torch.sin(a), atol=1e-12, rtol=0)
    torch.testing.assert_close(torch.cos(w), torch.cos(a), atol=1e-12, rtol=0)
    assert wrap_angle(torch.tensor(math.pi, dtype=torch.float64)).item() == pytest.approx(-math.pi)


def test_alpha_bins_edges() -> None:
    width = 2 * math.pi / NUM_POSE_BINS
    edges = -math.pi + width * torch.arange(NUM_POSE_BINS, dtype=torch.float64)
    # Each left edge (nudged inwards against rounding) starts its own bin.
    torch.testing.assert_close(alpha_bins(edges + 1e-9), torch.arange(NUM_POSE_BINS))
    # Just below each edge lies in the previous bin (wrapping below -pi to the last bin).
    below = alpha_bins(edges - 1e-9)
    expected = (torch.arange(NUM_POSE_BINS) - 1) % NUM_POSE_BINS
    torch.testing.assert_close(below, expected)
    ends = alpha_bins(torch.tensor([-math.pi, math.pi - 1e-9, math.pi, 0.0, -1e-9], dtype=torch.float64))
    assert ends.tolist() == [0, NUM_POSE_BINS - 1, 0, NUM_POSE_BINS // 2, NUM_POSE_BINS // 2 - 1]
    assert alpha_bins(torch.tensor([0.1]), num_bins=4).dtype == torch.long


def test_alpha_bins_cover_uniformly() -> None:
    alpha = torch.linspace(-math.pi, math.pi, 24 * 100 + 1, dtype=torch.float64)[:-1] + 1e-6
    counts = torch.bincount(alpha_bins(alpha), minlength=NUM_POSE_BINS)
    assert counts.tolist() == [100] * NUM_POSE_BINS


def test_camera_pose_tilt_matches_cityscapes_convention() -> None:
    """issue 40: CameraPose.tilt is the level -> camera rotation of a camera.json's pitch and roll (Cityscapes'
    ``Rz(yaw) Ry(pitch) Rx(roll)`` of ISO 8855 axes), whatever the yaw; a positive pitch looks down."""
    import numpy as np

    from sdn3d.data.cityscapes import camera_pose, camera_to_vehicle
    from sdn3d.math3d.camera import CameraPose

    for pitch, roll, yaw in ((0.05, 0.02, 0.3), (0.04, 0.0, 0.0), (0.0, -0.03, -0.1)):
        ext = {"yaw": yaw, "pitch": pitch, "roll": roll, "x": 1.7, "y": 0.1, "z": 1.2, "baseline": 0.2}
        level = camera_to_vehicle({**ext, "pitch": 0.0, "roll": 0.0})[:3, :3]
        cam_to_level = level.T @ camera_to_vehicle(ext)[:3, :3]
        pose = camera_pose(ext)
        assert (pose.height, pose.pitch, pose.roll) == (1.2, pitch, roll)
        assert np.allclose(pose.tilt(), cam_to_level.T, atol=1e-12)
    # Looking down: a far point straight ahead on the level horizon is above the principal point, at the level
    # virtual camera's cy.
    pose = CameraPose(1.2, 0.045)
    intr = Intrinsics(700.0, 710.0, 320.0, 180.0, 640, 360)
    point = torch.tensor(pose.tilt() @ [0.0, 0.0, 500.0], dtype=torch.float64)
    v = float(project_points(point[None], intr.matrix(torch.float64))[0, 1])
    assert v < intr.cy and v == pytest.approx(pose.level_intrinsics(intr).cy, abs=1e-6)
    # A road point ahead: the level virtual camera puts it where the pitched camera sees it, within 1.5 %
    # of its distance to the horizon.
    road = torch.tensor(pose.tilt() @ [0.0, 1.2, 6.0], dtype=torch.float64)
    v_true = float(project_points(road[None], intr.matrix(torch.float64))[0, 1])
    level = pose.level_intrinsics(intr)
    v_level = level.cy + level.fy * 1.2 / 6.0
    assert abs(v_level - v_true) < 0.015 * (v_true - level.cy)
    assert CameraPose().level and CameraPose().level_intrinsics(intr) is intr and CameraPose().height == 1.65


def test_camera_pose_rejects_bad_values() -> None:
    from sdn3d.math3d.camera import CameraPose

    for kwargs in ({"height": 0.0}, {"height": float("nan")}, {"pitch": 1.0}, {"roll": -0.8}, {"height": True}):
        with pytest.raises(ValueError, match="CameraPose"):
            CameraPose(**kwargs)
    assert CameraPose(roll=0.02).roll_ignored and not CameraPose(roll=0.005).roll_ignored


def _kornia_roty(ry: torch.Tensor) -> torch.Tensor:
    """``roty`` as kornia's axis-angle formula of ``(0, ry, 0)``, op for op (what :func:`roty` gives bit for bit)."""
    from sdn3d.math3d.rotations import _axis_angle_to_rotation_matrix

    flat = ry.reshape(-1)
    zeros = torch.zeros_like(flat)
    return _axis_angle_to_rotation_matrix(torch.stack([zeros, flat, zeros], -1)).reshape(*ry.shape, 3, 3)


def _same_bits(a: torch.Tensor, b: torch.Tensor) -> bool:
    """Equal bit for bit (signed zeros told apart), NaN wherever the other is NaN; the same shape and strides."""
    as_int = torch.int64 if a.dtype == torch.float64 else torch.int32
    same = (a.view(as_int) == b.view(as_int)) | (a.isnan() & b.isnan())
    return a.dtype == b.dtype and a.shape == b.shape and a.stride() == b.stride() and bool(same.all())


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_roty_without_grad_is_kornias_formula_bit_for_bit(dtype: torch.dtype) -> None:
    """roty's folded arithmetic (no autograd) gives kornia's bits: signed zeros of the zero entries on both sides of
    0, the series' rows (``ry^2 <= 1e-6``, alone and mixed with Rodrigues' rows) and their boundary, large angles,
    infinities and NaN; scalar and batched shapes. With grad, values and gradients are kornia's."""
    gen = torch.Generator().manual_seed(3)
    limit = torch.tensor(1e-3, dtype=dtype)
    boundary = torch.stack([torch.nextafter(limit, torch.zeros_like(limit)), limit,
                            torch.nextafter(limit, torch.ones_like(limit))])
    angles = torch.cat([
        torch.tensor([0.0, -0.0, 1e-30, -1e-30, 1e-45, math.pi, -math.pi, math.pi / 2, 1e3, -1e30,
                      float("inf"), float("-inf"), float("nan")], dtype=dtype),
        boundary, -boundary,
        torch.rand(4000, generator=gen, dtype=torch.float64).to(dtype) * 20 - 10,
        (torch.rand(4000, generator=gen, dtype=torch.float64).to(dtype) - 0.5) * 4e-3,  # series and Rodrigues rows
    ])
    assert _same_bits(roty(angles), _kornia_roty(angles))
    for only_series in (angles[(angles * angles) <= 1e-6], torch.tensor([-0.0, 0.0, -2e-4], dtype=dtype)):
        assert _same_bits(roty(only_series), _kornia_roty(only_series))
    for shaped in (angles[5], angles[:12].view(3, 4), angles[:12].view(4, 3).T):
        assert _same_bits(roty(shaped), _kornia_roty(shaped))
    ry = angles[13:200].clone().requires_grad_(True)
    ry_kornia = ry.detach().clone().requires_grad_(True)
    rot, rot_kornia = roty(ry), _kornia_roty(ry_kornia)
    weights = torch.rand(rot.shape, generator=gen, dtype=torch.float64).to(dtype)
    (rot * weights).sum().backward()
    (rot_kornia * weights).sum().backward()
    assert _same_bits(rot.detach(), rot_kornia.detach()) and _same_bits(ry.grad, ry_kornia.grad)
