"""Soft silhouette: culled sparse version vs dense reference, gradients, pose fitting, edge cases."""

from __future__ import annotations

import math

import pytest
import torch
import trimesh

from sdn3d.math3d.rotations import roty
from sdn3d.render import (
    SoftSilhouetteSettings,
    sigma_from_ndc,
    soft_silhouette,
    soft_silhouette_dense,
)


def crop_K(f: float, size: int, dtype: torch.dtype = torch.float32) -> torch.Tensor:
    c = (size - 1) / 2
    return torch.tensor([[f, 0.0, c], [0.0, f, c], [0.0, 0.0, 1.0]], dtype=dtype)


def mesh_tensors(
    mesh: trimesh.Trimesh, dtype: torch.dtype = torch.float32
) -> tuple[torch.Tensor, torch.Tensor]:
    return torch.tensor(mesh.vertices, dtype=dtype), torch.tensor(mesh.faces)


def small_scene(dtype: torch.dtype = torch.float32) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Three meshes (padded to one face count) with per-mesh crop intrinsics at 32x32."""
    meshes = [
        trimesh.creation.icosphere(subdivisions=1).apply_scale([2.0, 0.8, 1.0]),
        trimesh.creation.box(extents=(2.0, 1.0, 1.5)),
        trimesh.creation.icosphere(subdivisions=2),
    ]
    verts = torch.zeros(3, max(len(m.vertices) for m in meshes), 3, dtype=dtype)
    faces = torch.zeros(3, max(len(m.faces) for m in meshes), 3, dtype=torch.long)
    for n, mesh in enumerate(meshes):
        v, f = mesh_tensors(mesh, dtype)
        rot = roty(torch.tensor(0.4 + n, dtype=dtype))
        verts[n, : len(v)] = v @ rot.T + torch.tensor([0.3 * n, -0.2, 8.0 + 2 * n], dtype=dtype)
        faces[n, : len(f)] = f
    K = torch.stack([crop_K(f, 32, dtype) for f in (60.0, 70.0, 90.0)])
    return verts, faces, K


@pytest.mark.parametrize("sigma", [SoftSilhouetteSettings((1, 1)).sigma, 1.0])
@pytest.mark.parametrize("native", [True, False], ids=["kernel", "pytorch"])
def test_sparse_matches_dense_reference(sigma: float, native: bool) -> None:
    verts, faces, K = small_scene()
    settings = SoftSilhouetteSettings(image_size=(32, 32), sigma=sigma, native_kernel=native)  # default cull_eps
    sparse = soft_silhouette(verts, faces, K, settings)
    dense = soft_silhouette_dense(verts, faces, K, settings)
    assert sparse.shape == (3, 32, 32)
    assert (sparse - dense).abs().max() < 1e-3
    assert dense.max() > 0.99 and dense.min() < 1e-3  # the objects fill part of each crop
    # Chunking and one-mesh-at-a-time give the same result.
    tiny_chunks = SoftSilhouetteSettings(image_size=(32, 32), sigma=sigma, max_pairs_per_chunk=50, native_kernel=native)
    assert torch.allclose(soft_silhouette(verts, faces, K, tiny_chunks), sparse, atol=1e-6)
    assert torch.allclose(soft_silhouette(verts[1:2], faces[1:2], K[1], settings)[0], sparse[1], atol=1e-6)


def test_crop_borders_and_module_wrapper() -> None:
    # Objects cut by the crop border: boxes are clipped, padding pixels must not leak.
    verts, faces, K = small_scene()
    shifted = K.clone()
    shifted[:, 0, 2] += torch.tensor([-20.0, 18.0, 0.0])
    shifted[:, 1, 2] += torch.tensor([0.0, -17.0, 21.0])
    settings = SoftSilhouetteSettings(image_size=(32, 32))
    sparse = soft_silhouette(verts, faces, shifted, settings)
    dense = soft_silhouette_dense(verts, faces, shifted, settings)
    assert (sparse - dense).abs().max() < 1e-3
    assert (sparse.amax((1, 2)) > 0.9).all() and (sparse.amin((1, 2)) < 1e-3).all()
    # Half precision is computed in float32.
    half = soft_silhouette(verts.half(), faces, K, settings)
    assert (
        half.dtype == torch.float32 and (half - soft_silhouette(verts, faces, K, settings)).abs().max() < 2e-2
    )


def test_huge_projected_faces_near_the_camera() -> None:
    # A ground-like quad reaching almost to the near plane projects ~1e4 px out of the crop.
    quad = torch.tensor([[[-30.0, 1.6, 0.11], [30.0, 1.6, 0.11], [30.0, 1.6, 60.0], [-30.0, 1.6, 60.0]]])
    faces = torch.tensor([[0, 1, 2], [0, 2, 3]])
    K = crop_K(40.0, 32)
    settings = SoftSilhouetteSettings(image_size=(32, 32))
    sparse = soft_silhouette(quad, faces, K, settings)
    dense = soft_silhouette_dense(quad, faces, K, settings)
    assert (sparse - dense).abs().max() < 1e-3
    assert sparse[0, -1].min() > 0.99 and sparse[0, 0].max() < 1e-3  # ground below the horizon only


def test_culling_error_follows_cull_eps() -> None:
    # Each culled term is below cull_eps; the error shrinks with it even for a very soft edge.
    verts, faces, K = small_scene()
    for cull_eps, tolerance in ((1e-3, 2e-2), (1e-6, 2e-5)):
        settings = SoftSilhouetteSettings(image_size=(32, 32), sigma=3.0, cull_eps=cull_eps)
        error = (
            soft_silhouette(verts, faces, K, settings) - soft_silhouette_dense(verts, faces, K, settings)
        ).abs()
        assert cull_eps / 10 < error.max() < tolerance


@pytest.mark.parametrize("native", [True, False], ids=["kernel", "pytorch"])
def test_sparse_gradient_matches_dense_autograd(native: bool) -> None:
    verts, faces, K = small_scene(torch.float64)
    # With a negligible culling threshold the culled sum equals the dense one (to ~1e-12).
    settings = SoftSilhouetteSettings(image_size=(32, 32), sigma=1.0, cull_eps=1e-13, native_kernel=native)
    weight = torch.rand(3, 32, 32, dtype=torch.float64)
    grads = []
    for render in (soft_silhouette, soft_silhouette_dense):
        v = verts.clone().requires_grad_(True)
        (render(v, faces, K, settings) * weight).sum().backward()
        grads.append(v.grad)
    assert grads[1].abs().max() > 1e-3
    assert torch.allclose(grads[0], grads[1], rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize("native", [True, False], ids=["kernel", "pytorch"])
def test_gradcheck_tetrahedron(native: bool) -> None:
    verts = torch.tensor(
        [[-1.0, 0.6, 6.0], [1.2, 0.5, 6.5], [0.1, -1.1, 6.2], [0.0, 0.3, 5.0]], dtype=torch.float64
    ).unsqueeze(0)
    verts = verts + 0.01 * torch.randn_like(verts)  # keep pixel centres off the edges
    faces = torch.tensor([[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
    K = crop_K(40.0, 16, torch.float64)
    settings = SoftSilhouetteSettings(image_size=(16, 16), sigma=2.0, native_kernel=native)
    weight = torch.rand(1, 16, 16, dtype=torch.float64)

    def fn(v: torch.Tensor) -> torch.Tensor:
        return (soft_silhouette(v, faces, K, settings) * weight).sum((-1, -2))

    assert torch.autograd.gradcheck(fn, (verts.requires_grad_(True),), eps=1e-7, atol=1e-6, rtol=1e-4)


def test_gradient_wrt_intrinsics_flows() -> None:
    verts, faces, K = small_scene()
    K = K.clone().requires_grad_(True)
    soft_silhouette(verts, faces, K, SoftSilhouetteSettings(image_size=(32, 32))).sum().backward()
    assert torch.isfinite(K.grad).all() and K.grad[:, 0, 0].abs().min() > 0


def _box_verts(pose: torch.Tensor, canonical: torch.Tensor) -> torch.Tensor:
    """Car-sized box (l, h, w) = (4, 1.5, 1.8) at pose (yaw, x, y, z)."""
    dims = canonical.new_tensor([4.0, 1.5, 1.8])
    return (canonical * dims) @ roty(pose[0]).T + pose[1:]


@pytest.fixture
def single_thread():
    """Small per-step problems: one thread avoids stalls when the shared CPU is busy."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


@pytest.mark.usefixtures("single_thread")
def test_pose_is_recovered_by_optimisation() -> None:
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0)).subdivide().subdivide()
    canonical, faces = mesh_tensors(box)
    K = crop_K(90.0, 64)
    settings = SoftSilhouetteSettings(image_size=(64, 64))  # default sigma
    target_pose = torch.tensor([0.6, 0.4, 0.3, 14.0])
    with torch.no_grad():
        target = soft_silhouette(_box_verts(target_pose, canonical)[None], faces, K, settings)
    pose = (target_pose + torch.tensor([0.35, -0.8, 0.4, 2.0])).requires_grad_(True)
    optim = torch.optim.Adam([pose], lr=0.03)
    for _ in range(150):
        sil = soft_silhouette(_box_verts(pose, canonical)[None], faces, K, settings)
        loss = (sil - target).abs().mean()  # L1 between soft silhouettes
        optim.zero_grad()
        loss.backward()
        optim.step()
    with torch.no_grad():
        final = soft_silhouette(_box_verts(pose, canonical)[None], faces, K, settings)
    hard_a, hard_b = final > 0.5, target > 0.5
    iou = (hard_a & hard_b).sum() / (hard_a | hard_b).sum()
    assert iou > 0.95
    assert (pose[1:] - target_pose[1:]).norm() < 0.3
    yaw_error = (pose[0] - target_pose[0] + math.pi / 2) % math.pi - math.pi / 2  # box: yaw mod pi
    assert abs(float(yaw_error.detach())) < 0.05


@pytest.mark.parametrize("native", [True, False], ids=["kernel", "pytorch"])
def test_no_nan_gradients_with_degenerate_and_clipped_faces(native: bool) -> None:
    verts, faces, K = small_scene()
    extra = torch.tensor(
        [[0.1, 0.1, 8.0], [0.2, 0.2, 8.0], [0.3, 0.3, 8.0], [0.0, 0.0, -3.0], [1.0, 0.0, 0.0]]
    )
    base = verts.shape[1]
    # Repeated-vertex, collinear, behind-the-camera and at-the-camera faces added to every mesh.
    new_faces = torch.tensor([[0, 0, 1], [0, 1, 2], [3, 0, 1], [4, 0, 1], [3, 4, 2]]) + base
    verts2 = torch.cat([verts, extra.expand(3, -1, -1)], 1).requires_grad_(True)
    faces2 = torch.cat([faces, new_faces.expand(3, -1, -1)], 1)
    settings = SoftSilhouetteSettings(image_size=(32, 32), native_kernel=native)
    sil = soft_silhouette(verts2, faces2, K, settings)
    assert torch.allclose(sil, soft_silhouette(verts, faces, K, settings), atol=1e-6)
    sil.sum().backward()
    assert torch.isfinite(verts2.grad).all()
    assert (verts2.grad[:, base:] == 0).all()  # culled faces pass no gradient


@pytest.mark.parametrize("native", [True, False], ids=["kernel", "pytorch"])
def test_nan_mesh_renders_empty_with_zero_gradient(native: bool) -> None:
    verts, faces, K = small_scene()
    verts = verts.clone()
    verts[1, 0, 0] = math.nan  # one NaN vertex in mesh 1
    verts[2] = math.nan  # mesh 2 entirely NaN
    v = verts.requires_grad_(True)
    settings = SoftSilhouetteSettings(image_size=(32, 32), native_kernel=native)
    sil = soft_silhouette(v, faces, K, settings)
    assert torch.isfinite(sil).all() and (sil[2] == 0).all() and sil[1].max() > 0.9
    sil.sum().backward()
    assert torch.isfinite(v.grad).all() and (v.grad[2] == 0).all() and v.grad[0].abs().sum() > 0


def test_empty_inputs_and_settings() -> None:
    settings = SoftSilhouetteSettings(image_size=(8, 12))
    empty = soft_silhouette(
        torch.zeros(0, 4, 3), torch.zeros(0, 3, dtype=torch.long), crop_K(10.0, 8), settings
    )
    assert empty.shape == (0, 8, 12)
    no_faces = soft_silhouette(
        torch.ones(2, 4, 3), torch.zeros(0, 3, dtype=torch.long), crop_K(10.0, 8), settings
    )
    assert no_faces.shape == (2, 8, 12) and (no_faces == 0).all()
    s = SoftSilhouetteSettings(image_size=(64, 64), sigma=0.7, cull_eps=1e-4)
    assert torch.sigmoid(
        torch.tensor(-s.cull_radius_sq / s.sigma, dtype=torch.float64)
    ).item() == pytest.approx(1e-4)
    assert sigma_from_ndc(1e-4, (64, 64)) == pytest.approx(0.1024)
    with pytest.raises(ValueError, match="sigma"):
        SoftSilhouetteSettings(image_size=(8, 8), sigma=0.0)
    with pytest.raises(ValueError, match="cull_eps"):
        SoftSilhouetteSettings(image_size=(8, 8), cull_eps=0.7)
    with pytest.raises(ValueError, match="K"):
        soft_silhouette(
            torch.ones(2, 4, 3), torch.zeros(1, 3, dtype=torch.long), torch.eye(3).expand(3, 3, 3), settings
        )


def test_culling_back_faces_keeps_a_closed_meshs_outline_and_halves_its_faces(monkeypatch) -> None:
    """A closed, outward-wound mesh: its front faces alone cover its silhouette (the same pixels above 0.5), while
    the raster draws about half the faces; a lone triangle facing away is not drawn at all."""
    import sdn3d.render.soft as soft

    mesh = trimesh.creation.icosphere(subdivisions=2).apply_scale([2.0, 0.8, 1.0])
    verts, faces = mesh_tensors(mesh)
    verts = (verts @ roty(torch.tensor([0.6]))[0].T + torch.tensor([0.3, 0.2, 6.0]))[None]
    K = crop_K(40.0, 32)
    drawn: list[int] = []
    chunks = soft._window_chunks

    def counted(box_w, box_h, budget):
        drawn.append(len(box_w))
        return chunks(box_w, box_h, budget)

    monkeypatch.setattr(soft, "_window_chunks", counted)  # the PyTorch path's chunking counts the faces drawn
    both = soft_silhouette(verts, faces, K, SoftSilhouetteSettings((32, 32), native_kernel=False))
    front = soft_silhouette(verts, faces, K, SoftSilhouetteSettings((32, 32), cull_backfaces=True, native_kernel=False))
    # the same hard outline: above 0.5 the same pixels but a few on the outline (one soft edge there, not two)
    inside = int((both > 0.5).sum())
    assert inside > 100 and not bool(((front > 0.5) & (both <= 0.5)).any())
    assert int(((both > 0.5) & (front <= 0.5)).sum()) <= 0.05 * inside
    assert 0.4 * len(faces) < drawn[1] < 0.6 * len(faces) and drawn[0] == len(faces)
    # one soft side per outline edge instead of two: a little less outside the outline, never more
    assert float((front - both).max()) < 1e-6 and float((both - front).sum()) > 1.0
    corners = torch.tensor([[[0.0, -1.0, 5.0], [-1.0, 1.0, 5.0], [1.0, 1.0, 5.0]]])
    towards, away = torch.tensor([[0, 1, 2]]), torch.tensor([[0, 2, 1]])  # normal (v1-v0)x(v2-v0): -z, +z
    cull = SoftSilhouetteSettings((32, 32), cull_backfaces=True)
    assert float(soft_silhouette(corners, away, K, SoftSilhouetteSettings((32, 32))).sum()) > 10
    assert float(soft_silhouette(corners, away, K, cull).sum()) == 0
    assert torch.equal(soft_silhouette(corners, towards, K, cull),
                       soft_silhouette(corners, away, K, SoftSilhouetteSettings((32, 32))))
