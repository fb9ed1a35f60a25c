"""The silhouette L_reproj fits with: the soft one's L1 optimum is a shrunken car, the straight-through one's
is the true size (issue 29)."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric import render_silhouettes, reprojection_error
from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.meshes.bank import MeshBank
from sdn3d.render import RasterSettings, SoftSilhouetteSettings, rasterize_meshes, silhouette
from sdn3d.render.objects import pose_meshes


@pytest.fixture(scope="module")
def cars():
    """Three templates at known poses in 64-px crops and their hard masks (the paper's reprojection target)."""
    bank = MeshBank.templates()
    f64 = torch.float64
    dims = torch.tensor([[4.0, 1.5, 1.8], [4.5, 1.7, 1.9], [5.5, 2.2, 2.0]], dtype=f64)
    ry = torch.tensor([0.3, -1.2, 2.5], dtype=f64)
    center = torch.tensor([[0.0, 0.0, 12.0], [0.0, 0.0, 10.0], [0.0, 0.0, 15.0]], dtype=f64)
    crop_k = torch.tensor([[120.0, 120.0, 31.5, 31.5], [110.0, 110.0, 31.5, 31.5], [160.0, 160.0, 31.5, 31.5]],
                          dtype=f64)
    ids = torch.tensor([0, 3, 7])
    verts, faces = pose_meshes(bank, ids, dims, ry, center, None)
    mask = rasterize_meshes(verts, faces, as_intrinsics_matrix(crop_k, 3), RasterSettings((64, 64))).mask.to(f64)
    return bank, ids, dims, ry, center, crop_k, mask


def _fit_scale(cars, kind: str, start: float, steps: int = 80) -> torch.Tensor:
    """Each car's size factor after Adam on L1(silhouette(size * dims), true mask) from ``start``."""
    bank, ids, dims, ry, center, crop_k, mask = cars
    log_scale = torch.full((3, 1), math.log(start), dtype=torch.float64, requires_grad=True)
    optimizer = torch.optim.Adam([log_scale], lr=0.004)
    for _ in range(steps):
        optimizer.zero_grad()
        sil = render_silhouettes(bank, ids, dims * log_scale.exp(), ry, center, None, crop_k, 64, kind)
        reprojection_error(sil, mask).sum().backward()
        optimizer.step()
    return log_scale.detach().exp().flatten()


def test_straight_through_values_are_the_hard_silhouette_and_its_gradient_the_soft_one(cars):
    bank, ids, dims, ry, center, crop_k, mask = cars
    verts, faces = pose_meshes(bank, ids, dims * 0.97, ry, center, None)
    verts = verts.detach().requires_grad_(True)
    K = as_intrinsics_matrix(crop_k, 3)
    settings = SoftSilhouetteSettings((64, 64))
    hard = rasterize_meshes(verts.detach(), faces, K, RasterSettings((64, 64))).mask
    st = silhouette("straight_through", verts, faces, K, settings)
    assert torch.equal(st, hard.to(st.dtype))
    weights = torch.randn(st.shape, dtype=st.dtype, generator=torch.Generator().manual_seed(0))
    (grad_st,) = torch.autograd.grad((st * weights).sum(), verts)
    (grad_soft,) = torch.autograd.grad((silhouette("soft", verts, faces, K, settings) * weights).sum(), verts)
    torch.testing.assert_close(grad_st, grad_soft)
    with pytest.raises(ValueError, match="silhouette must be one of"):
        silhouette("hard", verts, faces, K, settings)


@pytest.mark.parametrize("start", [0.96, 1.03])
def test_straight_through_l1_fit_recovers_the_true_size_within_one_percent(cars, start):
    scale = _fit_scale(cars, "straight_through", start)
    assert (scale - 1.0).abs().max() < 0.01, scale


def test_soft_l1_fit_shrinks_the_car(cars):
    """The bias the straight-through silhouette removes: from the true size itself, soft L1 drifts smaller."""
    scale = _fit_scale(cars, "soft", 1.0)
    assert (scale < 0.985).all(), scale
