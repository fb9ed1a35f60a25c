"""Hard z-buffer rasterizer: agreement with trimesh ray casting, edge cases, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
import trimesh

from sdn3d.render import Fragments, RasterSettings, rasterize_meshes

H, W = 96, 160
FX = FY = 110.0
CX, CY = (W - 1) / 2, (H - 1) / 2
K = torch.tensor([[FX, 0.0, CX], [0.0, FY, CY], [0.0, 0.0, 1.0]], dtype=torch.float64)
SETTINGS = RasterSettings(image_size=(H, W))


def pad_meshes(meshes: list[trimesh.Trimesh], dtype: torch.dtype = torch.float32) -> tuple[torch.Tensor, ...]:
    """Padded ``(N, V, 3)`` verts and ``(N, F, 3)`` faces (padding faces are (0, 0, 0))."""
    num_v = max(len(m.vertices) for m in meshes)
    num_f = max(len(m.faces) for m in meshes)
    verts = torch.zeros(len(meshes), num_v, 3, dtype=dtype)
    faces = torch.zeros(len(meshes), num_f, 3, dtype=torch.long)
    for n, mesh in enumerate(meshes):
        verts[n, : len(mesh.vertices)] = torch.as_tensor(np.asarray(mesh.vertices), dtype=dtype)
        faces[n, : len(mesh.faces)] = torch.as_tensor(np.asarray(mesh.faces))
    return verts, faces


def random_scene(rng: np.random.Generator, count: int = 6) -> list[trimesh.Trimesh]:
    makers = [
        lambda: trimesh.creation.icosphere(subdivisions=2),
        lambda: trimesh.creation.box(),
        lambda: trimesh.creation.capsule(height=1.0, radius=0.5, count=[12, 12]),
    ]
    meshes = []
    for i in range(count):
        mesh = makers[i % 3]()
        mesh.apply_scale(rng.uniform(1.0, 4.0, 3))
        mesh.apply_transform(trimesh.transformations.random_rotation_matrix(rng.random(3)))
        z = rng.uniform(5.0, 40.0)
        mesh.apply_translation([rng.uniform(-0.5, 0.5) * z * W / FX, rng.uniform(-0.4, 0.4) * z * H / FY, z])
        meshes.append(mesh)
    return meshes


def raycast(meshes: list[trimesh.Trimesh]) -> tuple[np.ndarray, np.ndarray]:
    """Visible mesh index (-1 none) and camera z per pixel, one ray per pixel centre.

    Rays are cast per mesh, only over its projected bounding box: trimesh's rtree candidate
    search is slow for rays crossing a whole scene.
    """
    best = np.full(H * W, np.inf)
    owner = np.full(H * W, -1)
    for n, mesh in enumerate(meshes):
        uv = mesh.vertices[:, :2] / mesh.vertices[:, 2:] * [FX, FY] + [CX, CY]
        j0, i0 = np.maximum(np.floor(uv.min(0)).astype(int), 0)
        j1, i1 = np.minimum(np.ceil(uv.max(0)).astype(int), [W - 1, H - 1])
        if j1 < j0 or i1 < i0:
            continue
        jj, ii = np.meshgrid(np.arange(j0, j1 + 1), np.arange(i0, i1 + 1))
        dirs = np.stack([(jj - CX) / FX, (ii - CY) / FY, np.ones(jj.shape)], -1).reshape(-1, 3)
        loc, ray, _ = mesh.ray.intersects_location(np.zeros_like(dirs), dirs, multiple_hits=False)
        pixel = (ii * W + jj).ravel()[ray]
        closer = loc[:, 2] < best[pixel]
        best[pixel[closer]] = loc[closer, 2]
        owner[pixel[closer]] = n
    return owner, best


def render(verts, faces, settings=SETTINGS, **kwargs) -> Fragments:
    mesh_to_image = torch.zeros(verts.shape[0], dtype=torch.long)
    return rasterize_meshes(verts, faces, K, settings, mesh_to_image, 1, **kwargs)


@pytest.mark.parametrize("seed", [0, 1])
def test_matches_trimesh_raycast(seed: int) -> None:
    meshes = random_scene(np.random.default_rng(seed))
    verts, faces = pad_meshes(meshes)
    frags = render(verts, faces)
    owner, z_ref = raycast(meshes)
    ours = frags.pix_to_mesh.view(-1).numpy()
    assert (owner >= 0).mean() > 0.05, "the scene should cover part of the image"
    assert (ours == owner).mean() >= 0.995
    same = (ours == owner) & (owner >= 0)
    rel = np.abs(frags.depth.view(-1).numpy()[same] - z_ref[same]) / z_ref[same]
    assert rel.max() < 1e-4
    assert torch.isinf(frags.depth[~frags.mask]).all()


def test_barycentrics_are_perspective_correct() -> None:
    meshes = random_scene(np.random.default_rng(3))
    verts, faces = pad_meshes(meshes, torch.float64)
    frags = render(verts, faces)
    hit = frags.mask[0]
    assert hit.sum() > 100
    packed = frags.pix_to_face[0][hit]
    tri = verts.reshape(-1, 3)[
        (faces + torch.arange(len(meshes)).view(-1, 1, 1) * verts.shape[1]).view(-1, 3)[packed]
    ]
    bary = frags.bary[0][hit]
    assert torch.allclose(bary.sum(-1), torch.ones((), dtype=bary.dtype), atol=1e-9) and (bary >= 0).all()
    point = (bary.unsqueeze(-1) * tri).sum(1)  # surface point from barycentrics
    assert torch.allclose(point[:, 2], frags.depth[0][hit], rtol=1e-9)
    rows, cols = hit.nonzero().unbind(1)
    u = FX * point[:, 0] / point[:, 2] + CX
    v = FY * point[:, 1] / point[:, 2] + CY
    assert torch.allclose(u, cols.double(), atol=1e-6) and torch.allclose(v, rows.double(), atol=1e-6)


def test_ground_plane_depth_is_exact() -> None:
    height = 1.65  # camera above a ground plane y = 1.65 (y points down)
    verts = torch.tensor(
        [[[-80.0, height, 1.0], [80.0, height, 1.0], [80.0, height, 400.0], [-80.0, height, 400.0]]]
    )
    faces = torch.tensor([[[0, 1, 2], [0, 2, 3]]])
    frags = render(verts, faces)
    rows = torch.arange(H, dtype=torch.float64).view(-1, 1).expand(H, W)
    expected = FY * height / (rows - CY)  # ray-plane intersection
    inside = (rows > CY) & (expected < 400.0) & (expected > 1.0)
    # Keep clear of the far edge and the side edges of the quad.
    inside &= (expected < 300.0) & ((torch.arange(W) - CX).abs().view(1, -1) / FX * expected < 70.0)
    assert inside.sum() > 1000
    assert frags.mask[0][inside].all() and not frags.mask[0][rows < CY].any()
    rel = (frags.depth[0][inside].double() - expected[inside]).abs() / expected[inside]
    assert rel.max() < 1e-6


def test_shared_edges_leave_no_holes() -> None:
    # A square whose diagonals pass exactly through pixel centres (half-integers relative to the
    # principal point) while its sides do not, split into two triangles either way.
    z, half = 10.0, 10.25
    corners = [(-half, -half), (half, -half), (half, half), (-half, half)]
    verts = torch.tensor([[[u * z / FX, v * z / FY, z] for u, v in corners]], dtype=torch.float64)
    for faces in (torch.tensor([[[0, 1, 2], [0, 2, 3]]]), torch.tensor([[[0, 1, 3], [1, 2, 3]]])):
        frags = render(verts, faces)
        cols = (torch.arange(W) - CX).abs() < half
        rows = (torch.arange(H) - CY).abs() < half
        assert frags.mask[0][rows][:, cols].all()
        assert int(frags.mask.sum()) == 20 * 20


def test_batches_chunks_and_intrinsics_per_image() -> None:
    meshes = random_scene(np.random.default_rng(4))
    verts, faces = pad_meshes(meshes)
    image = torch.tensor([0, 1, 0, 1, 1, 0])
    K2 = torch.stack([K, K * torch.tensor([[0.5], [0.5], [1.0]], dtype=torch.float64)])
    batched = rasterize_meshes(verts, faces, K2, SETTINGS, image, 2)
    small = RasterSettings(image_size=(H, W), max_pairs_per_chunk=97)
    chunked = rasterize_meshes(verts, faces, K2, small, image, 2)
    for b in range(2):
        sel = (image == b).nonzero().squeeze(1)
        alone = rasterize_meshes(verts[sel], faces[sel], K2[b], SETTINGS, torch.zeros_like(sel), 1)
        expected = torch.where(alone.mask[0], sel[alone.pix_to_mesh[0].clamp(min=0)], -1)
        assert torch.equal(batched.pix_to_mesh[b], expected)
        assert torch.equal(batched.depth[b], alone.depth[0])
    for field in ("pix_to_face", "pix_to_mesh", "depth", "bary"):
        assert torch.equal(getattr(batched, field), getattr(chunked, field))
    assert torch.equal(
        batched.pix_to_mesh, torch.where(batched.mask, batched.pix_to_face // faces.shape[1], -1)
    )


def test_empty_and_invisible_inputs() -> None:
    empty = rasterize_meshes(
        torch.zeros(0, 0, 3), torch.zeros(0, 0, 3, dtype=torch.long), K, SETTINGS, batch_size=2
    )
    assert empty.pix_to_face.shape == (2, H, W) and (empty.pix_to_face == -1).all()
    assert torch.isinf(empty.depth).all() and (empty.bary == 0).all()
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    behind = box.copy().apply_translation([0.0, 0.0, -5.0])
    outside = box.copy().apply_translation([200.0, 0.0, 10.0])
    beyond = box.copy().apply_translation([0.0, 0.0, 5000.0])
    verts, faces = pad_meshes([behind, outside, beyond])
    frags = render(verts, faces)
    assert not frags.mask.any()
    no_faces = rasterize_meshes(verts, torch.zeros(0, 3, dtype=torch.long), K, SETTINGS)
    assert no_faces.pix_to_face.shape == (3, H, W) and not no_faces.mask.any()


def test_near_plane_degenerate_and_nan_faces_are_culled() -> None:
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0)).apply_translation([0.0, 0.0, 10.0])
    verts, faces = pad_meshes([box], torch.float64)
    reference = render(verts, faces)
    # Extra faces: straddling the near plane, degenerate (repeated / collinear vertices), NaN.
    extra_v = torch.tensor(
        [
            [-5.0, -5.0, -1.0],
            [5.0, -5.0, 20.0],
            [0.0, 5.0, 20.0],
            [1.0, 1.0, 8.0],
            [2.0, 2.0, 8.0],
            [3.0, 3.0, 8.0],
            [math.nan, 0.0, 9.0],
        ],
        dtype=torch.float64,
    )
    base = verts.shape[1]
    extra_f = torch.tensor([[0, 1, 2], [3, 3, 4], [3, 4, 5], [6, 3, 4], [6, 6, 6]]) + base
    verts2 = torch.cat([verts, extra_v[None]], 1)
    faces2 = torch.cat([faces, extra_f[None]], 1)
    frags = render(verts2, faces2)
    assert torch.equal(frags.pix_to_face, reference.pix_to_face)
    assert torch.equal(frags.depth, reference.depth)
    # A mesh made only of NaN vertices renders nothing and does not disturb the others.
    nan_mesh = torch.full_like(verts, math.nan)
    both = render(torch.cat([verts, nan_mesh]), torch.cat([faces, faces]))
    assert torch.equal(both.pix_to_mesh[0], reference.pix_to_mesh[0])


def test_backface_culling() -> None:
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0)).apply_translation([0.0, 0.0, 10.0])
    verts, faces = pad_meshes([box])
    culled = RasterSettings(image_size=(H, W), cull_backfaces=True)
    both = render(verts, faces)
    front = render(verts, faces, culled)
    assert front.mask.sum() > 100 and torch.equal(front.mask, both.mask)
    assert torch.allclose(front.depth[front.mask], both.depth[both.mask])
    flipped = render(verts, faces.flip(-1), culled)  # inward winding: only the far side survives
    assert torch.equal(flipped.mask, both.mask)
    assert (flipped.depth[flipped.mask] > both.depth[both.mask] + 1e-3).all()
    assert flipped.depth[0, H // 2, W // 2] == pytest.approx(11.0) and both.depth[0, H // 2, W // 2] == 9.0


def test_gradients_enabled_do_not_crash() -> None:
    meshes = random_scene(np.random.default_rng(5), count=2)
    verts, faces = pad_meshes(meshes)
    frags = render(verts.requires_grad_(True), faces)
    assert not frags.depth.requires_grad and frags.mask.any()


def test_bad_input_raises() -> None:
    verts, faces = pad_meshes([trimesh.creation.box().apply_translation([0, 0, 5])])
    with pytest.raises(ValueError, match="verts"):
        rasterize_meshes(verts[0], faces, K, SETTINGS)
    with pytest.raises(ValueError, match="faces"):
        rasterize_meshes(verts, faces.float(), K, SETTINGS)
    with pytest.raises(ValueError, match="faces index"):
        rasterize_meshes(verts, faces + 100, K, SETTINGS)
    with pytest.raises(ValueError, match="K"):
        rasterize_meshes(verts, faces, K[:2], SETTINGS)
    with pytest.raises(ValueError, match="mesh_to_image"):
        rasterize_meshes(verts, faces, K, SETTINGS, torch.tensor([3]), 2)
    with pytest.raises(ValueError, match="batch_size"):
        rasterize_meshes(verts.expand(2, -1, -1), faces[0], K, SETTINGS, batch_size=1)
    with pytest.raises(ValueError, match="image_size"):
        RasterSettings(image_size=(0, 10))
    with pytest.raises(ValueError, match="far"):
        RasterSettings(image_size=(10, 10), near=1.0, far=0.5)


def _whole_at(values: torch.Tensor, flat: torch.Tensor) -> torch.Tensor:
    return values.reshape(-1, *values.shape[3:])[flat]


def test_cropped_fragments_are_the_whole_images_inside_their_box() -> None:
    meshes = random_scene(np.random.default_rng(7))
    meshes[0].apply_translation([-60.0, 0.0, 0.0])  # partly off the left edge
    verts, faces = pad_meshes(meshes, torch.float64)
    image = torch.tensor([0, 1, 0, 1, 1, 0])
    g = torch.Generator().manual_seed(3)
    for settings, images, sel in ((SETTINGS, 2, slice(None)), (RasterSettings((H, W), max_pairs_per_chunk=97), 2,
                                                                  slice(None)), (SETTINGS, 1, slice(3, 4))):
        v, f, m = verts[sel], faces[sel], torch.zeros_like(image[sel]) if images == 1 else image
        whole = rasterize_meshes(v, f, K, settings, m, images)
        crop = rasterize_meshes(v, f, K, settings, m, images, crop=True)
        x0, y0, x1, y1 = crop.box
        assert crop.image_size == (H, W) and whole.box == (0, 0, W, H) and whole.whole and not crop.whole
        assert crop.pix_to_face.shape == (images, y1 - y0, x1 - x0) and crop.bary.shape[-1] == 3
        inside = torch.zeros(H, W, dtype=torch.bool)
        inside[y0:y1, x0:x1] = True
        for field, empty in (("pix_to_face", -1), ("pix_to_mesh", -1), ("depth", math.inf), ("bary", 0.0)):
            full, box = getattr(whole, field), getattr(crop, field)
            assert torch.equal(box, full[:, y0:y1, x0:x1]), field  # the same values in the box
            assert bool((full[:, ~inside] == empty).all()), field  # and nothing outside it
            assert torch.equal(crop.in_image(box, empty), full), field
        # the box is tight: each of its edge rows and columns holds a covered pixel of some image
        covered = whole.mask.any(0)
        assert bool(covered[y0].any() and covered[y1 - 1].any() and covered[:, x0].any() and covered[:, x1 - 1].any())
        assert torch.equal(crop.covered(), whole.mask.view(-1).nonzero().flatten())
        flat = torch.cat([torch.randint(0, images * H * W, (3000,), generator=g), crop.covered(),
                          torch.tensor([0, images * H * W - 1])])
        for pixels in (flat, crop.locate(flat)):  # looked up each time, or found once for all four
            for looked, got in ((whole.pix_to_face, crop.face_at(pixels)), (whole.pix_to_mesh, crop.mesh_at(pixels)),
                                (whole.depth, crop.depth_at(pixels)), (whole.bary, crop.bary_at(pixels))):
                assert torch.equal(got, _whole_at(looked, flat))
        assert crop.locate(crop.covered()).inside is None and crop.locate(flat).inside is not None
        assert torch.equal(crop.mesh_at(crop.covered()), whole.pix_to_mesh[whole.mask])  # all inside: no empties


def test_cropped_fragments_of_nothing_are_an_empty_box() -> None:
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    verts, faces = pad_meshes([box.copy().apply_translation([0.0, 0.0, -5.0]),
                               box.copy().apply_translation([200.0, 0.0, 10.0])], torch.float64)
    for v, f in ((verts, faces), (torch.zeros(0, 0, 3), torch.zeros(0, 0, 3, dtype=torch.long))):
        crop = rasterize_meshes(v, f, K, SETTINGS, torch.zeros(len(v), dtype=torch.long), 1, crop=True)
        assert crop.box == (0, 0, 0, 0) and crop.pix_to_face.shape == (1, 0, 0) and crop.image_size == (H, W)
        flat = torch.tensor([0, 5, H * W - 1])
        assert torch.equal(crop.face_at(flat), torch.full((3,), -1))
        assert torch.equal(crop.mesh_at(flat), crop.face_at(flat))
        assert bool(torch.isinf(crop.depth_at(flat)).all()) and crop.bary_at(flat).shape == (3, 3)
        assert not bool(crop.bary_at(flat).any()) and len(crop.covered()) == 0
        assert torch.equal(crop.in_image(crop.depth, math.inf), torch.full((1, H, W), math.inf, dtype=crop.depth.dtype))
