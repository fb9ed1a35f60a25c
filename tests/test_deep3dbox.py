"""Deep3DBox-style translation from 2D boxes (sdn3d.geometric.deep3dbox)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import torch

from sdn3d.geometric.deep3dbox import (
    border_sides,
    box_iou,
    deep3dbox_translation,
    solve_translation,
    upright_assignments,
)
from sdn3d.math3d.camera import project_points
from sdn3d.math3d.transforms import bottom_to_center, box_corners, project_box

CONF = Path(__file__).resolve().parents[1] / "conf" / "data"
# The synthetic data's camera (Virtual KITTI resized to 624x192).
K = torch.tensor([[364.25, 0.0, 311.5], [0.0, 371.2, 95.5], [0.0, 0.0, 1.0]], dtype=torch.float64)
IMAGE = (624, 192)


def _objects(n: int, seed: int = 0, near: float = 6.0, far: float = 50.0):
    """Car-sized boxes at random yaw, in front of the camera and inside the image."""
    g = torch.Generator().manual_seed(seed)

    def uni(lo, hi, size=(n,)):
        return torch.rand(size, generator=g, dtype=torch.float64) * (hi - lo) + lo

    dims = torch.stack([uni(3.5, 5.0), uni(1.4, 1.9), uni(1.6, 2.0)], -1)
    ry = uni(-math.pi, math.pi)
    z = uni(near, far)
    center = torch.stack([uni(-0.6, 0.6) * z, uni(0.5, 1.5), z], -1)
    return dims, ry, center


def _rel(a, b):
    return (a - b).norm(dim=-1) / b.norm(dim=-1)


def test_assignments_cover_every_upright_configuration():
    a = upright_assignments()
    assert a.shape == (192, 4) and len({tuple(r) for r in a.tolist()}) == 192
    assert (a[:, 0] != a[:, 2]).all()  # left and right touch different vertical edges
    assert ((a[:, [0, 2, 3]] < 4).all()) and ((a[:, 1] >= 4).all())  # bottom corners / top corners


@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
def test_exact_boxes_recover_the_translation(dtype):
    dims, ry, center = _objects(300)
    box = project_box(dims, ry, center, K)
    sol = solve_translation(box.to(dtype), dims.to(dtype), ry.to(dtype), K.to(dtype))
    assert sol.center.dtype == dtype and sol.valid.all()
    tol = 1e-9 if dtype == torch.float64 else 1e-4  # float32 boxes carry ~1e-5 px of rounding
    assert _rel(sol.center.double(), center).max() < tol
    assert torch.allclose(bottom_to_center(sol.location.double(), dims[:, 1]), center, atol=1e-3)
    assert (sol.location[:, 1] > sol.center[:, 1]).all()  # y points down: the bottom is below the centre
    assert (sol.iou > 1 - tol).all() and (sol.residual < 1e3 * tol).all()
    # The chosen corners are the ones that really are extreme in the image.
    uv = project_points(box_corners(dims, ry, center), K)  # (N, 8, 2)
    picked = torch.stack([uv[torch.arange(300), sol.assignment[:, s], s % 2] for s in range(4)], -1)
    assert torch.allclose(picked, box, atol=1e-3)
    # Per-object K and the convenience wrapper agree; the wrapper returns bottom centres first.
    location, c2 = deep3dbox_translation(box, dims, ry, K.expand(300, 3, 3))
    assert _rel(c2, center).max() < 1e-9
    assert torch.allclose(bottom_to_center(location, dims[:, 1]), c2, atol=1e-9)


def test_error_grows_gracefully_with_box_noise():
    dims, ry, center = _objects(400, seed=1, near=6.0, far=30.0)
    box = project_box(dims, ry, center, K)
    g = torch.Generator().manual_seed(2)
    noise = torch.randn(box.shape, generator=g, dtype=torch.float64)
    medians = []
    for sigma in (0.25, 1.0, 3.0):
        sol = solve_translation(box + sigma * noise, dims, ry, K)
        assert sol.valid.all()
        medians.append(float(_rel(sol.center, center).median()))
    assert medians[0] < medians[1] < medians[2]
    assert medians[0] < 0.01 and medians[1] < 0.03 and medians[2] < 0.1  # a few % for a few pixels
    # Roughly linear in the noise, not a jump to a wrong corner assignment.
    assert medians[2] / medians[1] < 6


def test_truncated_sides_can_be_dropped():
    dims = torch.tensor([[4.5, 1.6, 1.8]], dtype=torch.float64)
    ry = torch.tensor([0.4], dtype=torch.float64)
    center = torch.tensor([[-6.5, 0.9, 9.0]], dtype=torch.float64)  # sticks out of the left border
    full = project_box(dims, ry, center, K)
    assert full[0, 0] < -0.5
    clipped = full.clone()
    clipped[:, 0] = -0.5
    sides = border_sides(clipped, IMAGE)
    assert sides.tolist() == [[False, True, True, True]]
    plain = solve_translation(clipped, dims, ry, K)
    aware = solve_translation(clipped, dims, ry, K, sides=sides)
    assert _rel(aware.center, center).item() < 1e-9
    assert _rel(plain.center, center).item() > 1e-2
    # With fewer than three usable sides all four are used (no underdetermined solve).
    few = solve_translation(clipped, dims, ry, K, sides=torch.tensor([[False, True, False, True]]))
    assert torch.allclose(few.center, plain.center)


def test_box_iou():
    a = torch.tensor([[0.0, 0.0, 2.0, 2.0], [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 0.0, 1.0]])
    b = torch.tensor([[1.0, 1.0, 3.0, 3.0], [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0]])
    assert torch.allclose(box_iou(a, b), torch.tensor([1 / 7, 1.0, 0.0]))


def test_behind_the_camera_is_invalid():
    dims, ry, center = _objects(2)
    box = project_box(dims, ry, center, K)
    # A box whose size needs the object closer than its own half length: no valid candidate.
    huge = torch.tensor([[-4000.0, -3000.0, 4000.0, 3000.0]], dtype=torch.float64)
    sol = solve_translation(torch.cat([box, huge]), torch.cat([dims, dims[:1]]), torch.cat([ry, ry[:1]]), K)
    assert sol.valid.tolist() == [True, True, False]
    assert torch.isnan(sol.center[2]).all() and torch.isfinite(sol.center[:2]).all()


def test_bad_inputs_raise():
    dims, ry, center = _objects(3)
    box = project_box(dims, ry, center, K)
    with pytest.raises(ValueError, match="box must have shape"):
        solve_translation(box[:, :3], dims, ry, K)
    with pytest.raises(ValueError, match="dims must have shape"):
        solve_translation(box, dims[:2], ry, K)
    with pytest.raises(ValueError, match="ry must have shape"):
        solve_translation(box, dims, ry[:, None], K)
    with pytest.raises(ValueError, match="K must have shape"):
        solve_translation(box, dims, ry, K[:2])
    with pytest.raises(ValueError, match="r > l"):
        solve_translation(box[:, [2, 1, 0, 3]], dims, ry, K)
    with pytest.raises(ValueError, match="dims must be positive"):
        solve_translation(box, -dims, ry, K)
    with pytest.raises(ValueError, match="NaN"):
        solve_translation(box * float("nan"), dims, ry, K)
    with pytest.raises(ValueError, match="sides must be a bool"):
        solve_translation(box, dims, ry, K, sides=torch.ones(3, 4))
