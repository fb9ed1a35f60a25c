"""The 2D and 2D+ baselines: translate / scale / squeeze visible regions in the label maps."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.editing.pick import projected_centers
from sdn3d.evaluation.baselines import baseline_maps, warp_regions
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.scene.maps import scene_maps

W, H = 128, 48
ROAD, SKY = VKITTI_CLASS_INDEX["Road"], VKITTI_CLASS_INDEX["Sky"]
CAR = VKITTI_CLASS_INDEX["Car"]


def _box(top: int, left: int, bottom: int, right: int) -> torch.Tensor:
    mask = torch.zeros(H, W, dtype=torch.bool)
    mask[top:bottom, left:right] = True
    return mask


@pytest.fixture(scope="module")
def scene() -> SceneCode:
    """An observed car (mask = its rendered silhouette, labelled Car in the semantic map) and two
    mask-only cars, each with its own code."""
    semantic = torch.full((H, W), ROAD, dtype=torch.long)
    semantic[: H // 2] = SKY
    intr = VKITTI_INTRINSICS.resized(W, H)
    car = SceneObject(CAR * 1000 + 1, 0, (4.0, 1.5, 1.8), 0.5, (0.0, 1.65, 10.0), code=torch.full((5,), 1.0))
    probe = SceneCode(intr, semantic, "vkitti", ObjectTable.from_objects([car], H, W), torch.zeros(14, 5))
    silhouette = scene_maps(probe).instance == car.instance_id
    objects = [
        SceneObject(car.instance_id, 0, car.dims, car.ry, car.location, code=car.code, mask=silhouette),
        SceneObject(CAR * 1000 + 2, -1, mask=_box(26, 90, 31, 100), code=torch.full((5,), 2.0)),
        SceneObject(CAR * 1000 + 3, -1, mask=_box(30, 100, 41, 116), code=torch.full((5,), 3.0)),
    ]
    table = ObjectTable.from_objects(objects, H, W)
    semantic = torch.where(table.mask.any(0), CAR, semantic)
    return SceneCode(intr, semantic, "vkitti", table, torch.arange(70, dtype=torch.float32).reshape(14, 5))


def _at(scene: SceneCode, iid: int) -> tuple[float, float]:
    uv, _ = projected_centers(scene)
    return tuple(uv[scene.objects.index_of(iid)].tolist())


@pytest.mark.parametrize("mode", ["2d", "2d+"])
def test_identity_edit_reproduces_the_scene_maps(scene, mode):
    ops = [BenchmarkOperation.modify(_at(scene, i), _at(scene, i), 1.0, 0.0) for i in (12001, 12003)]
    maps = baseline_maps(scene, ops, mode=mode, frame_size=None)
    ref = scene_maps(scene)
    for key in ("instance", "label", "instance_label_map", "boundary", "normal", "pose", "depth", "feature"):
        assert torch.equal(getattr(maps, key), getattr(ref, key)), key


def test_translation_moves_the_region_and_its_maps(scene):
    ref = scene_maps(scene)
    src = _at(scene, 12001)
    du, dv = -20, 3
    maps = baseline_maps(scene, [BenchmarkOperation.modify(src, (src[0] + du, src[1] + dv), 1.0, 1.2)], frame_size=None)
    old = ref.instance == 12001
    new = maps.instance == 12001
    shifted = torch.zeros_like(old)
    shifted[dv:, : W + du] = old[: H - dv, -du:]
    assert torch.equal(new, shifted) and new.sum() == old.sum()
    # Rotation is ignored by '2d'; normals, pose and codes travel with the region.
    assert torch.equal(maps.normal[:, new], ref.normal[:, old]) and torch.equal(maps.pose[:, new], ref.pose[:, old])
    assert torch.allclose(maps.feature[:, new], torch.ones(5, 1))
    freed = old & ~new
    assert bool((maps.instance[freed] == 0).all()) and not bool((maps.label[freed] == CAR).any())


def _extent(mask: torch.Tensor) -> tuple[int, int]:
    rows, cols = mask.nonzero(as_tuple=True)
    return int(rows.max() - rows.min() + 1), int(cols.max() - cols.min() + 1)


def test_zoom_scales_and_2d_plus_squeezes_the_width(scene):
    src = _at(scene, 12003)
    # The car is deleted so that nothing occludes the scaled region.
    ops = [BenchmarkOperation.modify(src, (60.0, 30.0), 2.0, math.pi / 3), BenchmarkOperation.delete(_at(scene, 12001))]
    plain = baseline_maps(scene, ops, mode="2d", frame_size=None).instance == 12003
    plus = baseline_maps(scene, ops, mode="2d+", frame_size=None).instance == 12003
    h0, w0 = _extent(scene.objects.mask[2])
    assert _extent(plain) == (2 * h0, 2 * w0)
    assert _extent(plus) == (2 * h0, w0)  # |cos(pi / 3)| = 1/2
    assert plain.sum() == 4 * scene.objects.mask[2].sum() and plus.sum() == 2 * scene.objects.mask[2].sum()
    # The anchor maps to the target: the box centre (the mask centroid) lands on (60, 30).
    rows, cols = plain.nonzero(as_tuple=True)
    assert abs(float(cols.float().mean()) - 60.0) <= 0.5 and abs(float(rows.float().mean()) - 30.0) <= 0.5


def test_occlusion_uses_the_lowest_row(scene):
    src = _at(scene, 12002)  # region rows 26..30, cols 90..99; object 12003 spans rows 30..40, cols 100..115
    below = baseline_maps(scene, [BenchmarkOperation.modify(src, (src[0] + 12, src[1] + 12), 1.0, 0.0)],
                          frame_size=None)
    above = baseline_maps(scene, [BenchmarkOperation.modify(src, (src[0] + 5, src[1] + 5), 1.0, 0.0)], frame_size=None)
    assert (below.instance == 12002).sum() == 50  # rows 38..42, lowest 42 > 40: in front, fully visible
    # rows 31..35, cols 95..104: lowest row 35 < 40, so cols 100..104 are behind 12003.
    assert (above.instance == 12002).sum() == 25 and (above.instance[31:36, 95:100] == 12002).all()
    assert (above.instance == 12003).sum() == scene.objects.mask[2].sum()


def test_delete_and_empty_geometry(scene):
    ops = [BenchmarkOperation.delete(_at(scene, 12001)),
           BenchmarkOperation.modify(_at(scene, 12002), (40.0, 35.0), 1.5, 0.0)]
    maps = baseline_maps(scene, ops, mode="2d+", frame_size=None, geometry="empty")
    assert not bool((maps.instance == 12001).any()) and bool((maps.instance == 12002).any())
    assert maps.normal.abs().sum() == 0 and maps.pose.sum() == 0 and maps.depth.abs().sum() == 0
    assert not bool(((maps.label == CAR) & (maps.instance == 0)).any())
    with pytest.raises(ValueError, match="mode"):
        baseline_maps(scene, ops, mode="3d", frame_size=None)
    with pytest.raises(ValueError, match="geometry"):
        baseline_maps(scene, ops, frame_size=None, geometry="keep")


def test_warp_regions_inverse_sampling():
    regions = _box(2, 2, 4, 5)[None]
    values = torch.arange(H * W, dtype=torch.float32).reshape(1, H, W)
    src = torch.tensor([[3.0, 2.5]], dtype=torch.float64)
    hit, sampled = warp_regions(regions, values, src, src + 10, torch.tensor([[1.0, 1.0]], dtype=torch.float64))
    assert torch.equal(hit[0], regions[0].roll((10, 10), (0, 1)))
    assert torch.equal(sampled[0, 0][hit[0]], values[0][regions[0]])
