"""roty, project_points and unproject_pixels, and the photo appearance's Lab conversions, compute kornia's results
op for op (bit-identical values and gradients) without importing kornia, and the edit command starts without kornia."""

from __future__ import annotations

import subprocess
import sys

import pytest
import torch
from kornia.geometry.camera import project_points as kornia_project
from kornia.geometry.camera import unproject_points as kornia_unproject
from kornia.geometry.conversions import axis_angle_to_rotation_matrix

from sdn3d.math3d.camera import project_points, unproject_pixels
from sdn3d.math3d.rotations import roty


def _angles(dtype: torch.dtype) -> torch.Tensor:
    g = torch.Generator().manual_seed(0)
    return torch.cat([
        (torch.rand(200, generator=g, dtype=dtype) - 0.5) * 20,  # Rodrigues' branch, several turns
        (torch.rand(50, generator=g, dtype=dtype) - 0.5) * 2e-3,  # theta^2 <= 1e-6: the Taylor branch
        torch.tensor([0.0, 1e-3, -1e-3, 3.14159265, -3.14159265, 1.5707963], dtype=dtype),
    ])


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_roty_is_kornias_rotation_bit_for_bit(dtype: torch.dtype) -> None:
    ry = _angles(dtype)
    weight = torch.randn(len(ry), 3, 3, dtype=dtype, generator=torch.Generator().manual_seed(1))
    ours, theirs = ry.clone().requires_grad_(True), ry.clone().requires_grad_(True)
    zeros = torch.zeros_like(theirs)
    reference = axis_angle_to_rotation_matrix(torch.stack([zeros, theirs, zeros], -1))
    mine = roty(ours)
    assert torch.equal(mine, reference)
    (mine * weight).sum().backward()
    (reference * weight).sum().backward()
    assert torch.equal(ours.grad, theirs.grad) and float(ours.grad.abs().max()) > 0
    assert roty(ry.view(2, -1)).shape == (2, len(ry) // 2, 3, 3)


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_projection_and_unprojection_are_kornias_bit_for_bit(dtype: torch.dtype) -> None:
    g = torch.Generator().manual_seed(2)
    points = torch.randn(4, 50, 3, dtype=dtype, generator=g) * torch.tensor([5.0, 2.0, 10.0], dtype=dtype)
    points[0, :3, 2] = torch.tensor([0.0, 1e-9, -1e-9], dtype=dtype)  # kornia's divide guard
    K = torch.tensor([[700.0, 0.0, 310.5], [0.0, 690.0, 95.25], [0.0, 0.0, 1.0]], dtype=dtype)
    Ks = K.expand(4, 3, 3).clone()
    Ks[1, 0, 0] = 650.0
    for calib in (K, Ks[:, None]):
        ours, theirs = points.clone().requires_grad_(True), points.clone().requires_grad_(True)
        mine = project_points(ours, calib)
        reference = kornia_project(theirs, calib.expand(*points.shape[:-1], 3, 3))
        assert torch.equal(mine, reference)
        mine.sum().backward()
        reference.sum().backward()
        assert torch.equal(ours.grad, theirs.grad)
        uv, depth = reference.detach(), points[..., 2:]
        back = unproject_pixels(uv, depth, calib)
        assert torch.equal(back, kornia_unproject(uv, depth, calib.expand(*uv.shape[:-1], 3, 3)))
        assert torch.equal(unproject_pixels(uv, depth[..., 0], calib), back)


def test_the_edit_command_starts_without_kornia() -> None:
    code = "import sys, sdn3d.cli.edit; print(any(m.split('.')[0] == 'kornia' for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False"]


def test_the_photo_lab_conversions_are_kornias_bit_for_bit() -> None:
    import kornia.color

    from sdn3d.editing.photo.recolor import _rgb, srgb_to_lab

    g = torch.Generator().manual_seed(0)
    rgb = torch.cat([torch.rand(5000, 3, generator=g), torch.rand(200, 3, generator=g) * 0.05,  # the linear toe
                     torch.tensor([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.04045, 0.5, 1.0]])])
    theirs = kornia.color.rgb_to_lab(rgb.T[:, :, None])[:, :, 0].T
    assert torch.equal(srgb_to_lab(rgb), theirs)
    lab = torch.cat([theirs, torch.rand(500, 3, generator=g) * torch.tensor([100.0, 256.0, 256.0])
                     - torch.tensor([0.0, 128.0, 128.0])])  # out-of-gamut Lab too: the clip
    assert torch.equal(_rgb(lab), kornia.color.lab_to_rgb(lab.T[:, :, None], clip=True)[:, :, 0].T)
