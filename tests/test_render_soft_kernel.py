"""The soft silhouette's fused C++ kernel (render/soft_kernel.cpp) against its pure-PyTorch path, and its fallback."""

from __future__ import annotations

import ctypes
import shutil

import pytest
import torch
import trimesh
from helpers.native import needs_compiler, require_compiler_on_ci

import sdn3d.render._native as native
import sdn3d.render.soft as soft
from sdn3d.math3d.rotations import roty
from sdn3d.native import build_kernel
from sdn3d.render import SoftSilhouetteSettings, soft_silhouette

require_compiler_on_ci("soft silhouette")


def crop_K(f: float, size: int, dtype: torch.dtype) -> torch.Tensor:
    c = (size - 1) / 2
    return torch.tensor([[f, 0.0, c], [0.0, f, c], [0.0, 0.0, 1.0]], dtype=dtype)


def fit_like_scene(dtype: torch.dtype) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Five meshes as the fit draws them: many faces a few pixels wide, a large one, one clipped by the crop, one
    off-screen, one behind the camera; plus faces of every box size up to the whole crop."""
    sphere = trimesh.creation.icosphere(subdivisions=3)
    v = torch.tensor(sphere.vertices, dtype=dtype) * torch.tensor([2.0, 0.8, 1.0], dtype=dtype)
    f = torch.tensor(sphere.faces)
    shifts = [(0.0, 0.1, 8.0), (0.2, 0.0, 3.0), (2.5, -0.4, 7.0), (40.0, 0.0, 8.0), (0.0, 0.0, -8.0)]
    verts = torch.stack([v @ roty(torch.tensor(0.3 * n, dtype=dtype)).T + torch.tensor(s, dtype=dtype)
                         for n, s in enumerate(shifts)])
    K = torch.stack([crop_K(f_, 48, dtype) for f_ in (40.0, 50.0, 60.0, 40.0, 40.0)])
    return verts, f, K


def render_both(verts, faces, K, weight, **kw) -> list[tuple[torch.Tensor, torch.Tensor]]:
    out = []
    for use in (True, False):
        v = verts.clone().requires_grad_(True)
        sil = soft_silhouette(v, faces, K, SoftSilhouetteSettings((48, 48), native_kernel=use, **kw))
        (sil * weight).sum().backward()
        out.append((sil.detach(), v.grad))
    return out


@needs_compiler
def test_the_kernel_builds_here_and_is_used_on_cpu(monkeypatch) -> None:
    assert native.soft_kernel() is not None
    calls: list[str] = []
    real = soft._call
    monkeypatch.setattr(soft, "_call", lambda kernel, way, *a: calls.append(way) or real(kernel, way, *a))
    verts, faces, K = fit_like_scene(torch.float32)
    soft_silhouette(verts.requires_grad_(True), faces, K, SoftSilhouetteSettings((48, 48))).sum().backward()
    assert calls == ["forward", "backward"]
    soft_silhouette(verts, faces, K, SoftSilhouetteSettings((48, 48), native_kernel=False))
    assert calls == ["forward", "backward"]  # native_kernel=False: the PyTorch path


@needs_compiler
@pytest.mark.parametrize("cull_backfaces", [False, True])
@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_kernel_matches_the_pytorch_path(dtype: torch.dtype, cull_backfaces: bool) -> None:
    """Same silhouettes and vertex gradients: float64 to ~1e-12 (only the summation order differs), float32 to
    float rounding (the kernel's exp / log1p polynomials and the summation order)."""
    verts, faces, K = fit_like_scene(dtype)
    weight = torch.rand(5, 48, 48, dtype=dtype, generator=torch.Generator().manual_seed(0)) - 0.5
    (sil_k, grad_k), (sil_t, grad_t) = render_both(verts, faces, K, weight, cull_backfaces=cull_backfaces)
    assert sil_t[0].max() > 0.99 and sil_t[1].mean() > 0.3 and float(sil_t[3:].abs().max()) == 0.0
    big = float(grad_t.abs().max())
    assert big > 1.0 and float(grad_t[4].abs().max()) == 0.0 and float(grad_k[4].abs().max()) == 0.0
    sil_tol, grad_tol = (1e-12, 1e-10) if dtype == torch.float64 else (2e-6, 2e-5)
    assert float((sil_k - sil_t).abs().max()) < sil_tol
    assert float((grad_k - grad_t).abs().max()) < grad_tol * big


@needs_compiler
def test_kernel_softplus_over_the_whole_range() -> None:
    """One large triangle (terms from far inside, x ~ 1e4, to beyond the culling radius) and sigma from sharp to
    very soft: the float32 kernel's exp / log1p give the PyTorch path's silhouette to float rounding."""
    verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -2.0, 5.0], [0.5, 3.0, 5.0]]])
    faces = torch.tensor([[0, 1, 2]])
    K = crop_K(30.0, 48, torch.float32)  # the triangle spans about 36 x 36 px
    for sigma in (0.02, 0.25, 4.0, 60.0):
        sils = [soft_silhouette(verts, faces, K, SoftSilhouetteSettings((48, 48), sigma=sigma, native_kernel=use))
                for use in (True, False)]
        assert float((sils[0] - sils[1]).abs().max()) < 3e-7  # about 1 ulp: r = w - t e fused as PyTorch's addcmul
        assert float(sils[1].max()) > 0.8 and bool(((sils[1] > 1e-4) & (sils[1] < 0.5)).any())


@needs_compiler
def test_gradcheck_kernel_on_a_fit_sized_mesh() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=1)
    verts = (torch.tensor(sphere.vertices) * torch.tensor([1.5, 0.7, 1.0]) + torch.tensor([0.1, 0.0, 6.0]))[None]
    verts = verts + 0.01 * torch.randn(verts.shape, dtype=torch.float64, generator=torch.Generator().manual_seed(1))
    faces = torch.tensor(sphere.faces)
    K = crop_K(30.0, 24, torch.float64)
    settings = SoftSilhouetteSettings((24, 24), sigma=1.0)
    weight = torch.rand(1, 24, 24, dtype=torch.float64, generator=torch.Generator().manual_seed(2))

    def fn(v: torch.Tensor) -> torch.Tensor:
        return (soft_silhouette(v, faces, K, settings) * weight).sum((-1, -2))

    assert torch.autograd.gradcheck(fn, (verts.requires_grad_(True),), eps=1e-7, atol=1e-6, rtol=1e-4)


def test_without_the_kernel_the_pytorch_path_draws(monkeypatch) -> None:
    verts, faces, K = fit_like_scene(torch.float32)
    expected = soft_silhouette(verts, faces, K, SoftSilhouetteSettings((48, 48), native_kernel=False))
    monkeypatch.setattr(soft, "soft_kernel", lambda: None)
    assert torch.equal(soft_silhouette(verts, faces, K, SoftSilhouetteSettings((48, 48))), expected)



@needs_compiler
def test_the_kernels_threads_split_meshes_and_change_nothing() -> None:
    """The kernel's own outputs (log_keep, the screen gradient) are bit-identical for any thread count. (Torch's
    elementwise ops around it, e.g. expm1, may round a lane differently when the thread count moves their split.)"""
    verts, faces, K = fit_like_scene(torch.float32)
    settings = SoftSilhouetteSettings((48, 48))
    screen, valid, meshes, faces_per_mesh = soft._screen_triangles(verts, faces, K, settings.near)
    col0, row0, box_w, box_h, _, _ = soft._face_boxes(screen, valid, settings.cull_radius, 48, 48)
    box = torch.stack([col0, row0, box_w, box_h], 1).contiguous()
    pixel_grad = torch.rand(meshes * 48 * 48, generator=torch.Generator().manual_seed(3)) - 0.5
    kernel, threads, results = native.soft_kernel(), torch.get_num_threads(), []
    try:
        for count in (1, 3, 2):
            torch.set_num_threads(count)
            log_keep, grad = torch.zeros(meshes * 48 * 48), torch.empty_like(screen)
            soft._call(kernel, "forward", screen, box, faces_per_mesh, settings, log_keep)
            soft._call(kernel, "backward", screen, box, faces_per_mesh, settings, pixel_grad, grad)
            results.append((log_keep, grad))
    finally:
        torch.set_num_threads(threads)
    for log_keep, grad in results[1:]:
        assert torch.equal(log_keep, results[0][0]) and torch.equal(grad, results[0][1])
    assert float(results[0][0].min()) < -1.0 and float(results[0][1].abs().max()) > 0


@needs_compiler
def test_the_float32_kernel_in_vectors_of_8_is_the_one_vector_kernel_to_the_bit() -> None:
    """float32 groups 16 faces in two vectors of 8 lanes (without AVX-512) or one of 16, skipping a vector whose
    boxes all end before the pixel: the two give the same outputs, bit for bit (a pixel adds its faces' terms in the
    same order). A mesh with faces of many box sizes, so some vectors are skipped. The build this machine does not
    use is made once into the kernel's cache (a few seconds the first time)."""
    verts, faces, K = fit_like_scene(torch.float32)
    settings = SoftSilhouetteSettings((48, 48))
    screen, valid, meshes, faces_per_mesh = soft._screen_triangles(verts, faces, K, settings.near)
    col0, row0, box_w, box_h, _, _ = soft._face_boxes(screen, valid, settings.cull_radius, 48, 48)
    box = torch.stack([col0, row0, box_w, box_h], 1).contiguous()
    pixel_grad = torch.rand(meshes * 48 * 48, generator=torch.Generator().manual_seed(5)) - 0.5
    compiler = shutil.which("g++")
    lanes = native.soft_kernel().sdn3d_soft_f32_lanes()
    assert lanes in (8, 16)
    results, libraries = [], set()
    for defines in ((), (f"-DSDN3D_SOFT_F32_LANES={24 - lanes}",)):
        library = build_kernel(compiler, native.SOURCE, defines)
        libraries.add(library)
        kernel = native.bind(ctypes.CDLL(str(library)))
        log_keep, grad = torch.zeros(meshes * 48 * 48), torch.empty_like(screen)
        soft._call(kernel, "forward", screen, box, faces_per_mesh, settings, log_keep)
        soft._call(kernel, "backward", screen, box, faces_per_mesh, settings, pixel_grad, grad)
        results.append((log_keep, grad))
    assert len(libraries) == 2  # two builds, not one reused
    assert torch.equal(results[0][0], results[1][0]) and torch.equal(results[0][1], results[1][1])
    assert float(results[0][0].min()) < -1.0 and float(results[0][1].abs().max()) > 0


@needs_compiler
@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_the_kernels_face_boxes_are_the_pytorch_paths_integers(dtype: torch.dtype) -> None:
    """The kernel computes each face's grown pixel box itself (sdn3d_soft_boxes_*): the same integers as
    _face_boxes' first four, culled faces 0 wide. Faces of the fit-like scene (clipped, off-screen, behind the
    camera), then triangles whose corners lie a radius from a pixel centre give or take an ulp (ceil and floor
    decide there), on the crop's edges, far outside it and huge."""
    settings = SoftSilhouetteSettings((40, 48), sigma=0.25)  # (height, width): an oblong crop
    verts, faces, K = fit_like_scene(dtype)
    screen, valid, _, _ = soft._screen_triangles(verts, faces, K, settings.near)
    r = settings.cull_radius
    gen = torch.Generator().manual_seed(11)
    near = (torch.randint(-3, 52, (4000, 3, 2), generator=gen) + r).to(dtype)
    near = near + torch.randint(-2, 3, near.shape, generator=gen).to(dtype) * torch.finfo(dtype).eps * near.abs()
    spread = torch.rand(4000, 3, 2, generator=gen, dtype=dtype) * 120 - 40
    huge = torch.tensor([[[-1e7, 3.0], [1e7, 5.0], [0.0, 1e9]], [[47.0, 39.0], [48.0, 40.0], [47.5, 39.5]],
                         [[-1.0, -1.0], [-r, -r], [-2.0, 0.0]]], dtype=dtype)
    screen = torch.cat([screen.to(dtype), near, spread, huge]).contiguous()
    valid = torch.cat([valid, torch.rand(len(screen) - len(valid), generator=gen) > 0.2])
    box = soft._kernel_boxes(native.soft_kernel(), screen, valid, settings)
    expected = torch.stack(soft._face_boxes(screen, valid, r, 40, 48)[:4], 1)
    assert torch.equal(box, expected)
    assert int((box[:, 2] * box[:, 3] > 0).sum()) > 1000 and bool((box[~valid, 2:] == 0).all())
