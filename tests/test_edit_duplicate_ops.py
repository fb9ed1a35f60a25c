"""Issue 42: ops on an op's product. A duplicate's copy can be edited by the later ops of the same spec, stands clear
of the other cars in 3D, and keeps the original's look (a recolour before the duplicate included)."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.editing.apply import DUPLICATE_GAP, Duplicate, EditError, SetCode, _floor, _overlap, apply_edits
from sdn3d.editing.photo.recolor import paints
from sdn3d.editing.spec import parse_edit_spec, resolve_ops
from sdn3d.math3d.camera import Intrinsics, project_points
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.textural.code_bank import named_color

INTR = Intrinsics(100.0, 100.0, 99.5, 29.5, width=200, height=60)
ALONG = math.pi / 2  # the car's length along the camera's z: it drives away from the camera, down the road


def _scene(zs=(12.0,), x=0.0) -> SceneCode:
    cars = [SceneObject(12001 + k, template_id=0, dims=(4.0, 1.5, 1.8), ry=ALONG, location=(x, 1.6, z))
            for k, z in enumerate(zs)]
    return SceneCode(INTR, torch.zeros(60, 200, dtype=torch.long), "vkitti",
                     ObjectTable.from_objects(cars, 60, 200), background_codes={})


def _pixel(scene: SceneCode, x: float, z: float) -> list[float]:
    centre = torch.tensor([[x, 1.6 - 0.75, z]], dtype=torch.float64)
    return [round(float(c), 2) for c in project_points(centre, INTR.matrix(torch.float64))[0]]


def test_later_ops_name_the_copy_a_duplicate_made():
    scene = _scene()
    spec = parse_edit_spec([{"op": "duplicate", "id": 12001, "to": _pixel(scene, 3.0, 12.0)},
                            {"op": "rotate", "id": 12002, "ry_deg": 30},
                            {"op": "recolor", "id": 12002, "color": "red"},
                            {"op": "duplicate", "id": 12002, "to": _pixel(scene, -3.0, 12.0)},
                            {"op": "move", "id": 12003, "to": _pixel(scene, -3.0, 20.0)}])
    ops = resolve_ops(spec, scene)  # before issue 42: "op 1 (rotate id=12002): no object with id 12002"
    assert [op.new_id for op in ops if isinstance(op, Duplicate)] == [12002, 12003]
    edited = apply_edits(scene, ops)
    assert edited.objects.instance_id.tolist() == [12001, 12002, 12003]
    row = edited.objects.index_of(12002)
    assert float(edited.objects.ry[row]) == pytest.approx(math.remainder(ALONG + math.radians(30), 2 * math.pi))
    assert paints(ops) == {12002: named_color("red"), 12003: named_color("red")}  # the copy of the red copy is red


def test_an_op_on_a_deleted_object_says_which_op_deleted_it():
    spec = parse_edit_spec([{"op": "delete", "id": 12001}, {"op": "rotate", "id": 12001, "ry_deg": 5}])
    with pytest.raises(EditError, match=r"op 1 \(rotate id=12001\): no object with id 12001; op 0 \(delete "
                                        r"id=12001\) deleted it \(the scene has \[\]\)"):
        resolve_ops(spec, _scene())


def test_a_recolour_before_the_duplicate_is_carried_over_to_the_copy():
    scene = _scene()
    spec = parse_edit_spec([{"op": "recolor", "id": 12001, "color": "blue"},
                            {"op": "duplicate", "id": 12001, "to": _pixel(scene, 3.0, 12.0)}])
    ops = resolve_ops(spec, scene)
    assert paints(ops) == {12001: named_color("blue"), 12002: named_color("blue")}
    assert isinstance(ops[-1], SetCode) and ops[-1].instance_id == 12002


def test_a_copy_placed_on_its_original_is_pushed_along_the_road_until_it_clears():
    scene = _scene()
    to = _pixel(scene, 0.5, 13.0)  # half a metre beside, one metre behind: the two cars would overlap
    [dup] = resolve_ops(parse_edit_spec([{"op": "duplicate", "id": 12001, "to": to}]), scene)
    assert dup.uv != pytest.approx(tuple(to))
    edited = apply_edits(scene, [dup])
    o = edited.objects
    a, b = (_floor(o.location[k], o.dims[k], o.ry[k], DUPLICATE_GAP * 0.99) for k in range(2))
    assert not _overlap(a, b)
    assert float(o.location[1, 2]) > 12.0 + 4.0  # pushed backwards (away from the original, along the road)
    assert float(o.location[1, 0]) == pytest.approx(0.5, abs=1e-2)  # on its own lane line (`to` is rounded)
    # A copy placed clear of every car stays where it was asked to go.
    far = _pixel(scene, 3.0, 12.0)
    [dup] = resolve_ops(parse_edit_spec([{"op": "duplicate", "id": 12001, "to": far}]), scene)
    assert dup.uv == pytest.approx(tuple(far))


def test_a_copy_with_no_clear_place_in_the_picture_is_refused():
    scene = _scene(zs=[6.0 + 4.2 * k for k in range(12)])  # a queue of cars, bumper to bumper
    spec = parse_edit_spec([{"op": "duplicate", "id": 12003, "to": _pixel(scene, 0.0, 14.4)}])
    with pytest.raises(EditError, match=r"op 0 \(duplicate id=12003\): the copy at \[.*\] would overlap object "
                                        r"120\d\d in 3D, and no place along the road .* give another 'to'"):
        resolve_ops(spec, scene)


def test_a_copy_sent_above_the_horizon_is_refused_naming_the_op():
    """Found by the property test: the copy's landing point is checked like a move's, and the error names the op."""
    spec = parse_edit_spec([{"op": "duplicate", "id": 12001, "to": [0.0, 0.0]}])
    with pytest.raises(EditError, match=r"^op 0 \(duplicate id=12001\): .*never meets the object's ground plane"):
        resolve_ops(spec, _scene())
