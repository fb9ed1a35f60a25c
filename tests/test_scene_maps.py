"""Composing a SceneCode into the textural generator's inputs."""

from __future__ import annotations

import pytest
import torch

from sdn3d.data import vkitti1
from sdn3d.data.datasets import TexturalDataset
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.math3d.rotations import alpha_bins, observation_angle
from sdn3d.meshes.bank import default_bank
from sdn3d.reference.scene_maps import scene_maps_dense
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.scene.fill import fill_background, scene_code_map
from sdn3d.scene.maps import _projected_boxes, compose_instances, posed_meshes, scene_maps

WORK = (160, 64)
ROAD, SKY, TREE = (VKITTI_CLASS_INDEX[n] for n in ("Road", "Sky", "Tree"))
CAR, VAN = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Van"]
W, H = 128, 48


def _scene(objects: list[SceneObject]) -> SceneCode:
    semantic = torch.full((H, W), ROAD, dtype=torch.long)
    semantic[: H // 2] = SKY
    table = ObjectTable.from_objects(objects, H, W)
    codes = torch.arange(14 * 5, dtype=torch.float32).reshape(14, 5)
    return SceneCode(VKITTI_INTRINSICS.resized(W, H), semantic, "vkitti", table, codes)


NEAR = SceneObject(CAR * 1000 + 1, 0, (4.0, 1.5, 1.8), 0.4, (0.0, 1.65, 9.0), code=torch.full((5,), 1.0))
FAR = SceneObject(VAN * 1000 + 2, 5, (5.0, 2.0, 2.0), -1.0, (0.5, 1.65, 16.0), code=torch.full((5,), 2.0))


@pytest.fixture(scope="module")
def fixture_records(tmp_path_factory):
    root = tmp_path_factory.mktemp("vk1")
    write_vkitti1_fixture(root, frames=(0, 1), size=(310, 94))
    return vkitti1.read_frames(root)


def test_ground_truth_scene_matches_textural_dataset(fixture_records):
    dataset = TexturalDataset(fixture_records, WORK)
    for index, record in enumerate(fixture_records):
        maps = scene_maps(scene_from_frame(record, image_size=WORK))
        item = dataset[index]
        for key in ("instance", "label", "instance_label_map", "boundary", "pose"):
            assert torch.equal(getattr(maps, key), item[key]), key
        # The dataset keeps normals only where the object's own render is frontmost; we keep them
        # wherever the visible object was rendered, a superset that agrees where both exist.
        shown = item["normal"].abs().sum(0) > 0
        assert bool(shown.any()) and torch.allclose(maps.normal[:, shown], item["normal"][:, shown], atol=1e-5)
        assert bool(((maps.normal.abs().sum(0) > 0) <= (maps.instance > 0)).all())


def test_occlusion_follows_depth_not_table_order():
    alone = {o.instance_id: scene_maps(_scene([o])) for o in (NEAR, FAR)}
    both = scene_maps(_scene([FAR, NEAR]))
    swapped = scene_maps(_scene([NEAR, FAR]))
    assert torch.equal(both.instance, swapped.instance) and torch.equal(both.depth, swapped.depth)
    near, far = (alone[o.instance_id].instance == o.instance_id for o in (NEAR, FAR))
    overlap = near & far
    assert overlap.sum() > 20
    assert bool((both.instance[overlap] == NEAR.instance_id).all())
    assert torch.equal(both.instance == FAR.instance_id, far & ~near)
    assert bool((both.depth[0][overlap] < alone[FAR.instance_id].depth[0][overlap]).all())
    assert torch.equal(both.depth[0][near], alone[NEAR.instance_id].depth[0][near])
    # Pose: one-hot of each object's alpha bin over its visible region; normals face the camera.
    for obj, region in ((NEAR, near), (FAR, far & ~near)):
        alpha = observation_angle(torch.tensor(obj.ry), torch.tensor(obj.location[0]), torch.tensor(obj.location[2]))
        assert bool((both.pose[int(alpha_bins(alpha))][region] == 1).all())
    assert bool((both.pose.sum(0) == (both.instance > 0).float()).all())
    assert torch.allclose(both.normal[:, near].norm(dim=0), torch.ones(int(near.sum())), atol=1e-5)
    assert both.normal[2, near].max() <= 0  # camera-facing: negative z component
    assert torch.equal(compose_instances(_scene([FAR, NEAR])), both.instance)


def test_masks_win_over_silhouettes_and_mask_only_objects_lie_behind():
    mask = torch.zeros(H, W, dtype=torch.bool)
    mask[30:40, 40:90] = True
    flat = SceneObject(CAR * 1000 + 9, -1, mask=mask)
    observed = SceneObject(NEAR.instance_id, 0, NEAR.dims, NEAR.ry, NEAR.location, mask=mask.roll(5, 1))
    maps = scene_maps(_scene([flat, FAR]))
    far = scene_maps(_scene([FAR])).instance == FAR.instance_id
    assert torch.equal(maps.instance == flat.instance_id, mask & ~far)
    assert bool((maps.pose[:, mask & ~far] == 0).all()) and bool((maps.depth[0][mask & ~far] == 0).all())
    only = scene_maps(_scene([observed]))
    assert torch.equal(only.instance == NEAR.instance_id, mask.roll(5, 1))


def test_label_map_codes_and_boundaries():
    maps = scene_maps(_scene([NEAR, FAR]))
    car = maps.instance == NEAR.instance_id
    assert bool((maps.label[car] == CAR).all()) and bool((maps.instance_label_map[car] == NEAR.instance_id).all())
    background = maps.instance == 0
    assert torch.equal(maps.instance_label_map[background], maps.label[background])
    assert torch.allclose(maps.feature[:, car], torch.ones(5, 1))
    sky = maps.instance_label_map == SKY
    assert torch.allclose(maps.feature[:, sky], torch.arange(SKY * 5, SKY * 5 + 5, dtype=torch.float32)[:, None])
    assert bool((maps.boundary[0][car] >= 0).all()) and maps.boundary[0][car].sum() > 0
    keys = set(maps.as_dict())
    assert {"instance", "label", "instance_label_map", "boundary", "normal", "pose", "depth"} <= keys


def test_empty_scene_is_the_semantic_map():
    scene = _scene([])
    maps = scene_maps(scene)
    assert torch.equal(maps.label, scene.semantic) and not bool(maps.instance.any())
    assert maps.normal.abs().sum() == 0 and maps.pose.sum() == 0 and maps.pose.shape == (24, H, W)


def test_code_map_handles_unknown_and_ignore():
    lmap = torch.tensor([[12001, 12005, 255], [0, 1, 13000]])
    out = scene_code_map(lmap, torch.tensor([13000, 12001]), torch.tensor([[1.0, 1.0], [2.0, 2.0]]),
                   torch.tensor([[5.0, 5.0], [6.0, 6.0]]))
    assert out[:, 0, 0].tolist() == [2.0, 2.0] and out[:, 1, 2].tolist() == [1.0, 1.0]
    assert out[:, 0, 1].tolist() == [0.0, 0.0] and out[:, 0, 2].tolist() == [0.0, 0.0]
    assert out[:, 1, 0].tolist() == [5.0, 5.0] and out[:, 1, 1].tolist() == [6.0, 6.0]


def test_fill_background_takes_nearest_non_object_labels():
    sem = torch.full((10, 12), ROAD)
    sem[:4] = TREE
    sem[2:8, 3:9] = CAR  # a car spanning tree and road
    sem[5:7, 9:11] = VAN  # a neighbouring van must not leak into the freed region
    vacated = sem == CAR
    out = fill_background(sem, vacated, torch.tensor([CAR, VAN]))
    assert torch.equal(out[~vacated], sem[~vacated])
    assert set(out[vacated].unique().tolist()) == {TREE, ROAD}
    assert bool((out[2:4, 3:9] == TREE).all()) and bool((out[6:8, 3:9] == ROAD).all())
    assert torch.equal(fill_background(sem, torch.zeros_like(vacated), torch.tensor([CAR])), sem)
    with pytest.raises(ValueError, match="must match"):
        fill_background(sem, vacated[:-1], torch.tensor([CAR]))


def _mixed_scene() -> SceneCode:
    """One object of every kind the composition tells apart (module doc), overlapping."""
    box = torch.zeros(H, W, dtype=torch.bool)
    box[30:40, 40:90] = True
    car = CAR * 1000
    return _scene([
        SceneObject(car + 1, 0, NEAR.dims, NEAR.ry, NEAR.location, mask=box.roll(6, 1)),  # mask != silhouette
        FAR,  # drawn from its silhouette
        SceneObject(car + 2, -1, mask=box.roll(-4, 0) & ~box),  # mask only: behind everything with geometry
        SceneObject(car + 3, 2, (4.0, 1.5, 1.8), 0.3, (-5.0, 1.65, 8.0)),  # across the left border
        SceneObject(car + 4, 1, (4.0, 1.5, 1.8), 1.57, (2.0, 1.65, 1.2)),  # vertices behind the near plane
        SceneObject(car + 5, 3, (4.0, 1.5, 1.8), 0.0, (0.0, 1.65, -3.0), mask=box.roll(3, 0)),  # behind the camera
        SceneObject(car + 6, 4, (4.0, 1.5, 1.8), 0.0, (1.0, 1.65, 12.0), mask=torch.zeros(H, W, dtype=torch.bool)),
        SceneObject(car + 7, 5, (4.0, 1.5, 1.8), 0.0, (60.0, 1.65, 10.0)),  # outside the frame
        SceneObject(car + 8, 6, (4.0, 1.5, 1.8), -0.8, (3.0, 1.65, 11.0)),  # and its exact twin, one row later:
        SceneObject(car + 9, 6, (4.0, 1.5, 1.8), -0.8, (3.0, 1.65, 11.0)),  # equal depths, the first row wins
    ])


def test_sparse_composition_equals_the_dense_reference():
    scene = _mixed_scene()
    maps, ref = scene_maps(scene), scene_maps_dense(scene)
    for key in ref.as_dict():
        assert torch.equal(getattr(maps, key), getattr(ref, key)), key
    assert torch.equal(compose_instances(scene), ref.instance)
    # The fixture exercises what it claims: ties go to the first row, a mask-less object crossing the
    # near plane and one across the border are drawn, the object behind the camera wins its mask.
    ids = set(maps.instance.unique().tolist())
    car = CAR * 1000
    assert {car + 1, FAR.instance_id, car + 3, car + 4, car + 5, car + 8} <= ids
    assert not {car + 6, car + 7, car + 9} & ids
    assert bool((maps.instance[scene.objects.mask[5]] == car + 5).all())
    # Reversing the table moves the twins' tie to the other one and changes nothing else.
    flipped = scene.replace(objects=scene.objects.select(torch.arange(len(scene.objects)).flip(0)))
    other = scene_maps(flipped).instance
    assert torch.equal(other, torch.where(ref.instance == car + 8, car + 9, ref.instance))


def test_objects_are_rasterized_in_crops_holding_every_pixel_they_cover(monkeypatch):
    scene = _mixed_scene()
    bank = default_bank()
    rows, verts, faces = posed_meshes(scene.objects, bank)
    K = scene.intrinsics.matrix().double()
    full = rasterize_meshes(verts, faces, K, RasterSettings(image_size=(H, W)))
    box = _projected_boxes(verts, K, 0.1, H, W)
    ii, jj = torch.meshgrid(torch.arange(H), torch.arange(W), indexing="ij")
    inside = ((jj >= box[:, 0, None, None]) & (jj < box[:, 2, None, None]) & (ii >= box[:, 1, None, None])
              & (ii < box[:, 3, None, None]))  # (x0, y0, x1, y1), half-open
    assert bool(full.mask.any()) and bool((full.mask <= inside).all())
    # One rasterizer call, with windows smaller than the frame (a regression to full-frame images shows here).
    import sdn3d.scene.maps as module

    sizes = []

    def spy(*args, **kwargs):
        sizes.append(args[3].image_size)
        return rasterize_meshes(*args, **kwargs)

    monkeypatch.setattr(module, "rasterize_meshes", spy)
    scene_maps(_scene([NEAR, FAR]))
    assert len(sizes) == 1 and sizes[0][0] * sizes[0][1] < H * W / 4


def test_fill_background_takes_a_nearest_source_on_random_maps():
    """Each vacated pixel takes the label of a source pixel at most 1 px (and 2 %) farther than the exact nearest."""
    from scipy.ndimage import distance_transform_edt

    gen = torch.Generator().manual_seed(0)
    for _ in range(5):
        sem = torch.randint(0, 4, (40, 56), generator=gen) * 3  # labels 0, 3, 6, 9; 9 is a thing class
        vacated = torch.zeros(40, 56, dtype=torch.bool)
        for _ in range(4):
            y, x = torch.randint(0, 32, (1,), generator=gen).item(), torch.randint(0, 48, (1,), generator=gen).item()
            vacated[y : y + 8, x : x + 8] = True
        out = fill_background(sem, vacated, torch.tensor([9]))
        assert torch.equal(out[~vacated], sem[~vacated])
        source = (~vacated & (sem != 9)).numpy()
        exact = distance_transform_edt(~source)
        for label in out[vacated].unique().tolist():
            assert label != 9
            taken = (out == label) & vacated
            # distance from each pixel that took `label` to the nearest source pixel of that label
            d_label = distance_transform_edt(~(source & (sem == label).numpy()))
            assert bool((d_label[taken.numpy()] <= exact[taken.numpy()] * 1.02 + 1.0).all())
