"""Mesh library: procedural templates, ShapeNet loading, padded MeshBank."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest
import torch
import trimesh
from PIL import Image, ImageDraw
from scipy.spatial import cKDTree

from sdn3d.math3d.ffd import bernstein_basis, ffd_deform
from sdn3d.meshes import (
    SHAPENET_TO_CANONICAL,
    TEMPLATE_CATEGORY,
    TEMPLATE_DIMENSIONS,
    TEMPLATE_NAMES,
    MeshBank,
    all_templates,
    build_template,
    cluster_simplify,
    load_mesh_directory,
    load_shapenet_obj,
)
from sdn3d.meshes.templates import _build_arrays

FACE_BUDGET = 1500


def side_silhouette(mesh: trimesh.Trimesh, res: int = 128) -> np.ndarray:
    """``(res, res)`` bool mask of the x-y (side view) projection of a unit-box mesh."""
    img = Image.new("L", (res, res), 0)
    draw = ImageDraw.Draw(img)
    xy = (np.asarray(mesh.vertices)[:, :2] + 0.5) * (res - 1)
    for tri in xy[mesh.faces]:
        draw.polygon([tuple(p) for p in tri], fill=255)
    return np.asarray(img) > 0


@pytest.fixture(scope="module")
def templates() -> dict[str, trimesh.Trimesh]:
    return dict(zip(TEMPLATE_NAMES, all_templates(), strict=True))


# -- templates --------------------------------------------------------------------------------


def test_template_tables_cover_all_names() -> None:
    assert TEMPLATE_NAMES == ("sedan", "hatchback", "wagon", "suv", "pickup", "van", "minibus", "bus")
    assert set(TEMPLATE_DIMENSIONS) == set(TEMPLATE_NAMES) == set(TEMPLATE_CATEGORY)
    assert set(TEMPLATE_CATEGORY.values()) == {"Car", "Van"}
    assert TEMPLATE_CATEGORY["sedan"] == "Car" and TEMPLATE_CATEGORY["bus"] == "Van"
    length, height, width = TEMPLATE_DIMENSIONS["bus"]
    assert length > 10 and height > 3 and length > TEMPLATE_DIMENSIONS["sedan"][0] * 2


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_template_is_closed_outward_and_in_budget(templates: dict[str, trimesh.Trimesh], name: str) -> None:
    mesh = templates[name]
    assert mesh.is_watertight
    assert mesh.is_winding_consistent
    assert mesh.volume > 0.3  # a solid vehicle fills a good part of its box, outward normals
    assert 400 <= len(mesh.faces) <= FACE_BUDGET
    np.testing.assert_allclose(mesh.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-6)


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_template_is_mirror_symmetric(templates: dict[str, trimesh.Trimesh], name: str) -> None:
    verts = np.asarray(templates[name].vertices)
    dist, _ = cKDTree(verts).query(verts * [1.0, 1.0, -1.0])
    assert dist.max() < 1e-6


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_template_orientation(templates: dict[str, trimesh.Trimesh], name: str) -> None:
    verts = np.asarray(templates[name].vertices)
    # Wheels touch the ground (y = +0.5) near the axles, not at the bumpers.
    ground = verts[verts[:, 1] > 0.5 - 1e-6]
    assert len(ground) >= 4 and np.all(np.abs(ground[:, 0]) < 0.4)
    # Roof (y = -0.5) is on the centre line, and the whole floor of the body is above the ground.
    roof = verts[verts[:, 1] < -0.5 + 1e-6]
    assert np.all(np.abs(roof[:, 2]) < 1e-9)


def test_front_is_plus_x_for_cars(templates: dict[str, trimesh.Trimesh]) -> None:
    # The hood (front, +x) is lower than the roof: the top of the body near x = +0.45 is well
    # below the roof for every template with a hood; the pickup bed (rear) is low too.
    for name in ("sedan", "hatchback", "wagon", "suv", "pickup", "van", "minibus"):
        verts = np.asarray(templates[name].vertices)
        front_top = verts[verts[:, 0] > 0.45][:, 1].min()
        assert front_top > -0.3, name
    bed = np.asarray(templates["pickup"].vertices)
    mid_rear = bed[(bed[:, 0] > -0.35) & (bed[:, 0] < -0.15)]
    assert mid_rear[:, 1].min() > -0.2


def test_side_silhouettes_differ_pairwise(templates: dict[str, trimesh.Trimesh]) -> None:
    masks = {n: side_silhouette(m) for n, m in templates.items()}
    for a, b in itertools.combinations(TEMPLATE_NAMES, 2):
        iou = (masks[a] & masks[b]).sum() / (masks[a] | masks[b]).sum()
        assert iou < 0.96, f"{a} vs {b}: side IoU {iou:.3f}"


def test_templates_are_deterministic() -> None:
    first = build_template("pickup")
    first.vertices[0] = 99.0  # a returned mesh is a copy: mutating it must not touch the cache
    again = build_template("pickup")
    fresh_v, fresh_f, _ = _build_arrays.__wrapped__("pickup")
    np.testing.assert_array_equal(again.vertices, fresh_v)
    np.testing.assert_array_equal(again.faces, fresh_f)


def test_unknown_template_name() -> None:
    with pytest.raises(ValueError, match="name must be one of"):
        build_template("tank")


# -- ShapeNet ---------------------------------------------------------------------------------


def _shapenet_wedge() -> trimesh.Trimesh:
    """A car-like wedge in ShapeNet orientation: +y up, front towards -z, width along x.

    The front (z = -2) is lower (roof 0.5) than the back (z = +2, roof 1.0), and the back of the
    right side (+x) bulges out to x = 1.2 so that a reflection would be detected.
    """
    box = trimesh.creation.box(extents=[1.6, 1.0, 4.0])
    v = np.array(box.vertices) + [0.0, 0.5, 0.0]  # x in +-0.8, y in [0, 1], z in +-2
    front = v[:, 2] < 0
    v[front & (v[:, 1] > 0.5), 1] = 0.5
    v[~front & (v[:, 0] > 0), 0] = 1.2
    return trimesh.Trimesh(v, box.faces, process=False)


def _write_obj(path: Path, mesh: trimesh.Trimesh, header: str = "") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(header + trimesh.exchange.obj.export_obj(mesh, include_normals=False))
    return path


def test_shapenet_axis_map_is_a_proper_rotation() -> None:
    np.testing.assert_allclose(SHAPENET_TO_CANONICAL @ SHAPENET_TO_CANONICAL.T, np.eye(3))
    assert np.linalg.det(SHAPENET_TO_CANONICAL) == pytest.approx(1.0)
    # ShapeNet front (-z) -> canonical +x, up (+y) -> canonical -y (down is +y).
    np.testing.assert_allclose(SHAPENET_TO_CANONICAL @ [0, 0, -1], [1, 0, 0])
    np.testing.assert_allclose(SHAPENET_TO_CANONICAL @ [0, 1, 0], [0, -1, 0])


def test_load_shapenet_obj_orientation(tmp_path: Path) -> None:
    path = _write_obj(tmp_path / "car" / "models" / "model_normalized.obj", _shapenet_wedge(),
                      header="mtllib model_normalized.mtl\nusemtl paint\n")  # the .mtl is missing
    mesh = load_shapenet_obj(path)
    v = np.asarray(mesh.vertices)
    np.testing.assert_allclose(mesh.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-9)
    front, back = v[v[:, 0] > 0.49], v[v[:, 0] < -0.49]
    # Up -> -y: the ground (ShapeNet y = 0) is at y = +0.5; the low front roof lies at y = 0.
    assert front[:, 1].max() == pytest.approx(0.5) and front[:, 1].min() == pytest.approx(0.0)
    assert back[:, 1].min() == pytest.approx(-0.5)
    # The right-side bulge (ShapeNet +x, back) is at canonical -z: proper rotation, no mirror.
    assert back[:, 2].min() == pytest.approx(-0.5) and front[:, 2].min() > -0.45
    assert mesh.is_watertight and mesh.volume > 0
    assert mesh.visual.kind is None


_MULTI_OBJ = """mtllib model_normalized.mtl
o body
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
vt 0 0
vt 1 0
vt 0 1
vn 0 0 1
usemtl red
f 1/1/1 3/3/1 2/2/1
f 1/1/1 2/2/1 4/3/1
usemtl blue
f 1/1/1 4/2/1 3/3/1
f 2/1/1 3/2/1 4/3/1
o wheel
v 2 0 0
v 3 0 0
v 2 1 0
v 2 0 1
usemtl red
f 5 7 6
f 5 6 8
f 5 8 7
f 6 7 8
"""


def test_load_shapenet_obj_merges_objects_and_drops_materials(tmp_path: Path) -> None:
    path = tmp_path / "multi.obj"
    path.write_text(_MULTI_OBJ)
    mesh = load_shapenet_obj(path)
    assert isinstance(mesh, trimesh.Trimesh) and len(mesh.faces) == 8 and len(mesh.vertices) == 8
    assert mesh.visual.kind is None and mesh.is_watertight and mesh.volume > 0
    np.testing.assert_allclose(mesh.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-9)


def test_load_shapenet_obj_simplifies_to_budget(tmp_path: Path) -> None:
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5120 faces
    path = _write_obj(tmp_path / "sphere.obj", sphere)
    mesh = load_shapenet_obj(path, max_faces=600)
    assert 100 <= len(mesh.faces) <= 600
    np.testing.assert_allclose(mesh.bounds, [[-0.5] * 3, [0.5] * 3], atol=1e-9)
    assert mesh.faces.max() < len(mesh.vertices)
    # Still the same round shape: vertices stay near the sphere of radius 0.5.
    radii = np.linalg.norm(mesh.vertices, axis=1)
    assert radii.min() > 0.4


def test_cluster_simplify_keeps_small_meshes() -> None:
    box = trimesh.creation.box()
    v, f = cluster_simplify(box.vertices, box.faces, max_faces=100)
    np.testing.assert_array_equal(f, box.faces)
    with pytest.raises(ValueError, match="max_faces"):
        cluster_simplify(box.vertices, box.faces, max_faces=2)


def _np_unique_simplify(vertices: np.ndarray, faces: np.ndarray, max_faces: int) -> tuple[np.ndarray, ...]:
    """cluster_simplify as it was written with ``np.unique(axis=0)`` (session 21): the reference its faster unique rows
    must reproduce to the bit."""
    vertices, faces = np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)
    if len(faces) <= max_faces:
        return vertices, faces, np.arange(len(faces))
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    extent = np.maximum(hi - lo, 1e-12)
    resolution = 256.0
    while resolution >= 1.0:
        cells = np.floor((vertices - lo) / extent * resolution).astype(np.int64)
        _, cluster, counts = np.unique(cells, axis=0, return_inverse=True, return_counts=True)
        new_faces = cluster.reshape(-1)[faces]
        keep = (new_faces[:, 0] != new_faces[:, 1]) & (new_faces[:, 1] != new_faces[:, 2]) & (
            new_faces[:, 0] != new_faces[:, 2])
        new_faces = new_faces[keep]
        _, first = np.unique(np.sort(new_faces, axis=1), axis=0, return_index=True)
        new_faces, kept = new_faces[np.sort(first)], np.flatnonzero(keep)[np.sort(first)]
        if len(new_faces) <= max_faces:
            sums = np.zeros((len(counts), 3))
            np.add.at(sums, cluster.reshape(-1), vertices)
            used, remap = np.unique(new_faces, return_inverse=True)
            return (sums / counts[:, None])[used], remap.reshape(-1, 3), kept
        resolution /= 1.25
    raise ValueError("no reduction")


def test_cluster_simplify_is_the_np_unique_reference_to_the_bit() -> None:
    # The templates at the fit's budgets (coarse 250, fine 600) and others, and random meshes with repeated faces in
    # other windings (which the face step must drop, keeping the first one's winding).
    rng = np.random.default_rng(3)
    meshes = [(mesh.vertices, mesh.faces) for mesh in all_templates()]
    for _ in range(6):
        v = rng.normal(size=(int(rng.integers(20, 300)), 3))
        f = rng.integers(0, len(v), size=(int(rng.integers(40, 700)), 3))
        meshes.append((v, np.concatenate([f, f[rng.integers(0, len(f), 25)][:, [1, 2, 0]]])))
    for (vertices, faces), budget in itertools.product(meshes, (20, 250, 600)):
        got = cluster_simplify(vertices, faces, budget, return_index=True)
        for a, b in zip(got, _np_unique_simplify(vertices, faces, budget), strict=True):
            assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("low, high", [(0, 5), (-7, 7), (2**40, 2**40 + 3), (-2**62, 2**62)])
def test_unique_rows_is_np_uniques_first_index_inverse_and_counts(low: int, high: int) -> None:
    from sdn3d.meshes.shapenet import _unique_rows

    rng = np.random.default_rng(low & 0xFFFF)
    for shape in ((0, 3), (1, 3), (200, 3), (300, 2)):
        rows = rng.integers(low, high, size=shape, dtype=np.int64, endpoint=True)
        rows = np.concatenate([rows, rows[: len(rows) // 3]])  # repeats, whose first index must be the earlier one
        _, first, inverse, counts = np.unique(rows, axis=0, return_index=True, return_inverse=True,
                                              return_counts=True)
        got = _unique_rows(rows)
        for a, b in zip(got, (first, inverse.reshape(-1), counts), strict=True):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("content", ["", "# only a comment\n", "v nan 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\n",
                                     "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "v 0 0 0\nf 1 2 9\n"])
def test_load_shapenet_obj_bad_files(tmp_path: Path, content: str) -> None:
    path = tmp_path / "bad" / "model_normalized.obj"
    path.parent.mkdir()
    path.write_text(content)
    with pytest.raises(ValueError, match=re.escape(str(path))):
        load_shapenet_obj(path)


def test_load_shapenet_obj_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nope.obj"
    with pytest.raises(ValueError, match=re.escape(str(path))):
        load_shapenet_obj(path)


def test_load_mesh_directory_sorted_names(tmp_path: Path) -> None:
    for model in ("b2", "a1", "c3"):
        _write_obj(tmp_path / "02958343" / model / "models" / "model_normalized.obj", _shapenet_wedge())
    loaded = load_mesh_directory(tmp_path)
    assert [n for n, _ in loaded] == ["02958343/a1", "02958343/b2", "02958343/c3"]
    assert all(np.allclose(m.bounds, [[-0.5] * 3, [0.5] * 3]) for _, m in loaded)
    with pytest.raises(ValueError, match="not a directory"):
        load_mesh_directory(tmp_path / "missing")


# -- MeshBank ---------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def bank() -> MeshBank:
    return MeshBank.templates()


def test_bank_shapes_and_padding(bank: MeshBank, templates: dict[str, trimesh.Trimesh]) -> None:
    m = len(TEMPLATE_NAMES)
    vmax = max(len(t.vertices) for t in templates.values())
    fmax = max(len(t.faces) for t in templates.values())
    assert bank.names == list(TEMPLATE_NAMES)
    assert bank.verts.shape == (m, vmax, 3) and bank.verts.dtype == torch.float32
    assert bank.faces.shape == (m, fmax, 3) and bank.faces.dtype == torch.long
    assert bank.ffd_basis.shape == (m, vmax, 64)
    assert bank.face_mask.shape == (m, fmax) and bank.face_mask.dtype == torch.bool
    for i, name in enumerate(TEMPLATE_NAMES):
        nv, nf = int(bank.num_verts[i]), int(bank.num_faces[i])
        assert (nv, nf) == (len(templates[name].vertices), len(templates[name].faces))
        np.testing.assert_allclose(bank.verts[i, :nv].numpy(), templates[name].vertices, atol=1e-7)
        assert torch.all(bank.verts[i, nv:] == 0) and torch.all(bank.faces[i, nf:] == 0)
        assert bank.face_mask[i].sum() == nf and bool(bank.face_mask[i, :nf].all())
    assert bank.face_mask.sum() < bank.face_mask.numel()  # some template is actually padded


def test_bank_padded_faces_are_degenerate(bank: MeshBank) -> None:
    tri = torch.gather(bank.verts[:, None].expand(-1, bank.faces.shape[1], -1, -1), 2,
                       bank.faces[..., None].expand(-1, -1, -1, 3))
    area = torch.linalg.cross(tri[:, :, 1] - tri[:, :, 0], tri[:, :, 2] - tri[:, :, 0]).norm(dim=-1)
    assert torch.all(area[~bank.face_mask] == 0)
    assert torch.all(area[bank.face_mask] > 0)  # templates have no degenerate real faces


def test_bank_ffd_basis(bank: MeshBank) -> None:
    i = TEMPLATE_NAMES.index("suv")
    nv = int(bank.num_verts[i])
    torch.testing.assert_close(bank.ffd_basis[i, :nv], bernstein_basis(bank.verts[i, :nv]))
    assert torch.all(bank.ffd_basis[i, nv:] == 0)
    # Identity field keeps vertices; a uniform shift moves real vertices and leaves padding at zero.
    ids = torch.tensor([i, i])
    phi = torch.zeros(2, 64, 3)
    phi[1, :, 1] = 0.1
    out = ffd_deform(bank.verts[ids], phi, bank.ffd_basis[ids])
    torch.testing.assert_close(out[0], bank.verts[i])
    torch.testing.assert_close(out[1, :nv, 1], bank.verts[i, :nv, 1] + 0.1)
    assert torch.all(out[1, nv:] == 0)


def test_bank_gather(bank: MeshBank) -> None:
    ids = torch.tensor([3, 0, 7, 3])
    verts, faces = bank.gather(ids)
    assert verts.shape == (4, *bank.verts.shape[1:]) and faces.shape == (4, *bank.faces.shape[1:])
    for row, i in enumerate(ids.tolist()):
        assert torch.equal(verts[row], bank.verts[i]) and torch.equal(faces[row], bank.faces[i])
    with pytest.raises(ValueError, match="mesh_ids must lie in"):
        bank.gather(torch.tensor([0, 8]))
    with pytest.raises(ValueError, match="1-D integer"):
        bank.gather(torch.tensor([0.0]))


def test_bank_to_trimesh_round_trip(bank: MeshBank, templates: dict[str, trimesh.Trimesh]) -> None:
    i = TEMPLATE_NAMES.index("van")
    mesh = bank.to_trimesh(i)
    assert mesh.is_watertight and len(mesh.faces) == len(templates["van"].faces)
    np.testing.assert_array_equal(mesh.faces, templates["van"].faces)
    moved = bank.verts[i] * 2.0  # padded (Vmax, 3) input, e.g. a deformed mesh
    np.testing.assert_allclose(bank.to_trimesh(i, moved).bounds, [[-1.0] * 3, [1.0] * 3], atol=1e-6)
    assert bank.to(torch.device("cpu")) is bank and bank.device.type == "cpu"
    assert bank.index("van") == i


def test_bank_from_directory_and_validation(tmp_path: Path) -> None:
    for model in ("m2", "m1"):
        _write_obj(tmp_path / "cars" / model / "models" / "model_normalized.obj", _shapenet_wedge())
    bank = MeshBank.from_directory(tmp_path)
    assert bank.names == ["cars/m1", "cars/m2"] and bank.verts.shape[0] == 2
    with pytest.raises(ValueError, match="no files"):
        MeshBank.from_directory(tmp_path / "cars" / "m1" / "models", pattern="*.ply")
    with pytest.raises(ValueError, match="unique"):
        MeshBank.from_trimeshes([build_template("bus")] * 2, ["a", "a"])
    with pytest.raises(ValueError, match="one entry per mesh"):
        MeshBank.from_trimeshes([build_template("bus")], ["a", "b"])


def _bank_arrays(bank: MeshBank) -> list[torch.Tensor]:
    return [bank.verts, bank.faces, bank.num_verts, bank.num_faces, bank.face_parts, bank.ffd_basis]


def test_simplified_bank_is_kept_on_disk_and_read_back_to_the_bit(tmp_path: Path, monkeypatch) -> None:
    """``MeshBank.simplified`` keeps its clustering in ``$SDN3D_MESHES_CACHE`` (0.06 CPU s of every fitting
    process, issue 40): a fresh bank reads the file back instead of clustering, and gets the bank the clustering
    makes, every array equal to the bit; another ``max_faces`` or a bank of other vertices has its own file; a
    damaged file is computed and written again."""
    import sdn3d.meshes.shapenet as shapenet

    monkeypatch.setenv("SDN3D_MESHES_CACHE", str(tmp_path))
    clustered: list[int] = []
    cluster = shapenet.cluster_simplify

    def counted(*args, **kwargs):
        clustered.append(1)
        return cluster(*args, **kwargs)

    monkeypatch.setattr(shapenet, "cluster_simplify", counted)
    computed = MeshBank.templates().simplified(300)
    files = sorted(tmp_path.glob("simplified_*.npz"))
    assert len(files) == 1 and len(clustered) == 8
    read = MeshBank.templates().simplified(300)  # a new bank: nothing kept in memory
    assert len(clustered) == 8  # read back, not clustered
    assert all(torch.equal(a, b) for a, b in zip(_bank_arrays(read), _bank_arrays(computed), strict=True))
    assert read.names == computed.names
    MeshBank.templates().simplified(400)
    assert len(clustered) == 16 and len(list(tmp_path.glob("simplified_*.npz"))) == 2
    moved = MeshBank.templates()
    moved.verts[0, 0, 0] += 0.01  # other arrays: another file, clustered anew
    moved.simplified(300)
    assert len(clustered) == 24 and len(list(tmp_path.glob("simplified_*.npz"))) == 3
    files[0].write_bytes(b"not a bank")
    again = MeshBank.templates().simplified(300)
    assert len(clustered) == 32
    assert all(torch.equal(a, b) for a, b in zip(_bank_arrays(again), _bank_arrays(computed), strict=True))
    assert MeshBank.templates().simplified(300) is not None and len(clustered) == 32  # the file was written again


def test_simplified_bank_without_a_writable_cache_is_computed_each_time(tmp_path: Path, monkeypatch) -> None:
    """A file where the cache folder would be, or modules whose source cannot be read (no key): the bank is computed,
    the same, and nothing is written."""
    import sdn3d.meshes.bank as bank_module

    blocked = tmp_path / "file"
    blocked.write_text("a file where the folder would be")
    monkeypatch.setenv("SDN3D_MESHES_CACHE", str(blocked / "meshes"))
    bank = MeshBank.templates().simplified(300)
    assert int(bank.num_faces.max()) <= 300 and not (blocked / "meshes").exists()

    def unreadable(*args):
        raise OSError("no source")

    monkeypatch.setenv("SDN3D_MESHES_CACHE", str(tmp_path / "meshes"))
    monkeypatch.setattr(bank_module, "_simplified_key", unreadable)
    again = MeshBank.templates().simplified(300)
    assert all(torch.equal(a, b) for a, b in zip(_bank_arrays(again), _bank_arrays(bank), strict=True))
    assert not (tmp_path / "meshes").exists()
