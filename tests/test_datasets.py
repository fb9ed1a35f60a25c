"""Branch datasets on tiny fixtures written in the real on-disk formats."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.data.datasets import GeometricDataset, ObjectFilter, SemanticDataset, TexturalDataset, closer_object_mask
from sdn3d.data.fixtures import write_vkitti1_fixture, write_vkitti2_fixture
from sdn3d.data.fixtures_cityscapes import write_cityscapes_fixture
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.data.vkitti1 import paper_object_filter
from sdn3d.image_ops import boundary_map, crop_windows, instance_label_map, resize_map, scale_boxes
from sdn3d.labels import CITYSCAPES_TRAIN_CLASSES, IGNORE_INDEX, INSTANCE_DIVISOR, VKITTI_CLASS_INDEX, VKITTI_CLASSES
from sdn3d.math3d.camera import project_points
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.rotations import alpha_bins, wrap_angle

NATIVE = (310, 94)  # a fifth of 1242x375: cars have several hundred pixels, the occluded van < 256
WORK = (160, 64)  # anisotropic resize (sx = 0.516, sy = 0.681)


FIXTURE_SPLIT = {"rule": "paper", "val_fraction": 0.25, "val_gap": 0}


def _k(vec: torch.Tensor) -> torch.Tensor:
    fx, fy, cx, cy = vec.tolist()
    return torch.tensor([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])


@pytest.fixture(scope="module")
def vk1(tmp_path_factory):
    root = tmp_path_factory.mktemp("vkitti1")
    frames = write_vkitti1_fixture(root, frames=range(5), size=NATIVE)
    # A fixture-sized split (the released ranges need Virtual KITTI's frame numbers): train 0-2, val 3, test 4.
    return SourceConfig(kind="vkitti1", root=str(root), image_size=WORK, split=FIXTURE_SPLIT), frames


def test_split_follows_paper_rule(vk1):
    source, frames = vk1
    paper = source
    train, test = load_split(paper, "train"), load_split(paper, "test")
    assert [r.frame for r in train] == [0, 1, 2] and [r.frame for r in test] == [4]
    assert [r.frame for r in load_split(paper, "val")] == [3]  # carved from the training frames, not test
    last = SourceConfig(kind="vkitti1", root=source.root, split={"rule": "paper", "first": False, "val_gap": 0})
    assert [r.frame for r in load_split(last, "train")] == [1, 2, 3]
    assert [r.frame for r in load_split(last, "val")] == [4]


def test_source_config_rejects_bad_input(vk1):
    with pytest.raises(ValueError, match="kind"):
        SourceConfig(kind="kitti", root=".")
    with pytest.raises(ValueError, match="unknown keys"):
        SourceConfig.from_mapping({"kind": "vkitti1", "root": ".", "worlds": ["0001"]})
    with pytest.raises(ValueError, match="classes"):
        SourceConfig(kind="vkitti1", root=".", classes="cityscapes")
    assert SourceConfig(kind="cityscapes", root=".").image_size == (512, 256)


def test_semantic_items_and_instance_ids(vk1):
    source, frames = vk1
    ds = SemanticDataset.from_source(source, "train")
    assert len(ds) == 3 and len(ds.classes) == 14 and ds.class_names[12] == "Car"
    item = ds[0]
    assert item["image"].shape == (3, 64, 160) and item["image"].dtype == torch.float32
    assert 0.0 <= float(item["image"].min()) and float(item["image"].max()) <= 1.0
    assert item["label"].shape == (64, 160) and item["label"].dtype == torch.long
    assert item["instance"].dtype == torch.long and item["key"] == "vkitti1/0001/clone/00000"
    ids = item["instance"].unique()
    ids = ids[ids != 0]
    tids = {o.track_id for o in frames[0].objects}
    assert len(ids) >= 3
    for i in ids.tolist():  # class * 1000 + (tid + 1), class agreeing with the semantic map
        cls, k = divmod(i, INSTANCE_DIVISOR)
        assert cls in (VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Van"]) and k - 1 in tids
        assert (item["label"][item["instance"] == i] == cls).all()
    # Nearest resizing invents no label: every value exists in the native map.
    native = torch.from_numpy(frames[0].semantic)
    assert set(item["label"].unique().tolist()) <= set(native.unique().tolist())


def test_resize_keeps_intrinsics(vk1):
    """The 3D centre projected with the working intrinsics lands in the resized box and object."""
    source, frames = vk1
    item = SemanticDataset.from_source(source, "train")[0]
    K = _k(item["intrinsics"])
    assert item["intrinsics"][0] / item["intrinsics"][1] != pytest.approx(1.0)  # anisotropic
    checked = 0
    for obj in frames[0].objects:
        x, y, z = obj.center
        uv = project_points(torch.tensor([[x, y, z]]), K)[0]
        l, t, r, b = scale_boxes(torch.tensor(obj.box2d), frames[0].intrinsics, WORK).tolist()
        assert l <= uv[0] <= r and t <= uv[1] <= b
        if obj.occluded == 0 and obj.truncr == 0:  # occupr is visible / box area: about 0.84 here when unoccluded
            j, i = round(float(uv[0])), round(float(uv[1]))
            assert int(item["instance"][i, j]) % INSTANCE_DIVISOR == obj.track_id + 1
            checked += 1
    assert checked >= 2


def test_resize_map_nearest_keeps_ids():
    ids = torch.tensor([[12001, 12001, 0, 13004]] * 3)
    out = resize_map(ids, (8, 6))
    assert out.dtype == torch.long and set(out.unique().tolist()) == {0, 12001, 13004}
    assert (out[:, :4] == 12001).all() and (out[:, 6:] == 13004).all()


@pytest.fixture(scope="module")
def geo(vk1):
    source, frames = vk1
    return GeometricDataset.from_source(source, "train"), frames


def test_geometric_filter_drops_tiny_objects(geo):
    ds, frames = geo
    expected = set()
    dropped_small = 0
    for f in frames[:3]:
        counts = torch.from_numpy(f.instances)
        for obj in f.objects:
            visible = int((counts % INSTANCE_DIVISOR == obj.track_id + 1).logical_and(counts > 0).sum())
            if paper_object_filter(obj, visible):
                expected.add(f"vkitti1/0001/clone/{f.frame:05d}/{obj.track_id}")
            elif visible <= 256:
                dropped_small += 1
    assert dropped_small >= 1  # the van hidden behind car 1 has < 256 pixels
    assert {ds[i]["key"] for i in range(len(ds))} == expected
    loose = GeometricDataset(ds.records, WORK, object_filter=ObjectFilter(min_pixels=0, max_occlusion=1.0))
    assert len(loose) > len(ds)


def test_geometric_item_layout_and_targets_decode(geo):
    ds, _ = geo
    batch = torch.utils.data.default_collate([ds[i] for i in range(len(ds))])
    n = len(ds)
    assert batch["crop"].shape == (n, 3, 64, 64) and batch["mask"].shape == (n, 1, 64, 64)
    assert batch["ignore"].shape == (n, 1, 64, 64) and batch["template_id"].dtype == torch.long
    assert (batch["template_id"] == -1).all()  # fixture models ('Hatchback', 'SUV') are not templates
    # Masked crop: zero outside the object's mask, not zero inside.
    assert (batch["crop"] * (1 - batch["mask"])).abs().max() == 0
    assert (batch["crop"].sum(1, keepdim=True)[batch["mask"] > 0] > 0).all()
    K = torch.stack([_k(v) for v in batch["intrinsics"]])
    dims, ry, center = AttributeEncoding().decode(batch["targets"], batch["box"], K)
    torch.testing.assert_close(dims, batch["dims"], rtol=1e-5, atol=1e-5)
    torch.testing.assert_close(ry, wrap_angle(batch["ry"]), rtol=0, atol=1e-5)
    torch.testing.assert_close(center, batch["center"], rtol=1e-4, atol=1e-4)


def test_geometric_item_cache_serves_identical_items_without_decoding(geo, monkeypatch):
    ds, _ = geo
    cached = GeometricDataset(ds.records, WORK, cache_items=True)
    order = list(range(len(cached)))[::-1]
    first = [cached[i] for i in order]
    decoded = []
    monkeypatch.setattr(cached, "_frame", lambda index: decoded.append(index))  # must not be called again
    again = [cached[i] for i in order]
    assert decoded == []
    for a, b, c in zip(first, again, [ds[i] for i in order], strict=True):
        assert a["key"] == b["key"] == c["key"]
        for k in ("crop", "mask", "ignore", "box", "crop_intrinsics"):
            assert torch.equal(a[k], c[k]) and torch.equal(b[k], c[k])



def test_geometric_item_cache_reads_a_frames_objects_from_one_decode(geo, monkeypatch):
    """With cache_items, the first read of an object reads its frame's other objects too: a shuffled order decodes
    each frame once, not once per object; and they are the items an uncached read gives."""
    import sdn3d.data.datasets.geometric as module

    ds, _ = geo
    cached = GeometricDataset(ds.records, WORK, cache_items=True)
    frames = [ref.frame for ref in cached.objects]
    shared = next(f for f in frames if frames.count(f) > 1)  # a frame with several objects
    members = [i for i, f in enumerate(frames) if f == shared]
    other = next(i for i, f in enumerate(frames) if f != shared)
    decoded = []
    real = module.load_frame

    def counting(record, *args, **kwargs):
        decoded.append(record.key)
        return real(record, *args, **kwargs)
    monkeypatch.setattr(module, "load_frame", counting)
    order = [members[-1], other, members[0], *range(len(cached))]  # shuffled: the frame's objects apart
    items = [cached[i] for i in order]
    assert sorted(decoded) == sorted({cached.records[f].key for f in frames})  # every frame decoded once
    for i, item in zip(order, items, strict=True):
        assert item["key"] == ds[i]["key"] and torch.equal(item["crop"], ds[i]["crop"])


def test_crop_intrinsics_match_crop_pixels(geo):
    ds, frames = geo
    for i in range(len(ds)):
        item = ds[i]
        side = float(item["crop_box"][2] - item["crop_box"][0])
        assert side == float(item["crop_box"][3] - item["crop_box"][1])  # square window
        # The crop camera maps a point exactly as "full image, shift by the window, scale".
        uv_full = project_points(item["center"][None], _k(item["intrinsics"]))[0]
        uv_crop = project_points(item["center"][None], _k(item["crop_intrinsics"]))[0]
        expected = (uv_full - item["crop_box"][:2]) * (64 / side) - 0.5
        torch.testing.assert_close(uv_crop, expected, rtol=0, atol=1e-3)
        if item["track_id"] == 0:  # never occluded: its projected centre is on its own mask
            j, k = round(float(uv_crop[0])), round(float(uv_crop[1]))
            assert item["mask"][0, k, j] == 1


def test_closer_object_mask_constructed():
    inst = torch.zeros(6, 8, dtype=torch.long)
    depth = torch.full((6, 8), 100.0)
    inst[1:5, 2:6], depth[1:5, 2:6] = 12001, 10.0  # the object
    inst[2:6, 5:8], depth[2:6, 5:8] = 12002, 5.0  # closer object, overlapping its right edge
    inst[0:2, 0:2], depth[0:2, 0:2] = 13003, 20.0  # farther object
    mask = inst == 12001
    ignore = closer_object_mask(inst, depth, mask, depth[mask].median())
    assert torch.equal(ignore, inst == 12002)


def test_geometric_ignore_marks_only_closer_objects(vk1):
    source, frames = vk1
    ds = GeometricDataset(load_split(source, "train")[:1], WORK,
                          object_filter=ObjectFilter(min_pixels=0, max_occlusion=1.0))
    items = {int(ds[i]["track_id"]): ds[i] for i in range(len(ds))}
    van, car1 = items[3], items[1]  # the van (z = 22 m) is partly hidden by car 1 (z = 10.7 m)
    inst = resize_map(torch.from_numpy(frames[0].instances), WORK)
    left, top = (int(v + 0.5) for v in van["crop_box"][:2])
    side = int(van["crop_box"][2] - van["crop_box"][0])
    others = crop_windows(((inst != 0) & (inst % 1000 != 4)).float()[None], torch.tensor([[left, top, side]]), 64,
                          "nearest")[0]
    assert van["ignore"].sum() > 0 and torch.equal(van["ignore"], others)  # every other car is closer
    left, top = (int(v + 0.5) for v in car1["crop_box"][:2])
    side = int(car1["crop_box"][2] - car1["crop_box"][0])
    van_px = crop_windows((inst % 1000 == 4).float()[None], torch.tensor([[left, top, side]]), 64, "nearest")[0]
    assert van_px.sum() > 0 and (car1["ignore"] * van_px).sum() == 0  # the farther van is not ignored


def test_instance_label_map_and_boundary():
    sem = torch.tensor([[5, 5, 5, 1], [5, 12, 12, 1], [5, 12, 12, 1]])
    inst = torch.tensor([[0, 0, 0, 0], [0, 12001, 12001, 0], [0, 12001, 13002, 0]])
    label, lmap = instance_label_map(sem, inst)
    assert int(label[2, 2]) == 13  # instance wins the conflict with the semantic map
    assert torch.equal(lmap, torch.tensor([[5, 5, 5, 1], [5, 12001, 12001, 1], [5, 12001, 13002, 1]]))
    edge = boundary_map(lmap[None])[0, 0]
    assert edge.shape == (3, 4) and edge[0, 0] == 0 and edge[1, 1] == 1 and edge[2, 2] == 1
    assert edge[0, 2] == 1 and edge[0, 3] == 1  # the 5 | 1 border marks both sides


def test_textural_items(vk1):
    source, frames = vk1
    ds = TexturalDataset.from_source(source, "train")
    item = ds[0]
    h, w = 64, 160
    shapes = {"image": (3, h, w), "label": (h, w), "instance": (h, w), "instance_label_map": (h, w),
              "boundary": (1, h, w), "normal": (3, h, w), "pose": (24, h, w), "depth": (1, h, w)}
    for key, shape in shapes.items():
        assert item[key].shape == shape, key
    inst, lmap = item["instance"], item["instance_label_map"]
    objects = inst != 0
    assert torch.equal(lmap >= 1000, objects) and torch.equal(lmap[objects], inst[objects])
    assert torch.equal(lmap[~objects], item["label"][~objects])
    assert bool(item["has_geometry"]) and float(item["depth"].min()) > 0
    # Pose: one-hot of each object's alpha bin on its visible pixels, zero elsewhere.
    assert torch.equal(item["pose"].sum(0), objects.float())
    for obj in frames[0].objects:
        px = objects & (inst % 1000 == obj.track_id + 1)
        bin_ = int(alpha_bins(torch.tensor(obj.alpha)))
        assert (item["pose"][bin_][px] == 1).all()
    # Normals: unit length on (most) object pixels, zero off objects, facing the camera.
    norm = item["normal"].norm(dim=0)
    on = norm > 0
    assert not (on & ~objects).any() and on.sum() > 0.5 * objects.sum()
    torch.testing.assert_close(norm[on], torch.ones(int(on.sum())), rtol=0, atol=1e-5)
    fx, fy, cx, cy = item["intrinsics"].tolist()
    i, j = torch.nonzero(on, as_tuple=True)
    rays = torch.stack([(j - cx) / fx, (i - cy) / fy, torch.ones_like(j, dtype=torch.float32)], -1)
    assert ((item["normal"][:, i, j].T * rays).sum(-1) < 0).all()


def test_vkitti2_and_cityscapes(tmp_path):
    write_vkitti2_fixture(tmp_path / "vk2", frames=range(5), size=NATIVE)
    vk2 = SourceConfig(kind="vkitti2", root=str(tmp_path / "vk2"), image_size=WORK, split=FIXTURE_SPLIT)
    item = SemanticDataset.from_source(vk2, "train")[0]
    assert item["label"].shape == (64, 160) and int(item["label"][0, 0]) == IGNORE_INDEX  # Undefined patch
    geo = GeometricDataset.from_source(vk2, "train")  # counts from bbox.txt's number_pixels
    assert len(geo) > 0 and all(int(geo[i]["visible_pixels"]) > 256 for i in range(len(geo)))

    write_cityscapes_fixture(tmp_path / "cs", size=(128, 64))
    cs = SourceConfig(kind="cityscapes", root=str(tmp_path / "cs"), image_size=(64, 32))
    sem = SemanticDataset.from_source(cs, "train")
    # train and validation from the train folder (aachen 0 | gap 1 | val 2), test = the official val folder
    assert len(sem) == 1 and len(SemanticDataset.from_source(cs, "val")) == 1
    assert [r.world for r in SemanticDataset.from_source(cs, "test").records] == ["frankfurt"]
    assert sem.classes == CITYSCAPES_TRAIN_CLASSES and len(sem.classes) == 19
    item = sem[0]
    ids = item["instance"].unique()
    assert set((ids[ids != 0] // 1000).tolist()) == {11, 13}  # person, car (caravan/crowd dropped)
    assert (item["label"] == IGNORE_INDEX).any()
    intr = item["intrinsics"]
    assert intr[0] == pytest.approx(2262.52 * 128 / 2048 * 0.5)
    assert intr[1] == pytest.approx(2265.3017905988 / 32)
    assert len(GeometricDataset.from_source(cs, "train")) == 0  # no 3D annotations
    tex = TexturalDataset.from_source(cs, "val")[0]
    assert not bool(tex["has_geometry"]) and tex["pose"].abs().sum() == 0
    assert tex["label"].max() <= IGNORE_INDEX and math.isfinite(float(tex["depth"].sum()))
    assert len(VKITTI_CLASSES) == 14


def test_geometric_mirror_serves_each_object_reflected_with_consistent_targets(geo):
    """Issue 40: ``mirror=True`` doubles the objects; item ``n + i`` is item ``i`` reflected about the principal point's
    column: the crop and masks flipped, ``x -> -x``, ``ry -> pi - ry``, the box mirrored, and targets that decode to
    the reflected pose."""
    ds, _ = geo
    mirrored = GeometricDataset(ds.records, WORK, mirror=True)
    n = len(ds)
    assert len(mirrored) == 2 * n
    for i in range(n):
        a, b = mirrored[i], mirrored[n + i]
        assert b["key"] == a["key"] + "/mirrored"
        torch.testing.assert_close(b["crop"], a["crop"].flip(-1))
        torch.testing.assert_close(b["mask"], a["mask"].flip(-1))
        cx = float(a["intrinsics"][2])
        torch.testing.assert_close(b["box"], torch.stack([2 * cx - a["box"][2], a["box"][1], 2 * cx - a["box"][0],
                                                          a["box"][3]]))
        torch.testing.assert_close(b["center"], a["center"] * torch.tensor([-1.0, 1.0, 1.0]))
        assert math.cos(float(b["ry"]) - (math.pi - float(a["ry"]))) == pytest.approx(1.0, abs=1e-6)
        dims, ry, center = AttributeEncoding().decode({k: v[None] for k, v in b["targets"].items()}, b["box"][None],
                                                      _k(b["intrinsics"])[None])
        torch.testing.assert_close(center[0], b["center"], rtol=1e-4, atol=1e-4)
        torch.testing.assert_close(ry[0], wrap_angle(b["ry"]), rtol=0, atol=1e-5)
        # The crop camera is reflected too: the centre projects to the mirrored crop column.
        fx, fy, ccx, ccy = b["crop_intrinsics"].tolist()
        u_b = fx * float(b["center"][0]) / float(b["center"][2]) + ccx
        fx, fy, ccx, ccy = a["crop_intrinsics"].tolist()
        u_a = fx * float(a["center"][0]) / float(a["center"][2]) + ccx
        assert u_b == pytest.approx(a["crop"].shape[-1] - 1 - u_a, abs=1e-3)
    with pytest.raises(IndexError):
        mirrored[2 * n]



def test_semantic_item_cache_serves_identical_items_without_decoding(vk1, monkeypatch):
    source, _ = vk1
    plain = SemanticDataset.from_source(source, "train")
    expected = [plain[i] for i in range(len(plain))]
    cached = SemanticDataset.from_source(source, "train", cache_items=True)
    first = [cached[i] for i in range(len(cached))]
    first[0]["image"].zero_()  # a caller changing its item in place leaves the kept frame alone
    first[0]["label"].fill_(7)
    monkeypatch.setattr("sdn3d.data.datasets.semantic.load_frame",
                        lambda *a, **k: pytest.fail("a kept frame was decoded again"))
    again = [cached[i] for i in range(len(cached))]
    for b, c in zip(again, expected, strict=True):
        assert b["key"] == c["key"]
        for k in ("image", "label", "instance", "intrinsics"):
            assert b[k].dtype == c[k].dtype and torch.equal(b[k], c[k]), k
