"""Vehicle parts (issue 41 item 1): every face of every lofted vehicle carries a Part label from the loft, the
labels sit where the part is, follow the faces through the bank, its simplified copy, the FFD and the glTF export."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import trimesh

from sdn3d.export import PARTS_KEY, export_gltf
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.math3d.ffd import ffd_deform
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.parts import PART_NAMES, Part
from sdn3d.meshes.templates import (
    TEMPLATE_NAMES,
    TEMPLATE_SPECS,
    loft_vehicle,
    loft_vehicle_parts,
    template_arrays,
    template_parts,
)
from sdn3d.meshes.vehicle_family import FAMILY, canonical_belt, family_arrays, family_parts
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject

SHAPES = [(n, TEMPLATE_SPECS[n]) for n in TEMPLATE_NAMES] + [(s.name, s.spec) for s in FAMILY]


@pytest.mark.parametrize(("name", "spec"), SHAPES, ids=[n for n, _ in SHAPES])
def test_every_face_has_a_part_where_the_part_is(name, spec):
    verts, faces, parts = loft_vehicle_parts(spec)
    v0, f0 = loft_vehicle(spec)
    assert np.array_equal(verts, v0) and np.array_equal(faces, f0)  # labels only: the mesh is the same
    assert parts.shape == (len(faces),) and parts.dtype == np.int64
    assert set(np.unique(parts).tolist()) == {int(p) for p in Part}  # every part on every vehicle
    tri = verts[faces]  # (F, 3, 3) canonical: +x front, +y down
    centre = tri.mean(1)
    # Glass: the greenhouse, above the belt line (y is down: every vertex at or above it).
    glass = parts == Part.GLASS
    assert tri[glass][..., 1].max() <= canonical_belt(spec) + 1e-9
    assert glass.sum() >= 40
    # Tyres: every vertex of a tyre face within the wheel radius of one of the four wheel centres (in metres).
    extent = np.array([spec.length + 2 * spec.round, max(h for _, h in spec.top), spec.width])
    metres = tri[parts == Part.TYRE] * extent
    half_w = 0.5 * spec.width
    wheel_x = [(a - 0.5) * spec.length for a in spec.axles]
    centres = np.array([[x, 0.5 * extent[1] - spec.wheel_radius, z] for x in wheel_x for z in (-1.0, 1.0)])
    dist = np.linalg.norm((metres[..., None, :2] - centres[:, :2]), axis=-1).min(-1)  # in the wheel plane
    assert dist.max() <= spec.wheel_radius + 1e-6 and (parts == Part.TYRE).sum() == 4 * 48
    assert np.abs(metres[..., 2]).max() <= half_w + 1e-6
    # Lights and plates on the end panels: head lights and grille at the front (+x), tail lights at the rear.
    assert centre[parts == Part.FRONT_LIGHTS, 0].min() > 0.45
    assert centre[parts == Part.TAIL_LIGHTS, 0].max() < -0.45
    plate = centre[parts == Part.PLATE]
    assert (plate[:, 0] > 0.45).sum() == 2 and (plate[:, 0] < -0.45).sum() == 2
    assert np.abs(plate[:, 2]).max() < 0.3 and plate[:, 1].min() > 0.0  # centred, in the lower half
    # Mirror-symmetric across z = 0, like the mesh: each part covers as many faces on either side.
    left, right = centre[:, 2] > 1e-9, centre[:, 2] < -1e-9
    assert np.array_equal(np.bincount(parts[left], minlength=6), np.bincount(parts[right], minlength=6))


def test_public_arrays_and_bank_carry_the_labels():
    for name in TEMPLATE_NAMES:
        assert len(template_parts(name)) == len(template_arrays(name)[1])
    for shape in FAMILY[:3]:
        assert len(family_parts(shape.name)) == len(family_arrays(shape.name)[1])
    with pytest.raises(ValueError, match="name must be one of"):
        template_parts("tank")
    bank = MeshBank.vehicle_shapes()
    assert bank.face_parts.shape == bank.faces.shape[:2]
    for i, name in enumerate(bank.names):
        nf = int(bank.num_faces[i])
        expected = template_parts(name) if i < len(TEMPLATE_NAMES) else family_parts(name)
        assert torch.equal(bank.face_parts[i, :nf], torch.from_numpy(expected))
        assert bool((bank.face_parts[i, nf:] == -1).all())
    # A bank built without labels: every real face BODY.
    v, f = template_arrays("sedan")
    plain = MeshBank.from_arrays([v], [f], ["sedan"])
    assert bool((plain.face_parts == Part.BODY).all())
    with pytest.raises(ValueError, match="parts of mesh"):
        MeshBank.from_arrays([v], [f], ["sedan"], [np.zeros(3, dtype=np.int64)])


def test_simplified_bank_keeps_the_labels_of_the_faces_it_keeps():
    bank = MeshBank.templates()
    coarse = bank.simplified(450)
    for i in range(len(bank)):
        nf = int(coarse.num_faces[i])
        labels = coarse.face_parts[i, :nf]
        assert bool((labels >= 0).all()) and bool((coarse.face_parts[i, nf:] == -1).all())
        # Each kept face's label is the label of an original face whose vertices clustered onto it: tyre faces of
        # the coarse mesh lie low, where the wheels are (y down: below the body's middle).
        v = coarse.verts[i][coarse.faces[i, :nf]]
        tyre = labels == Part.TYRE
        assert bool(tyre.any()) and float(v[tyre][..., 1].mean()) > 0.2
        assert bool((labels == Part.GLASS).any())


def test_ffd_moves_vertices_faces_keep_their_parts():
    bank = MeshBank.templates()
    ids = torch.arange(len(bank))
    verts, faces = bank.gather(ids)
    phi = 0.05 * torch.randn(len(bank), 64, 3, generator=torch.Generator().manual_seed(0))
    deformed = ffd_deform(verts, phi, bank.ffd_basis[ids])
    assert not torch.allclose(deformed, verts)
    # Labels index faces; the deformation leaves faces, hence labels, as they were. The glass is still the part
    # of the car above its belt: its mean height stays above the tyres' after the deformation.
    parts = bank.face_parts[ids]
    for i in range(len(bank)):
        nf = int(bank.num_faces[i])
        tri = deformed[i][faces[i, :nf]]
        p = parts[i, :nf]
        assert float(tri[p == Part.GLASS][..., 1].mean()) < float(tri[p == Part.TYRE][..., 1].mean())


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_export_writes_the_parts_of_the_deformed_meshes(tmp_path, suffix):
    w, h = 96, 32
    car = VKITTI_CLASS_INDEX["Car"]
    phi = 0.03 * torch.randn(64, 3, generator=torch.Generator().manual_seed(1))
    objects = [SceneObject(car * 1000 + 1, 1, (4.0, 1.5, 1.8), 0.4, (-1.0, 1.6, 9.0), phi=phi),
               SceneObject(car * 1000 + 2, 7, (9.0, 3.0, 2.5), 2.0, (4.0, 1.7, 25.0))]
    scene = SceneCode(VKITTI_INTRINSICS.resized(w, h), torch.zeros(h, w, dtype=torch.long), "vkitti",
                      ObjectTable.from_objects(objects, h, w), torch.zeros(14, 5))
    loaded = trimesh.load(export_gltf(scene, tmp_path / f"scene{suffix}"), process=False)
    for iid, template in ((12001, "hatchback"), (12002, "bus")):
        mesh = loaded.geometry[f"instance_{iid}"]
        stored = mesh.metadata[PARTS_KEY]
        assert stored["names"] == list(PART_NAMES)
        assert np.array_equal(stored["faces"], template_parts(template))
        assert len(stored["faces"]) == len(mesh.faces)
    assert PARTS_KEY not in loaded.geometry["ground"].metadata
