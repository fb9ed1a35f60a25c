"""The one picking rule (:mod:`sdn3d.editing.pick`) as the benchmark (:func:`ops_from_benchmark`) and ``sdn3d-edit``
(:func:`resolve_ops`) use it: the mask under the point first, one object per operation, a mask-only object refused
for an edit that needs geometry."""

import pytest
import torch

from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import Delete, EditError, Modify, ops_from_benchmark
from sdn3d.editing.spec import parse_edit_spec, resolve_ops
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import compose_instances

SIZE = (208, 64)


@pytest.fixture(scope="module")
def scene(tmp_path_factory) -> SceneCode:
    """A synthetic frame's ground-truth scene (8-10 cars, masks and geometry)."""
    cfg = SynthConfig(output_dir=str(tmp_path_factory.mktemp("synth") / "data"), seed=3, image_size=SIZE,
                      frames_per_sequence=2, cars_per_frame=(8, 10), edit_pairs=0)
    return scene_from_frame({r.frame: r for r in read_frames(generate_dataset(cfg))}[1])


def _biggest(scene: SceneCode, count: int) -> list[int]:
    """Instance ids of the ``count`` objects with the most visible pixels."""
    area = (compose_instances(scene)[None] == scene.objects.instance_id[:, None, None]).flatten(1).sum(1)
    return [int(scene.objects.instance_id[i]) for i in torch.argsort(area, descending=True)[:count]]


def _front_pixel(scene: SceneCode, iid: int) -> tuple[float, float]:
    """``(u, v)`` of the pixel of ``iid`` in the composed instance map nearest its visible pixels' centroid."""
    ys, xs = (compose_instances(scene) == iid).nonzero(as_tuple=True)
    pts = torch.stack([xs, ys], 1).double()
    k = int((pts - pts.mean(0)).norm(dim=1).argmin())
    return float(pts[k, 0]), float(pts[k, 1])


def _centre_pick(scene: SceneCode, uv: tuple[float, float]) -> int:
    """The object whose projected centre is nearest ``uv`` (the old benchmark rule)."""
    obj = scene.objects
    centre = obj.center
    proj = torch.stack([centre[:, 0] / centre[:, 2] * scene.intrinsics.fx + scene.intrinsics.cx,
                        centre[:, 1] / centre[:, 2] * scene.intrinsics.fy + scene.intrinsics.cy], 1)
    return int(obj.instance_id[int((proj - torch.tensor(uv, dtype=proj.dtype)).norm(dim=1).argmin())])


def _with_locations(scene: SceneCode, moves: dict[int, torch.Tensor]) -> SceneCode:
    location = scene.objects.location.clone()
    for iid, where in moves.items():
        location[scene.objects.index_of(iid)] = where
    return scene.replace(objects=scene.objects.replace(location=location))


def test_a_car_fitted_elsewhere_is_picked_by_its_mask(scene):
    """Issue 40: a car whose 3D fit projects its centre far from where it shows (here: put on the other side of the
    road, farther) is picked by a point on its mask, not the object whose centre is nearest the point."""
    car = _biggest(scene, 1)[0]
    where = scene.objects.location[scene.objects.index_of(car)].clone()
    fitted = _with_locations(scene, {car: torch.stack([-where[0] - 4.0, where[1], where[2] + 15.0])})
    point = _front_pixel(fitted, car)
    assert _centre_pick(fitted, point) != car  # the old rule's pick
    (op,) = ops_from_benchmark([BenchmarkOperation.modify(point, None, 1.0, 0.5)], fitted, frame_size=None)
    assert isinstance(op, Modify) and op.instance_id == car
    (op,) = resolve_ops(parse_edit_spec([{"op": "rotate", "at": list(point), "ry_deg": 30}]), fitted)
    assert op.instance_id == car


def test_two_picks_never_share_an_object_and_each_keeps_its_mask(scene):
    """Two cars whose fits are swapped: each point picks the car under it (the centres would swap the picks); two
    points on one car take two different objects."""
    a, b = _biggest(scene, 2)
    loc = scene.objects.location
    swapped = _with_locations(scene, {a: loc[scene.objects.index_of(b)], b: loc[scene.objects.index_of(a)]})
    pa, pb = _front_pixel(swapped, a), _front_pixel(swapped, b)
    assert _centre_pick(swapped, pa) != a or _centre_pick(swapped, pb) != b  # the old rule's picks
    ops = ops_from_benchmark([BenchmarkOperation.delete(pa), BenchmarkOperation.delete(pb)], swapped,
                             frame_size=None)
    assert [op.instance_id for op in ops] == [a, b]
    ops = ops_from_benchmark([BenchmarkOperation.delete(pa)] * 2, swapped, frame_size=None)
    assert ops[0].instance_id != ops[1].instance_id and a in {op.instance_id for op in ops}


def test_a_mask_only_object_under_a_modify_is_passed_over_or_named(scene):
    """The front object under a modify's point has a mask only: the pick goes on to an object with geometry (the
    benchmark scores every entry), and where none holds the point or is within reach the refusal names the mask-only
    object; a user's ``at`` point there is refused at once, naming it; a delete there takes it."""
    car = _biggest(scene, 1)[0]
    row = scene.objects.index_of(car)
    template = scene.objects.template_id.clone()
    template[row] = -1
    flat = scene.replace(objects=scene.objects.replace(template_id=template))
    point = _front_pixel(flat, car)
    (op,) = ops_from_benchmark([BenchmarkOperation.modify(point, None, 1.0, 0.5)], flat, frame_size=None)
    assert op.instance_id != car and bool(flat.objects.has_geometry[flat.objects.index_of(op.instance_id)])
    assert ops_from_benchmark([BenchmarkOperation.delete(point)], flat, frame_size=None) == [Delete(car)]
    alone = flat.replace(objects=flat.objects.select(torch.tensor([row])))
    message = rf"lands on object {car}, which has no 3D geometry, only its mask of {int(flat.objects.mask[row].sum())} "
    with pytest.raises(EditError, match=message):
        ops_from_benchmark([BenchmarkOperation.modify(point, None, 1.0, 0.5)], alone, frame_size=None)
    with pytest.raises(EditError, match=rf"op 0 \(rotate at=.*\): the edit at .* {message}"):
        resolve_ops(parse_edit_spec([{"op": "rotate", "at": list(point), "ry_deg": 30}]), alone)
    # A user's point is refused at once, whatever else is in reach: turning another car than the one pointed at
    # would surprise; the refusal names the objects with geometry nearest the point.
    with pytest.raises(EditError, match=rf"op 0 \(rotate at=.*\): the edit at .* {message}.*moved, turned or "
                                        r"zoomed; the nearest objects with geometry: \d+"):
        resolve_ops(parse_edit_spec([{"op": "rotate", "at": list(point), "ry_deg": 30}]), flat, pick_radius=None)
    (op,) = resolve_ops(parse_edit_spec([{"op": "modify", "from": list(point), "ry_deg": 30}]), flat, pick_radius=None)
    assert op.instance_id != car  # a spec's benchmark op passes over it, as the benchmark does


def test_a_listed_centre_picks_its_object_even_behind_another(scene):
    """A point on an object's projected centre (the listing's centre pasted, or a synthetic benchmark ``from``
    point) picks it even where a car in front shows there; a point a little off it picks the car in front."""
    front, behind = _biggest(scene, 2)
    u, v = _front_pixel(scene, front)
    intr = scene.intrinsics
    row = scene.objects.index_of(behind)
    depth = float(scene.objects.location[scene.objects.index_of(front), 2]) + 10.0
    half = float(scene.objects.location[row, 1] - scene.objects.center[row, 1])  # location is the bottom centre
    lands = u + 0.8  # its centre projects 0.8 px off the point, within the snap (1.4 px at 208 wide)
    centre = torch.tensor([(lands - intr.cx) / intr.fx * depth, (v - intr.cy) / intr.fy * depth, depth],
                          dtype=torch.float64)
    hidden = _with_locations(scene, {behind: centre + torch.tensor([0.0, half, 0.0], dtype=torch.float64)})
    assert int(compose_instances(hidden)[round(v), round(u)]) == front
    (op,) = ops_from_benchmark([BenchmarkOperation.delete((u, v))], hidden, frame_size=None)
    assert op.instance_id == behind
    off = next((u + du, v) for du in (-6.0, 6.0, -8.0, 8.0)
               if 0 <= round(u + du) < SIZE[0] and int(compose_instances(hidden)[round(v), round(u + du)]) == front)
    (op,) = ops_from_benchmark([BenchmarkOperation.delete(off)], hidden, frame_size=None)
    assert op.instance_id == front
