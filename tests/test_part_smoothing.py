"""Gouraud interpolation of the part lookup's colours (issue 41, "sides the photo never showed"): a turned car's
never-seen side was drawn from examples looked up by one normal per coarse template face, so each face took its own
colour and the side showed stair-step facets. ``photo.part_smoothing`` keeps that lookup but makes each face corner
stand for the lookup at the pixel's point averaged over the normals of the vertex's smoothing fan
(``transfer._corner_groups``), and mixes a pixel's three corners by its barycentrics."""

from __future__ import annotations

import dataclasses
import math

import pytest
import torch
import torch.nn.functional as F

from sdn3d.editing.apply import apply_edits
from sdn3d.editing.ops import Rotate
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.settings import MIRROR, PART, PHOTO, PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import (
    _bank_belts,
    _corner_groups,
    _corner_part_colors,
    _fan_labels,
    _rasterize,
    _surface,
    _surface_points,
    render_photo,
)
from sdn3d.meshes.bank import default_bank
from sdn3d.meshes.parts import Part, greenhouse_glass
from sdn3d.scene.code import SceneObject
from sdn3d.scene.maps import posed_meshes
from tests.test_photo import FRAME, INPUT_SIZE, _k_input, _scene

pytestmark = pytest.mark.usefixtures("one_torch_thread")


def _arch(segments: int = 8, depth: float = 6.0) -> tuple[torch.Tensor, torch.Tensor]:
    """``(verts (V, 3), faces (F, 3))``: a half cylinder of radius 1 (axis along y, bulging towards the camera at
    ``depth``) cut in ``segments`` strips of two triangles each, faces wound alike: a coarsely tessellated curved
    panel, each strip's normal ``180 / segments`` degrees from its neighbour's."""
    angle = torch.linspace(0, math.pi, segments + 1, dtype=torch.float64)
    ring = torch.stack([-angle.cos(), torch.zeros_like(angle), depth - angle.sin()], 1)
    verts = torch.cat([ring + torch.tensor([0.0, -1.0, 0.0], dtype=torch.float64),
                       ring + torch.tensor([0.0, 1.0, 0.0], dtype=torch.float64)])
    n = segments + 1
    faces = torch.tensor([f for i in range(segments) for f in ((i, i + 1, n + i + 1), (i, n + i + 1, n + i))])
    return verts, faces


def _unit(verts: torch.Tensor, faces: torch.Tensor) -> torch.Tensor:
    tri = verts[faces]
    return F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)


def test_corner_groups_join_a_smooth_panel_and_keep_creases_and_part_edges():
    verts, faces = _arch(8)  # neighbouring strips 22.5 degrees apart
    unit = _unit(verts, faces)
    body = torch.zeros(len(faces), dtype=torch.long)
    group = _corner_groups(faces, unit, body, 45.0)
    flat = group.reshape(-1)
    vertex = faces.reshape(-1)
    for v in range(len(verts)):  # every vertex's corners in one fan: the panel is smooth at 45 degrees
        assert len(flat[vertex == v].unique()) == 1
    # a crease below the strips' angle: a vertex between two strips has two fans, one per strip
    sharp = _corner_groups(faces, unit, body, 10.0).reshape(-1)
    assert len(sharp[vertex == 4].unique()) == 2
    # a part edge (strips 0-3 one part, 4-7 another) splits the fans at the vertex they share, not elsewhere
    parts = (torch.arange(len(faces)) >= 8).long()
    split = _corner_groups(faces, unit, parts, 45.0).reshape(-1)
    assert len(split[vertex == 4].unique()) == 2 and len(split[vertex == 3].unique()) == 1
    # a unit cube's edges (90 degrees) stay sharp: a corner vertex has a fan per side; padding faces join none
    cube = torch.tensor([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)], dtype=torch.float64)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = torch.tensor([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))] + [(0, 0, 0)] * 2)
    box = _corner_groups(tris, torch.nan_to_num(_unit(cube, tris)), torch.zeros(len(tris), dtype=torch.long), 45.0)
    assert len(box[:12].reshape(-1)[tris[:12].reshape(-1) == 0].unique()) == 3
    assert not torch.isin(box[12:], box[:12]).any()


def _arch_pixels(crease: float, labels: torch.Tensor | None = None, by_part: bool = False):
    """The arch rasterized, its middle row's pixels: ``(face normal colours, Gouraud colours, face normals, parts)``
    with a lookup whose colour is the normal it is given (as main's part lookup, one colour per face normal), or with
    ``by_part`` the part's own grey."""
    verts, faces = _arch(8, depth=4.0)
    size = (60, 400)
    K = torch.tensor([[200.0, 0.0, 200.0], [0.0, 200.0, 30.0], [0.0, 0.0, 1.0]], dtype=torch.float64)
    raster = _rasterize(torch.zeros(1, dtype=torch.long), verts[None], faces[None], K, size)
    row = torch.arange(size[1]) + 30 * size[1]
    pix = row[torch.isin(row, raster.frags.covered())]
    _, _, bary, normal, _, point = _surface_points(raster, pix)
    face = raster.frags.face_at(raster.frags.locate(pix))
    labels = torch.zeros(len(faces), dtype=torch.long) if labels is None else labels
    parts = labels[face]

    def lookup(points, normals, q_parts, points_t):
        color = q_parts.double()[:, None].expand(-1, 3) / 4 + 0.2 if by_part else normals.abs()
        return color, torch.full((len(points),), PART, dtype=torch.long)

    own, rules = lookup(pix, normal, parts, pix)
    smooth = _corner_part_colors(lookup, face, point, point, parts, rules, own, bary, normal, faces, verts, labels,
                                 crease)
    return own, smooth, normal, parts


def test_corner_colours_run_on_over_a_tessellated_panel():
    """A lookup that steps from face to face (one colour per face normal) is drawn without a step at the face edges:
    its corners agree across each edge; each face keeps its own colour on average."""
    flat, smooth, normal, _ = _arch_pixels(45.0)
    squarely = normal[:-1, 2].abs() > 0.5  # away from the silhouette, where a pixel spans a wide turn of the surface
    flat_steps = flat.diff(dim=0).abs().amax(1)[squarely]
    smooth_steps = smooth.diff(dim=0).abs().amax(1)[squarely]
    assert float(flat_steps.max()) > 0.1  # a face edge: a visible step
    assert float(smooth_steps.max()) < 0.25 * float(flat_steps.max())
    assert float((smooth - flat).abs().mean()) < 0.1  # the same colours, spread across the edges
    # a crease below the strips' angle keeps each strip's own colour: the steps stay
    flat10, sharp, _, _ = _arch_pixels(10.0)
    assert torch.allclose(sharp, flat10, atol=1e-9)


def test_the_pixels_own_face_is_not_looked_up_again():
    """Each pixel's own face stands for the lookup the caller made (``own``, ``rules``): the corner lookup asks only
    the other faces of its corners' fans, and the colours are those of asking every face (the lookup before), bit for
    bit, with a lookup whose rows are each their own."""
    verts, faces = _arch(8, depth=4.0)
    size = (60, 400)
    K = torch.tensor([[200.0, 0.0, 200.0], [0.0, 200.0, 30.0], [0.0, 0.0, 1.0]], dtype=torch.float64)
    raster = _rasterize(torch.zeros(1, dtype=torch.long), verts[None], faces[None], K, size)
    pix = raster.frags.covered()
    _, _, bary, normal, _, point = _surface_points(raster, pix)
    face = raster.frags.face_at(raster.frags.locate(pix))
    labels = torch.zeros(len(faces), dtype=torch.long)
    asked = []

    def lookup(points, normals, q_parts, points_t):  # a colour from the point and the normal; a rule from the height
        asked.append(normals)
        color = (normals.abs() * 0.7 + points.remainder(0.37) * 0.8).clamp(0, 1)
        return color, (points[:, 1] > 0).long()

    own, rules = lookup(point, normal, labels[face], point)
    asked.clear()
    got = _corner_part_colors(lookup, face, point, point, labels[face], rules, own, bary, normal, faces, verts, labels,
                              45.0)
    # every fan face asked, the pixel's own too: the formulation before
    group = _corner_groups(faces, _unit(verts, faces), labels, 45.0)
    fans = transfer._members(group.reshape(-1))[group[face]]  # (P, 3, D)
    every = [set((fans[p][fans[p] >= 0] // 3).tolist()) for p in range(len(face))]
    assert sum(len(a) for a in asked) == sum(len(e) - 1 for e in every)  # the own face never asked again
    side = torch.where((_unit(verts, faces)[face] * normal).sum(1) < 0, -1.0, 1.0)
    some = torch.arange(0, len(face), 23)
    want = torch.zeros(len(face), 3, dtype=torch.float64)
    for p in some.tolist():
        total = 0.0
        for k in range(3):
            members = fans[p, k][fans[p, k] >= 0] // 3
            for f in members.tolist():
                n = side[p] * _unit(verts, faces)[f]
                c, r = lookup(point[p:p + 1], n[None], labels[face][p:p + 1], point[p:p + 1])
                w = float(bary[p, k]) / len(members) * float(r[0] == rules[p])
                want[p] += w * c[0]
                total += w
        want[p] = want[p] / total if total > 0 else own[p]
    assert torch.allclose(got[some], want[some], atol=1e-12)


def test_part_boundaries_stay_sharp():
    """Strips 0-3 and 4-7 of different parts: their colours (each part's own) meet in a step, unsmoothed."""
    labels = (torch.arange(16) >= 8).long() * int(Part.TYRE)
    flat, smooth, _, parts = _arch_pixels(45.0, labels, by_part=True)
    assert torch.allclose(smooth, flat, atol=1e-12)
    edge = (parts[1:] != parts[:-1]).nonzero().flatten()
    assert len(edge) == 1 and float((smooth[edge + 1] - smooth[edge]).abs().max()) > 0.4


def _face_steps(result, scene_after) -> tuple[float, float]:
    """Mean |dRGB| between horizontally or vertically neighbouring never-seen body pixels (code part) of one smooth
    panel (faces within 40 degrees), across a face edge and within one face."""
    size = INPUT_SIZE[::-1]
    rows, verts, faces = posed_meshes(scene_after.objects, default_bank())
    raster = _rasterize(rows, verts, faces, _k_input(), size)
    pix = raster.frags.covered()
    _, _, _, normal = _surface(raster, pix)
    face = torch.full((size[0] * size[1],), -1, dtype=torch.long)
    face[pix] = raster.frags.face_at(raster.frags.locate(pix))
    nmap = torch.zeros(size[0] * size[1], 3, dtype=torch.float64)
    nmap[pix] = normal
    ok = ((result.source == PART) & (result.parts == int(Part.BODY))).reshape(-1)
    img = result.image.double().permute(1, 2, 0).reshape(-1, 3)
    across, within = [], []
    for step in (1, size[1]):
        a = torch.arange(size[0] * size[1] - step)
        b = a + step
        keep = ok[a] & ok[b] & ((nmap[a] * nmap[b]).sum(1) >= math.cos(math.radians(40)))
        if step == 1:
            keep &= (a % size[1]) != size[1] - 1
        d = (img[a] - img[b]).abs().mean(1)[keep]
        same = (face[a] == face[b])[keep]
        across.append(d[~same])
        within.append(d[same])
    return float(torch.cat(across).mean()), float(torch.cat(within).mean())


def _turned_car(**change) -> tuple:
    """A car whose paint is shaded smoothly across the picture (a real car's curved panels in a real light), seen from
    the rear three-quarter and turned so that its never-seen side faces the camera: ``(result, edited scene)``."""
    car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=-math.pi / 2 + 0.5, location=(-1.0, 1.6, 12.0))
    scene = _scene([car])
    h, w = INPUT_SIZE[::-1]
    y, x = torch.meshgrid(torch.linspace(0, 1, h), torch.linspace(0, 1, w), indexing="ij")
    light = 0.25 + 0.6 * (1 - y) * (0.6 + 0.4 * torch.cos(3 * x))
    image = light[None] * torch.tensor([0.9, 0.2, 0.15])[:, None, None]
    edited = apply_edits(scene, [Rotate(12001, 1.3)])
    settings = dataclasses.replace(PhotoSettings(relight=False, contact_shadow=0.0, fill="telea"), **change)
    return render_photo(image, FRAME, scene, edited, settings=settings), edited


def test_a_turned_cars_never_seen_side_steps_less_at_face_edges():
    assert PhotoSettings().part_smoothing
    ratios = []
    for smooth in (True, False):
        result, edited = _turned_car(part_smoothing=smooth)
        across, within = _face_steps(result, edited)
        ratios.append(across / within)
    assert ratios[1] > 2.0 and ratios[0] < 0.6 * ratios[1], ratios


def test_off_draws_each_pixels_own_lookup(monkeypatch):
    """``part_smoothing=False`` never reaches the corner lookup (main's picture: each pixel its own lookup), and the
    default changes only never-seen pixels drawn from examples."""
    on, _ = _turned_car()

    def fail(*args, **kwargs):
        raise AssertionError("the corner lookup ran with part_smoothing off")

    monkeypatch.setattr(transfer, "_corner_part_colors", fail)
    off, _ = _turned_car(part_smoothing=False)
    assert torch.equal(on.source, off.source)
    changed = (on.image != off.image).any(0)
    assert changed[on.source == PART].any()
    assert not changed[(on.source == PHOTO) | (on.source == MIRROR)].any()  # what the input showed: as it was


def test_part_smoothing_settings_are_checked():
    assert PhotoSettings().part_smoothing_crease_deg == 35.0
    with pytest.raises(PhotoSettingsError, match="part_smoothing"):
        PhotoSettings(part_smoothing=1)
    for bad in (0.0, 181.0, True):
        with pytest.raises(PhotoSettingsError, match="part_smoothing_crease_deg"):
            PhotoSettings(part_smoothing_crease_deg=bad)


def _greenhouse_side(bank, template: int) -> torch.Tensor:
    """``(F,)`` long per face of ``template``: 1 where its centroid is glass (its loft label, or a body point above
    the belt line told glass, ``_greenhouse_glass``'s rule), 0 where it is any other part's, -1 where the belt line
    crosses the face (its corners on both sides)."""
    parts = bank.face_parts[template].long()
    tri = bank.verts[template][bank.faces[template].long()].double()
    unit = torch.nan_to_num(F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1),
                                        dim=-1))
    belt = float(_bank_belts(bank)[template])
    told = greenhouse_glass(parts, tri[..., 1].mean(1), -unit[:, 1], belt)
    side = ((parts == int(Part.GLASS)) | told).long()
    corner = greenhouse_glass(parts[:, None], tri[..., 1], -unit[:, 1:2], belt)
    far = (tri[..., 1] - belt).abs() > 1e-6
    side[(corner & far).any(1) & (~corner & far).any(1)] = -1
    return side


def test_glass_and_body_never_share_a_corner():
    """A vertex on the belt line: the body faces below it and the greenhouse's glass faces above it (loft glass, or body
    faces told glass per point) are never one fan, so no corner mixes the body's lookup with the window's normals (the
    window band faded into the paint with no crisp belt line, session30/gouraud30/); a face the belt line crosses
    joins no fan. The window band's loft glass and told-glass faces still smooth together, and the labels before
    (glass and body one label) mixed them."""
    bank = default_bank()
    mixed_before = joined = 0
    for template in range(len(bank.names)):
        faces = bank.faces[template].long()
        tri = bank.verts[template][faces].double()
        unit = torch.nan_to_num(F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1),
                                            dim=-1))
        side = _greenhouse_side(bank, template)
        labels = _fan_labels(bank, template, len(faces))
        group = _corner_groups(faces, unit, labels, 35.0)
        face_of = torch.arange(len(faces))[:, None].expand(-1, 3)
        for g in group.unique():
            members = face_of[group == g].unique()
            sides = side[members].unique()
            assert len(sides) == 1, (bank.names[template], sides)  # one side of the belt line
            if int(sides[0]) == -1:
                assert len(members) == 1  # a face the belt line crosses: its own
        loft = bank.face_parts[template].long()
        window = [face_of[group == g].unique() for g in group.unique()]
        joined += any(bool((loft[m] == int(Part.GLASS)).any() and (loft[m] == int(Part.BODY)).any()) for m in window
                      if bool((side[m] == 1).all()))  # told glass smooths with loft glass
        before = torch.where(loft == int(Part.GLASS), int(Part.BODY), loft)  # session 29's labels
        old = _corner_groups(faces, unit, before, 35.0)
        mixed_before += sum(len(side[face_of[old == g].unique()].unique()) > 1 for g in old.unique())
    assert mixed_before > 0 and joined >= len(bank.names) - 1, (mixed_before, joined)  # the bus: none adjacent


def test_each_faces_table_holds_its_corners_fan_faces_once_with_how_often_each_corner_has_them():
    """``transfer._corner_fan_faces``: two faces whose corner groups ``(0, 0, 2)`` and ``(0, 4, 5)`` make group 0's
    fan of face 0 twice (two of its corners) and face 1 once. Each face's table lists the faces of its three corners'
    fans once, ascending; ``times`` how often each is a member of each corner's fan; ``sizes`` each fan's size."""
    table, times, sizes = transfer._corner_fan_faces(torch.tensor([[0, 0, 2], [0, 4, 5]]))
    assert table.tolist() == [[0, 1], [0, 1]]
    assert times.tolist() == [[[2, 2, 1], [1, 1, 0]], [[2, 0, 0], [1, 1, 1]]]
    assert sizes.tolist() == [[3, 3, 1], [3, 1, 1]]
