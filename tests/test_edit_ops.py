"""3D-aware edit operations: geometry round trips, freed pixels, errors, benchmark conversion."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

from sdn3d.data.edit_benchmark import BenchmarkEntry, BenchmarkOperation, load_edit_benchmark, scale_point
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME, SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import (
    Delete,
    Duplicate,
    EditError,
    Modify,
    ModifyAnchor,
    Move,
    Rotate,
    SetBackgroundCode,
    SetCode,
    Zoom,
    apply_edits,
    ops_from_benchmark,
)
from sdn3d.editing.pick import PickBy, pick_objects, projected_centers
from sdn3d.reference.editing import apply_edits_dense
from sdn3d.resources import paper_example_path
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.scene.maps import compose_instances, scene_maps

SIZE = (208, 64)


@pytest.fixture(scope="module")
def synth(tmp_path_factory):
    """A tiny synthetic dataset (2 frames, 2 edit pairs) and its records by frame."""
    cfg = SynthConfig(output_dir=str(tmp_path_factory.mktemp("synth") / "data"), seed=3, image_size=SIZE,
                      frames_per_sequence=2, cars_per_frame=(8, 10), edit_pairs=2)
    root = generate_dataset(cfg)
    return root, {r.frame: r for r in read_frames(root)}


@pytest.fixture(scope="module")
def scene(synth) -> SceneCode:
    return scene_from_frame(synth[1][1])


def _big(scene: SceneCode) -> int:
    """Instance id of the most visible object."""
    return int(scene.objects.instance_id[scene.objects.mask.flatten(1).sum(1).argmax()])


def _uv(scene: SceneCode, iid: int) -> torch.Tensor:
    uv, _ = projected_centers(scene)
    return uv[scene.objects.index_of(iid)]


def test_move_projects_to_target_and_keeps_ground(scene):
    iid = _big(scene)
    i = scene.objects.index_of(iid)
    target = (150.25, 45.5)
    out = apply_edits(scene, [Move(iid, target)])
    j = out.objects.index_of(iid)
    assert torch.allclose(_uv(out, iid), torch.tensor(target, dtype=torch.float64), atol=1e-9)
    assert float(out.objects.location[j, 1]) == pytest.approx(float(scene.objects.location[i, 1]), abs=1e-12)
    assert float(out.objects.ry[j]) == float(scene.objects.ry[i])
    # The moved object is drawn from geometry at its new place; its old pixels became background.
    assert not bool(out.objects.has_mask[j]) and not bool(out.objects.observed[j])
    old = scene.objects.mask[i]
    assert not bool(torch.isin(out.semantic[old], scene.thing_classes).any())
    maps = scene_maps(out)
    assert (maps.instance == iid).sum() > 0
    assert int(maps.instance[round(target[1]), round(target[0])]) == iid


def test_zoom_divides_distance(scene):
    iid = _big(scene)
    i = scene.objects.index_of(iid)
    c0 = scene.objects.center[i]
    ray = apply_edits(scene, [Zoom(iid, 1.25)])
    c1 = ray.objects.center[ray.objects.index_of(iid)]
    assert float(c1.norm()) == pytest.approx(float(c0.norm()) / 1.25, rel=1e-12)
    assert torch.allclose(_uv(ray, iid), _uv(scene, iid), atol=1e-9)
    ground = apply_edits(scene, [Zoom(iid, 0.8, on_ground=True)])
    c2 = ground.objects.center[ground.objects.index_of(iid)]
    assert float(c2.norm()) == pytest.approx(float(c0.norm()) / 0.8, rel=1e-12)
    assert float(c2[1]) == pytest.approx(float(c0[1]), abs=1e-12)
    assert float(_uv(ground, iid)[0]) == pytest.approx(float(_uv(scene, iid)[0]), abs=1e-9)


def test_rotate_by_two_pi_is_identity_and_other_angles_wrap(scene):
    iid = _big(scene)
    assert apply_edits(scene, [Rotate(iid, 2 * math.pi)]) == scene
    assert apply_edits(scene, [Rotate(iid, 0.7), Rotate(iid, -0.7)]) == scene
    assert apply_edits(scene, [Modify(iid, None, 1.0, 0.0)]) == scene
    out = apply_edits(scene, [Rotate(iid, 3.0), Rotate(iid, 3.0)])
    ry = out.objects.ry[out.objects.index_of(iid)]
    expected = math.remainder(float(scene.objects.ry[scene.objects.index_of(iid)]) + 6.0, 2 * math.pi)
    assert -math.pi <= float(ry) < math.pi and float(ry) == pytest.approx(expected, abs=1e-12)


def test_delete_removes_every_pixel_and_fills_background(scene):
    iid = _big(scene)
    before = scene_maps(scene)
    out = apply_edits(scene, [Delete(iid)])
    maps = scene_maps(out)
    assert len(out.objects) == len(scene.objects) - 1
    assert not bool((maps.instance == iid).any()) and not bool((maps.instance_label_map == iid).any())
    # No orphan object-class pixels: every thing-class label belongs to a drawn instance.
    things = torch.isin(maps.label, scene.thing_classes)
    assert not bool((things & (maps.instance == 0)).any())
    freed = before.instance == iid
    assert bool((maps.instance[freed] == 0).any()) and torch.equal(maps.label[~freed & (maps.instance == 0)],
                                                                   before.label[~freed & (maps.instance == 0)])


def _occluded_pair(scene: SceneCode) -> tuple[int, int, torch.Tensor]:
    """(front id, behind id, pixels of the front object's mask where the one behind renders) with the most
    such pixels."""
    obj = scene.objects
    alone = obj.replace(mask=torch.zeros_like(obj.mask), has_mask=torch.zeros_like(obj.has_mask))
    best = (0, 0, torch.zeros(0))
    for row in range(len(obj)):  # each object's silhouette alone: what it would cover unoccluded
        sil = compose_instances(scene.replace(objects=alone.select(torch.tensor([row])))) != 0
        for front in range(len(obj)):
            if front != row and float(obj.center[front, 2]) < float(obj.center[row, 2]):
                hidden = sil & obj.mask[front] & ~obj.mask[row]
                if int(hidden.sum()) > int(best[2].sum()):
                    best = (int(obj.instance_id[front]), int(obj.instance_id[row]), hidden)
    return best


def test_occluded_car_comes_back_when_its_occluder_leaves(scene):
    """Amodal completion: deleting (or moving) the car in front re-draws the hidden part of the car behind it
    from its geometry instead of turning it into road."""
    front, behind, hidden = _occluded_pair(scene)
    assert int(hidden.sum()) >= 20, "the fixture scene needs an occluded car"
    before = scene_maps(scene)
    assert not bool((before.instance[hidden] == behind).any())
    for op in (Delete(front), Move(front, (5.0, 60.0))):
        after = scene_maps(apply_edits(scene, [op]))
        uncovered = hidden & (after.instance != front)  # a moved car may still cover some of them
        assert float((after.instance[uncovered] == behind).float().mean()) > 0.9, op
        # the car behind keeps its own visible pixels
        assert bool((after.instance[before.instance == behind] == behind).all())
        # without amodal completion (an editor without 3D: the 2D baselines) the hidden part becomes background
        flat = scene_maps(apply_edits(scene, [op], amodal=False))
        assert not bool((flat.instance[uncovered] == behind).any()), op
        assert torch.equal(flat.instance[before.instance == behind], after.instance[before.instance == behind])


def test_baselines_do_not_complete_the_car_behind(scene):
    """The 2D / 2D+ baselines have no 3D: deleting the car in front leaves road where the car behind was hidden
    (3D-SDN completes it), so the occluder-removed benchmark entries tell them apart."""
    from sdn3d.data.edit_benchmark import BenchmarkOperation
    from sdn3d.evaluation.baselines import baseline_maps

    front, behind, hidden = _occluded_pair(scene)
    uv, _ = projected_centers(scene)
    at = tuple(uv[scene.objects.index_of(front)].tolist())
    three_d = scene_maps(apply_edits(scene, [Delete(front)]))
    for mode in ("2d", "2d+"):
        flat = baseline_maps(scene, [BenchmarkOperation.delete(at)], mode=mode, frame_size=None)
        assert not bool((flat.instance == front).any())
        assert not bool((flat.instance[hidden] == behind).any()), mode
    assert float((three_d.instance[hidden] == behind).float().mean()) > 0.9


def test_edits_are_pure(scene):
    copy = scene.replace(semantic=scene.semantic.clone(), objects=ObjectTable(
        **{k: v.clone() for k, v in scene.objects.__dict__.items()}))
    iid = _big(scene)
    apply_edits(scene, [Move(iid, (100.0, 50.0)), SetCode(iid, [1, 2, 3, 4, 5]), Delete(iid),
                        SetBackgroundCode(5, [0.1] * 5)])
    assert copy == scene


def test_codes_and_duplicate(scene):
    iid = _big(scene)
    out = apply_edits(scene, [SetCode(iid, [1, 2, 3, 4, 5]), SetBackgroundCode(5, [9, 9, 9, 9, 9]),
                              Duplicate(iid, (60.0, 50.0))])
    i = out.objects.index_of(iid)
    assert out.objects.code[i].tolist() == [1, 2, 3, 4, 5] and out.background_codes[5].tolist() == [9.0] * 5
    cls = iid // 1000
    new_id = cls * 1000 + int((scene.objects.instance_id[scene.objects.class_id == cls] % 1000).max()) + 1
    j = out.objects.index_of(new_id)
    assert torch.equal(out.objects.code[j], out.objects.code[i]) and not bool(out.objects.observed[j])
    assert torch.allclose(_uv(out, new_id), torch.tensor([60.0, 50.0], dtype=torch.float64), atol=1e-9)
    assert torch.equal(out.objects.location[i], scene.objects.location[scene.objects.index_of(iid)])
    maps = scene_maps(out)
    dup = maps.instance == new_id
    assert bool(dup.any()) and torch.allclose(maps.feature[:, dup], torch.tensor([1.0, 2, 3, 4, 5])[:, None])
    road = (maps.instance_label_map == 5)
    assert torch.allclose(maps.feature[:, road], torch.full((5, 1), 9.0))


def test_errors(scene):
    iid = _big(scene)
    with pytest.raises(EditError, match="no object"):
        apply_edits(scene, [Rotate(99001, 1.0)])
    with pytest.raises(EditError, match="outside"):
        apply_edits(scene, [Move(iid, (SIZE[0] + 3.0, 40.0))])
    with pytest.raises(EditError, match="horizon"):
        apply_edits(scene, [Move(iid, (100.0, 2.0))])
    for bad in (lambda: Zoom(iid, 0.0), lambda: Zoom(iid, -1.0), lambda: Move(iid, (float("nan"), 3.0)),
                lambda: Rotate(iid, float("inf")), lambda: Modify(iid, (1.0, 2.0), zoom=float("nan"))):
        with pytest.raises(EditError):
            bad()
    with pytest.raises(EditError, match="code has"):
        apply_edits(scene, [SetCode(iid, [1.0, 2.0])])
    with pytest.raises(EditError, match="new id"):
        apply_edits(scene, [Duplicate(iid, (60.0, 50.0), new_id=iid)])
    assert issubclass(EditError, ValueError)
    mask = torch.zeros(SIZE[1], SIZE[0], dtype=torch.bool)
    mask[40:45, 10:20] = True
    flat = scene.replace(objects=ObjectTable.from_objects([SceneObject(12001, mask=mask)], SIZE[1], SIZE[0]))
    with pytest.raises(EditError, match="no 3D geometry"):
        apply_edits(flat, [Move(12001, (50.0, 50.0))])
    assert not bool(apply_edits(flat, [Delete(12001)]).objects.has_mask.any())


def test_extreme_distances_are_refused_saying_why(scene):
    """Issue 20: ``zoom: 1e9`` put the camera inside the car, ``1e-9`` sent it 3e10 m away (both accepted)."""
    from sdn3d.editing.apply import MAX_DISTANCE, MIN_CLEARANCE

    iid = _big(scene)
    i = scene.objects.index_of(iid)
    distance, length = float(scene.objects.center[i].norm()), float(scene.objects.dims[i, 0])
    low = MIN_CLEARANCE + length / 2
    assert (MIN_CLEARANCE, MAX_DISTANCE) == (0.1, 1000.0)  # the rasterizer's default near / far planes
    for op, pattern in [(Zoom(iid, 1e9), "closer than .* near plane .* half its length"),
                        (Zoom(iid, distance / (0.99 * low)), "closer than"),
                        (Modify(iid, None, zoom=1e9), "closer than"),
                        (Zoom(iid, 1e-9), "farther than 1000 m .*far plane"),
                        (Zoom(iid, 1e-9, on_ground=True), "farther than 1000 m"),
                        (Zoom(iid, distance / 1001), "farther than 1000 m"),
                        (Modify(iid, (100.0, 40.0), zoom=1e-9), "farther than"),
                        (Move(iid, (100.0, scene.intrinsics.cy + 1e-3)), "farther than 1000 m .*below the horizon")]:
        with pytest.raises(EditError, match=f"object {iid} would end .*{pattern}"):
            apply_edits(scene, [op])
    # Just inside the bounds is fine, and exact as before.
    for zoom in (distance / (1.01 * low), distance / 999):
        edited = apply_edits(scene, [Zoom(iid, zoom)])
        c = edited.objects.center[edited.objects.index_of(iid)]
        assert float(c.norm()) == pytest.approx(distance / zoom, rel=1e-12)


def test_benchmark_ops_reproduce_the_synthetic_targets(synth):
    root, records = synth
    entries = [e for e in load_edit_benchmark(root / BENCHMARK_NAME) if e.operations]
    assert entries
    for entry in entries:
        source = scene_from_frame(records[entry.source_frame])
        target = scene_from_frame(records[entry.target_frame])
        ops = ops_from_benchmark(entry, source)
        assert [type(o).__name__ for o in ops] == ["Delete" if o.kind == "delete" else "Modify"
                                                    for o in entry.operations]
        edited = apply_edits(source, ops)
        deleted = {o.instance_id for o in ops if isinstance(o, Delete)}
        assert not deleted & set(edited.objects.instance_id.tolist())
        common = [i for i in edited.objects.instance_id.tolist() if i in set(target.objects.instance_id.tolist())]
        assert common
        a = edited.objects.select(torch.tensor([edited.objects.index_of(i) for i in common]))
        b = target.objects.select(torch.tensor([target.objects.index_of(i) for i in common]))
        # ``to`` and ``zoom`` are rounded in the file: a few centimetres at most.
        assert (a.location - b.location).abs().max() < 0.05
        assert (torch.remainder(a.ry - b.ry + math.pi, 2 * math.pi) - math.pi).abs().max() < 1e-5
        agree = (scene_maps(edited).instance == scene_maps(target).instance).float().mean()
        assert agree > 0.98


def test_benchmark_picks_and_frame_checks(scene):
    uv, _ = projected_centers(scene)
    iid = _big(scene)
    i = scene.objects.index_of(iid)
    full = scale_point(tuple(uv[i].tolist()), SIZE, (1242, 375))
    off = BenchmarkOperation.modify(full, (1300.0, 300.0), 1.0, 0.0)
    with pytest.raises(EditError, match="outside"):
        apply_edits(scene, ops_from_benchmark(BenchmarkEntry("0001", "clone", 1, 2, (off,)), scene))
    ops = ops_from_benchmark([off], scene, strict=False)
    assert ops[0].instance_id == iid and not ops[0].check_frame
    apply_edits(scene, ops)  # an off-frame target is accepted when not strict
    # Two picks at the same point take two different objects (one-to-one assignment).
    ids = pick_objects(scene, [tuple(uv[i].tolist())] * 2)
    assert ids[0] != ids[1] and iid in ids
    with pytest.raises(EditError, match=r"no object at \[[\d.]+, [\d.]+\]: no centre is within 1.0 px"):
        pick_objects(scene, [(uv[i, 0].item() + 50, uv[i, 1].item())], max_distance=1.0, by=PickBy.CENTRE)
    empty = scene.replace(objects=ObjectTable.empty(SIZE[1], SIZE[0]))
    with pytest.raises(EditError, match="only 0 objects"):
        ops_from_benchmark([BenchmarkOperation.delete((10.0, 10.0))], empty)


def test_an_object_without_geometry_is_picked_by_edits_that_need_none(scene):
    """A delete takes an object with a mask only (under ``min_pixels``) by its mask centroid; a point off the image
    picks nothing (the refusal of a move on such an object: tests/test_edit_pick.py)."""
    iid = _big(scene)
    i = scene.objects.index_of(iid)
    template = scene.objects.template_id.clone()
    template[i] = -1
    flat = scene.replace(objects=scene.objects.replace(template_id=template))
    uv, valid = projected_centers(flat)
    assert bool(valid[i])
    point = tuple(uv[i].tolist())
    others = valid & flat.objects.has_geometry
    reach = 0.5 * float((uv[others] - uv[i]).norm(dim=1).min())  # no object with geometry within the pick radius
    assert pick_objects(flat, [point], [False], max_distance=reach) == [iid]
    far = (point[0] + 300.0, point[1])  # off the image: no mask, no box, no centre within 1 px
    with pytest.raises(EditError, match="no object at"):
        pick_objects(flat, [far], [True], max_distance=1.0)


def test_published_example_rotates_the_picked_car(tmp_path):
    """The shipped 5-rotation example picks track 0 of the fixture's frame 0006/30-deg-right/00043."""
    write_vkitti1_fixture(tmp_path, world="0006", variation="30-deg-right", frames=(43,), size=(1242, 375))
    scene = scene_from_frame(read_frames(tmp_path)[0], image_size=(624, 192))
    car = scene.objects.index_of(12001)  # track 0 (k = tid + 1)
    for entry in load_edit_benchmark(paper_example_path()):
        (op,) = ops_from_benchmark(entry, scene)
        assert isinstance(op, Modify) and op.instance_id == 12001
        edited = apply_edits(scene, [op])
        turned = float(edited.objects.ry[car] - scene.objects.ry[car])
        assert math.isclose(math.remainder(turned - entry.operations[0].ry, 2 * math.pi), 0.0, abs_tol=1e-9)
        assert torch.equal(edited.objects.location, scene.objects.location)
        assert (edited == scene) == (abs(math.remainder(entry.operations[0].ry, 2 * math.pi)) < 1e-9)


def test_freed_pixels_match_the_reference_and_need_no_rendering_with_masks(scene, monkeypatch):
    """All observed objects have masks: the freed pixels come from the masks alone (no rasterization), and
    equal the reference that composes the observed objects' renders; without masks both render."""
    import sdn3d.editing.apply as module

    order = scene.objects.mask.flatten(1).sum(1).argsort(descending=True).tolist()
    a, b, c = (int(scene.objects.instance_id[i]) for i in order[:3])
    ops = [Delete(a), Move(b, (40.0, 50.0)), Modify(c, (150.0, 48.0), 1.3, 0.4), Rotate(b, 0.3)]
    ref = apply_edits_dense(scene, ops)
    assert bool(scene.objects.has_mask.all()) and not torch.equal(ref.semantic, scene.semantic)

    def no_render(*args, **kwargs):
        raise AssertionError("compose_instances called although every observed object has a mask")

    assert apply_edits(scene, ops) == ref
    vacate = torch.isin(scene.objects.instance_id, torch.tensor([a, b, c]))
    with monkeypatch.context() as patch:
        patch.setattr(module, "compose_instances", no_render)
        module._footprints(scene, vacate, None, 2)
    # Observed objects without masks (their footprint is where their render wins) take the rendering path.
    obj = scene.objects
    drop = torch.isin(obj.instance_id, torch.tensor([a, int(obj.instance_id[order[3]])]))
    unmasked = scene.replace(objects=obj.replace(mask=obj.mask & ~drop[:, None, None], has_mask=obj.has_mask & ~drop))
    calls = []
    with monkeypatch.context() as patch:
        patch.setattr(module, "compose_instances", lambda *a, **k: calls.append(1) or compose_instances(*a, **k))
        out = apply_edits(unmasked, ops)
    assert calls and out == apply_edits_dense(unmasked, ops)


@pytest.mark.parametrize("iterations", [1, 2, 5])
def test_vacated_region_growth_matches_scipy_binary_dilation(iterations):
    """editing.apply grows regions with torch (scipy.ndimage is not imported on the edit path)."""
    from scipy.ndimage import binary_dilation

    from sdn3d.image_ops import dilate_cross

    mask = torch.rand(37, 53, generator=torch.Generator().manual_seed(iterations)) > 0.97
    mask[0, :3] = mask[-1, -1] = True  # borders: nothing grows in from outside the image
    assert np.array_equal(dilate_cross(mask, iterations).numpy(), binary_dilation(mask.numpy(), iterations=iterations))


def test_a_modify_moves_the_point_it_picked_unless_anchored_at_the_centre(scene):
    """``ModifyAnchor.pick``: a de-rendered centre a few pixels off ``from`` keeps that offset (scaled by ``zoom``), so
    the object's pixels move as the 2D baselines paste them; ``centre``: the centre itself goes to ``to``."""
    uv, _ = projected_centers(scene)
    iid = _big(scene)
    i = scene.objects.index_of(iid)
    offset = torch.tensor([3.0, -2.0], dtype=torch.float64)
    pick = tuple((uv[i] + offset).tolist())  # the user's point, a little off the de-rendered centre
    to = (float(uv[i, 0]) + 20.0, float(uv[i, 1]) + 4.0)
    zoom = 1.25
    op = BenchmarkOperation.modify(pick, to, zoom, 0.0)
    for anchor, expected in ((ModifyAnchor.PICK, torch.tensor(to, dtype=torch.float64) - zoom * offset),
                             (ModifyAnchor.CENTRE, torch.tensor(to, dtype=torch.float64))):
        ops = ops_from_benchmark([op], scene, frame_size=None, anchor=anchor)
        assert ops[0].instance_id == iid
        edited = apply_edits(scene, ops)
        moved, _ = projected_centers(edited)
        assert moved[edited.objects.index_of(iid)] == pytest.approx(expected, abs=1e-6)
    with pytest.raises(ValueError):
        ops_from_benchmark([op], scene, frame_size=None, anchor="middle")
