"""The 2D baselines' removal takes 3D-SDN's 2D parts (issue 40, session 22): the pieces of a removed car its mask
missed (:func:`~sdn3d.editing.photo.fill.leftover_pieces`) and the rays from the road's vanishing point found from the
picture's edges around it (:func:`~sdn3d.editing.photo.road.removal_vanishing_point`), through the one shared
:func:`~sdn3d.editing.photo.fill.removal_guides`; without 3D they fall back on the camera's forward vanishing point."""

from __future__ import annotations

import pytest
import torch

from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.editing.photo.fill import removal_guides, vacated_hole
from sdn3d.editing.photo.road import PictureLab
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.baselines import baseline_photo, baseline_photos
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import Intrinsics
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from tests.test_photo_deletes import ROAD_K, _perspective_road
from tests.test_photo_leftovers import _street

pytestmark = pytest.mark.usefixtures("one_torch_thread")

ROAD, CAR = VKITTI_CLASS_INDEX["Road"], VKITTI_CLASS_INDEX["Car"]


def _mask_scene(masks: dict[int, torch.Tensor], K: torch.Tensor) -> SceneCode:
    """Mask-only cars (``{instance id: (H, W) mask}``) on road, the camera ``K (3, 3)``."""
    height, width = next(iter(masks.values())).shape
    intr = Intrinsics(float(K[0, 0]), float(K[1, 1]), float(K[0, 2]), float(K[1, 2]), width, height)
    objects = [SceneObject(iid, -1, mask=m, code=torch.full((5,), float(k)))
               for k, (iid, m) in enumerate(masks.items())]
    table = ObjectTable.from_objects(objects, height, width)
    semantic = torch.where(table.mask.any(0), CAR, torch.full((height, width), ROAD, dtype=torch.long))
    return SceneCode(intr, semantic, "vkitti", table, torch.zeros(14, 5))


def _centre(mask: torch.Tensor) -> tuple[float, float]:
    ys, xs = mask.nonzero(as_tuple=True)
    return float(xs.float().mean()), float(ys.float().mean())


def test_a_baseline_delete_fills_the_mirror_its_mask_missed():
    """The red car's mirror juts 6 pixels out of its mask; deleting the car, the 2D baseline now fills what of the
    mirror its hole missed (main left a red fleck there), and the car that stays keeps its pixels."""
    image, ids, parts = _street()
    car, other = CAR * 1000 + 7, CAR * 1000 + 9
    scene = _mask_scene({car: ids == 7, other: ids == 9}, torch.tensor([[90.0, 0, 79.5], [0, 90.0, 20.0], [0, 0, 1]]))
    out = baseline_photo(image, scene, [BenchmarkOperation.delete(_centre(ids == 7))], frame_size=None)
    tip = parts["mirror"] & ~vacated_hole(torch.where(ids == 7, car, torch.where(ids == 9, other, 0)),
                                          torch.tensor([car]), ids == 9, PhotoSettings())
    assert bool(tip.any())  # the masks' hole alone leaves the mirror's tip
    red = (out[0] - out[1:].mean(0)) > 0.3  # (H, W) red-looking pixels
    assert not bool(red[tip].any())
    assert torch.equal(out[:, ids == 9], image[:, ids == 9])
    # Modes share the removal; without a ray fill no vanishing point is looked for, the leftovers still are.
    both = baseline_photos(image, scene, [BenchmarkOperation.delete(_centre(ids == 7))], frame_size=None)
    assert torch.equal(both["2d"], out) and torch.equal(both["2d+"], out)
    telea = baseline_photo(image, scene, [BenchmarkOperation.delete(_centre(ids == 7))], frame_size=None,
                           settings=PhotoSettings(fill="telea"))
    assert not bool(((telea[0] - telea[1:].mean(0)) > 0.3)[tip].any())


def test_a_baseline_delete_runs_the_rays_from_the_roads_vanishing_point():
    """The road runs 30 degrees right of the camera's forward heading; a car (a dark box) covers a lane line. The 2D
    baseline's rays now run from the vanishing point voted by the edges around the car, so the lane line runs on
    through the hole as in the picture without the car; from the picture's centre (main) they crossed it."""
    clean = _perspective_road(30.0)
    mask = torch.zeros(192, 624, dtype=torch.bool)
    mask[118:150, 400:470] = True
    image = torch.where(mask[None], torch.tensor([0.12, 0.1, 0.1])[:, None, None], clean)
    scene = _mask_scene({CAR * 1000 + 1: mask}, ROAD_K)
    guides = removal_guides(image, ROAD_K.double(), PictureLab(image), mask, torch.where(mask, CAR * 1000 + 1, 0),
                            torch.tensor([CAR * 1000 + 1]), torch.zeros_like(mask), PhotoSettings())
    u, v = guides.vanishing
    assert v == pytest.approx(95.5) and u == pytest.approx(311.5 + 364.0 * 0.57735, abs=3.0)  # tan 30 degrees
    out = baseline_photo(image, scene, [BenchmarkOperation.delete(_centre(mask))], frame_size=None)
    line = mask & (clean.mean(0) > 0.8)  # the lane line's pixels the car hid
    assert int(line.sum()) > 50
    assert float(out[:, line].mean()) > 0.75  # the line runs on (the road around it is 0.42)
    assert float((out - clean).abs()[:, mask].mean()) < 0.05


def test_without_edges_the_baseline_falls_back_on_the_cameras_forward_vanishing_point():
    """A flat grey picture has no edges to vote: the rays run from the camera's forward direction (``K``'s principal
    point), not from a fitted yaw (the baselines have none) nor the picture's centre."""
    image = torch.full((3, 96, 160), 0.4)
    ids = torch.zeros(96, 160, dtype=torch.long)
    ids[40:70, 20:60] = CAR * 1000 + 1
    K = torch.tensor([[90.0, 0.0, 30.0], [0.0, 90.0, 20.0], [0.0, 0.0, 1.0]], dtype=torch.float64)
    guides = removal_guides(image, K, PictureLab(image), ids != 0, ids, torch.tensor([CAR * 1000 + 1]), ids == -1,
                            PhotoSettings())
    assert guides.vanishing == pytest.approx((30.0, 20.0))
    assert not bool(guides.leftovers.any())
    assert removal_guides(image, K, PictureLab(image), ids != 0, ids, torch.tensor([CAR * 1000 + 1]), ids == -1,
                          PhotoSettings(fill="telea")).vanishing is None
