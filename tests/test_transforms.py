"""Tests of object placement, 3D boxes and KITTI field conversions."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.math3d import VKITTI_INTRINSICS, project_points, roty
from sdn3d.math3d.transforms import (
    bottom_to_center,
    box_corners,
    camera_to_object,
    canonical_box_corners,
    center_to_bottom,
    dims_from_whl,
    from_kitti_fields,
    object_to_camera,
    project_box,
    to_kitti_fields,
    whl_from_dims,
)

F64 = torch.float64


def random_objects(batch: int, dtype: torch.dtype = F64) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    dims = torch.empty(batch, 3, dtype=dtype).uniform_(1, 5)
    ry = torch.empty(batch, dtype=dtype).uniform_(-math.pi, math.pi)
    center = torch.stack(
        [
            torch.empty(batch, dtype=dtype).uniform_(-15, 15),
            torch.empty(batch, dtype=dtype).uniform_(0.5, 1.5),
            torch.empty(batch, dtype=dtype).uniform_(8, 60),
        ],
        -1,
    )
    return dims, ry, center


def test_object_to_camera_matches_explicit_formula() -> None:
    dims, ry, center = random_objects(6)
    verts = torch.rand(6, 40, 3, dtype=F64) - 0.5
    out = object_to_camera(verts, dims, ry, center)
    expected = torch.einsum("bij,bvj->bvi", roty(ry), verts * dims[:, None]) + center[:, None]
    assert out.shape == (6, 40, 3)
    torch.testing.assert_close(out, expected, atol=1e-12, rtol=0)
    # Shared (V, 3) vertices broadcast over the batch.
    shared = object_to_camera(verts[0], dims, ry, center)
    torch.testing.assert_close(shared[2], object_to_camera(verts[:1].expand(6, -1, -1), dims, ry, center)[2])
    torch.testing.assert_close(camera_to_object(out, dims, ry, center), verts, atol=1e-12, rtol=0)


def test_axes_semantics_front_wheels_width() -> None:
    # ry = 0: canonical +x (front) is camera +x scaled by l, +y (wheels) is down by h/2, z spans w.
    dims = torch.tensor([[4.0, 1.5, 1.8]], dtype=F64)
    center = torch.tensor([[1.0, 2.0, 10.0]], dtype=F64)
    pts = torch.tensor([[[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]]], dtype=F64)
    out = object_to_camera(pts, dims, torch.zeros(1, dtype=F64), center)[0]
    expected = torch.tensor([[3.0, 2.0, 10.0], [1.0, 2.75, 10.0], [1.0, 2.0, 10.9]], dtype=F64)
    torch.testing.assert_close(out, expected)
    # The bottom face (wheels, y = +0.5) lands on the KITTI location y3d.
    location = center_to_bottom(center, dims[:, 1])
    assert out[1, 1].item() == pytest.approx(location[0, 1].item())


def test_bottom_center_round_trip() -> None:
    loc = torch.randn(5, 3, dtype=F64)
    h = torch.rand(5, dtype=F64) + 1
    c = bottom_to_center(loc, h)
    torch.testing.assert_close(c[:, 1], loc[:, 1] - h / 2)
    torch.testing.assert_close(c[:, [0, 2]], loc[:, [0, 2]])
    torch.testing.assert_close(center_to_bottom(c, h), loc)


def test_box_corners_devkit_order_and_extent() -> None:
    corners = canonical_box_corners(F64)
    assert corners.shape == (8, 3)
    assert torch.unique(corners, dim=0).shape[0] == 8
    assert bool((corners[:4, 1] == 0.5).all()) and bool((corners[4:, 1] == -0.5).all())
    dims, ry, center = random_objects(7)
    box = box_corners(dims, ry, center)
    assert box.shape == (7, 8, 3)
    torch.testing.assert_close(box.mean(1), center, atol=1e-12, rtol=0)
    # Edge lengths: 0-1 spans the width, 1-2 the length, 0-4 the height.
    torch.testing.assert_close((box[:, 0] - box[:, 1]).norm(dim=-1), dims[:, 2])
    torch.testing.assert_close((box[:, 1] - box[:, 2]).norm(dim=-1), dims[:, 0])
    torch.testing.assert_close((box[:, 0] - box[:, 4]).norm(dim=-1), dims[:, 1])


def test_box_corners_match_kitti_devkit_compute_box3d() -> None:
    # devkit: corners = R [x; y; z] + location with y in {0, -h} measured from the bottom face.
    w, h, l, ry = 1.7, 1.5, 4.1, 0.7
    loc = torch.tensor([2.0, 1.6, 20.0], dtype=F64)
    x = torch.tensor([l / 2, l / 2, -l / 2, -l / 2, l / 2, l / 2, -l / 2, -l / 2], dtype=F64)
    y = torch.tensor([0, 0, 0, 0, -h, -h, -h, -h], dtype=F64)
    z = torch.tensor([w / 2, -w / 2, -w / 2, w / 2, w / 2, -w / 2, -w / 2, w / 2], dtype=F64)
    devkit = (roty(torch.tensor(ry, dtype=F64)) @ torch.stack([x, y, z])).T + loc
    fields = (torch.tensor([v], dtype=F64) for v in (w, h, l, *loc.tolist(), ry))
    dims, ry_t, center = from_kitti_fields(*fields)
    torch.testing.assert_close(box_corners(dims, ry_t, center)[0], devkit, atol=1e-12, rtol=0)


def test_project_box_bounds_projected_vertices() -> None:
    dims, ry, center = random_objects(10)
    K = VKITTI_INTRINSICS.matrix(F64)
    box = project_box(dims, ry, center, K)
    assert box.shape == (10, 4)
    assert bool((box[:, 2] > box[:, 0]).all()) and bool((box[:, 3] > box[:, 1]).all())
    # Any point of the solid box projects inside (the projection of a convex set is the hull of corners).
    inner = object_to_camera(torch.rand(10, 200, 3, dtype=F64) - 0.5, dims, ry, center)
    uv = project_points(inner, K)
    assert bool((uv[..., 0] >= box[:, None, 0] - 1e-9).all() and (uv[..., 0] <= box[:, None, 2] + 1e-9).all())
    assert bool((uv[..., 1] >= box[:, None, 1] - 1e-9).all() and (uv[..., 1] <= box[:, None, 3] + 1e-9).all())
    # Batched K gives the same.
    torch.testing.assert_close(project_box(dims, ry, center, K.expand(10, 3, 3)), box)


def test_project_box_rejects_corners_behind_camera() -> None:
    dims = torch.tensor([[4.0, 1.5, 1.8]])
    with pytest.raises(ValueError, match="behind the camera"):
        project_box(dims, torch.zeros(1), torch.tensor([[0.0, 1.0, 0.5]]), VKITTI_INTRINSICS.matrix())


def test_dims_whl_order() -> None:
    w, h, l = torch.tensor([1.6]), torch.tensor([1.5]), torch.tensor([3.9])
    dims = dims_from_whl(w, h, l)
    assert dims.tolist() == [[pytest.approx(3.9), pytest.approx(1.5), pytest.approx(1.6)]]
    w2, h2, l2 = whl_from_dims(dims)
    assert (w2.item(), h2.item(), l2.item()) == (w.item(), h.item(), l.item())


def test_kitti_fields_round_trip() -> None:
    fields = {k: torch.rand(4, dtype=F64) + 1 for k in ("w3d", "h3d", "l3d", "x3d", "y3d", "z3d", "ry")}
    dims, ry, center = from_kitti_fields(**fields)
    back = to_kitti_fields(dims, ry, center)
    for key, value in fields.items():
        torch.testing.assert_close(back[key], value)


def test_placement_shape_errors() -> None:
    dims, ry, center = random_objects(3)
    with pytest.raises(ValueError, match="ry must have shape"):
        object_to_camera(torch.zeros(3, 5, 3, dtype=F64), dims, ry[:2], center)
    with pytest.raises(ValueError, match="verts"):
        object_to_camera(torch.zeros(2, 5, 3, dtype=F64), dims, ry, center)
    with pytest.raises(ValueError, match="dims"):
        box_corners(dims[:, :2], ry, center)


def test_empty_batch() -> None:
    dims, ry, center = random_objects(0)
    assert box_corners(dims, ry, center).shape == (0, 8, 3)
    assert project_box(dims, ry, center, VKITTI_INTRINSICS.matrix(F64)).shape == (0, 4)


def test_sum3_is_torch_sum_bit_for_bit() -> None:
    from sdn3d.math3d.sums import sum3

    g = torch.Generator().manual_seed(0)
    for dtype, bits in ((torch.float64, torch.int64), (torch.float32, torch.int32)):
        for n in (0, 1, 7, 5000, 60000):
            scale = torch.exp(torch.randn(n, 3, 3, generator=g) * 8).to(dtype)
            x = torch.randn(n, 3, 3, generator=g, dtype=dtype) * scale
            x[::5] = -0.0  # rows of -0.0 alone: torch's sum gives +0.0
            x[::7, 0] = 0.0
            x[1::11, :, 1] = -0.0
            x[2::13, 2, 2] = float("inf")
            x[3::17, 1, 0] = float("-inf")
            x[4::19, 0, 2] = float("nan")
            for t in (x, x.transpose(1, 2), x[:, 0], x[:, :, 1], x.permute(2, 0, 1).contiguous().permute(1, 2, 0)):
                for dim in range(1, t.dim()) if t.dim() == 3 else (1, -1):
                    for keepdim in (False, True):
                        want, got = t.sum(dim, keepdim=keepdim), sum3(t, dim, keepdim=keepdim)
                        assert got.shape == want.shape and got.dtype == want.dtype
                        assert torch.equal(got.view(bits), want.view(bits)), (dtype, n, t.stride(), dim, keepdim)
    with pytest.raises(ValueError, match="size 3"):
        sum3(torch.zeros(4, 2))
    with pytest.raises(ValueError, match="floating-point"):
        sum3(torch.zeros(4, 3, dtype=torch.long))
