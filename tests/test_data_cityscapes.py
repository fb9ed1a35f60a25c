"""Cityscapes reader on fixtures written in the exact on-disk format."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from sdn3d.data.cityscapes import camera_to_vehicle, read_frames
from sdn3d.data.errors import DataFormatError
from sdn3d.data.fixtures_cityscapes import CITYSCAPES_FIXTURE_FRAMES, write_cityscapes_fixture
from sdn3d.data.records import load_depth, load_instances, load_rgb, load_semantic
from sdn3d.labels import CITYSCAPES_EMBEDDED_LABELS, CITYSCAPES_LABELS, CITYSCAPES_TRAIN_CLASSES, LABEL_TO_TRAIN


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    root = tmp_path_factory.mktemp("cityscapes")
    return root, write_cityscapes_fixture(root)


def test_label_table_has_34_ids_and_19_train_classes():
    assert [row[1] for row in CITYSCAPES_LABELS] == list(range(34))
    assert [c.id for c in CITYSCAPES_TRAIN_CLASSES] == list(range(19))
    names = [c.name for c in CITYSCAPES_TRAIN_CLASSES]
    assert names == ["road", "sidewalk", "building", "wall", "fence", "pole", "traffic light", "traffic sign",
                     "vegetation", "terrain", "sky", "person", "rider", "car", "truck", "bus", "train",
                     "motorcycle", "bicycle"]  # fmt: skip
    assert {c.name for c in CITYSCAPES_TRAIN_CLASSES if c.has_instances} == {
        "person", "rider", "car", "truck", "bus", "train", "motorcycle", "bicycle"
    }  # fmt: skip
    assert LABEL_TO_TRAIN[7] == 0 and LABEL_TO_TRAIN[26] == 13 and LABEL_TO_TRAIN[9] == 255
    assert (LABEL_TO_TRAIN[34:] == 255).all()
    assert CITYSCAPES_TRAIN_CLASSES[13].color == (0, 0, 142)


def test_embedded_table_agrees_with_cityscapesscripts():
    labels = pytest.importorskip("cityscapesscripts.helpers.labels").labels
    official = sorted(
        (lb.name, lb.id, lb.trainId, bool(lb.hasInstances), tuple(lb.color)) for lb in labels if lb.id >= 0
    )
    assert sorted(CITYSCAPES_EMBEDDED_LABELS) == official


def test_records_and_arrays_match_what_was_written(tree):
    root, truth = tree
    for split in ("train", "val"):
        records = read_frames(root, split)
        expected = [f for f in truth if f.variation == split]
        assert [(r.world, r.sequence, r.frame) for r in records] == list(CITYSCAPES_FIXTURE_FRAMES[split])
        for record, exp in zip(records, expected, strict=True):
            assert record.intrinsics == exp.intrinsics
            assert load_rgb(record).shape == (32, 64, 3)
            np.testing.assert_array_equal(load_semantic(record), exp.semantic)
            np.testing.assert_array_equal(load_instances(record), exp.instances)
            np.testing.assert_allclose(load_depth(record), exp.depth, rtol=1e-6)
    keys = [r.key for r in read_frames(root, "train")]
    assert keys == [f"cityscapes/aachen/train/{s:06d}/000019" for s in range(3)]


def test_instances_keep_only_individual_objects_with_train_ids(tree):
    root, _ = tree
    record = read_frames(root, "train")[0]
    raw = np.asarray(Image.open(record.instance_path)).astype(np.int64)
    instances = load_instances(record)
    # Individual cars (26000, 26001) -> 13000, 13001; person 24000 -> 11000.
    np.testing.assert_array_equal(np.unique(instances), [0, 11000, 13000, 13001])
    np.testing.assert_array_equal(instances[raw == 26001], 13001)
    # Crowd (plain label id 26) and caravan instances (no train id) are not instances.
    assert (raw == 26).any() and (instances[raw == 26] == 0).all()
    assert (raw == 29000).any() and (instances[raw == 29000] == 0).all()
    semantic = load_semantic(record)
    np.testing.assert_array_equal(semantic[instances > 0], instances[instances > 0] // 1000)


def test_depth_from_disparity_and_invalid_pixels(tree):
    root, _ = tree
    record = read_frames(root, "val")[0]
    raw = np.asarray(Image.open(record.depth_path)).astype(np.float64)
    depth = load_depth(record)
    assert (depth[raw == 0] == 0).all() and (depth[raw > 1] > 0).all()
    camera = json.loads(record.aux_path("camera").read_text())
    i, j = np.argwhere(raw > 1)[0]
    expected = camera["extrinsic"]["baseline"] * camera["intrinsic"]["fx"] / ((raw[i, j] - 1) / 256)
    assert depth[i, j] == pytest.approx(expected, rel=1e-6)


def test_camera_extrinsics_in_kitti_axes(tree):
    root, _ = tree
    record = read_frames(root, "train")[0]
    to_camera = record.extrinsics_matrix()
    camera = json.loads(record.aux_path("camera").read_text())["extrinsic"]
    # The camera position in the vehicle frame maps to the camera origin.
    origin = to_camera @ [camera["x"], camera["y"], camera["z"], 1.0]
    np.testing.assert_allclose(origin[:3], 0, atol=1e-9)
    # With zero angles: vehicle forward/left/up -> camera +z / -x / -y (KITTI: x right, y down, z fwd).
    flat = camera_to_vehicle({"x": 0.0, "y": 0.0, "z": 0.0, "yaw": 0.0, "pitch": 0.0, "roll": 0.0})
    to_cam = np.linalg.inv(flat)
    np.testing.assert_allclose(to_cam[:3, :3] @ [1, 0, 0], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(to_cam[:3, :3] @ [0, 1, 0], [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(to_cam[:3, :3] @ [0, 0, 1], [0, -1, 0], atol=1e-12)
    # A positive pitch tilts the optical axis down (towards vehicle -z).
    pitched = camera_to_vehicle({"x": 0.0, "y": 0.0, "z": 0.0, "yaw": 0.0, "pitch": 0.1, "roll": 0.0})
    assert (pitched[:3, :3] @ [0, 0, 1])[2] < 0


def test_errors_name_the_file(tmp_path):
    write_cityscapes_fixture(tmp_path, frames={"train": (("bochum", 0, 1),)})
    (record,) = read_frames(tmp_path, "train")
    labels = np.asarray(Image.open(record.semantic_path)).copy()
    labels[0, :5] = 40
    Image.fromarray(labels).save(record.semantic_path)
    with pytest.raises(DataFormatError, match=r"labelIds.png: label ids outside 0..33: 40 x 5 px"):
        load_semantic(record)
    camera = record.aux_path("camera")
    camera.write_text('{"intrinsic": {"fx": 1}')
    with pytest.raises(DataFormatError, match=r"camera.json: invalid JSON"):
        read_frames(tmp_path, "train")
    camera.write_text(json.dumps({"intrinsic": {"fx": "a", "fy": 1, "u0": 1, "v0": 1}, "extrinsic": {}}))
    with pytest.raises(DataFormatError, match=r"camera.json: intrinsic.fx must be a finite number"):
        read_frames(tmp_path, "train")
    camera.unlink()
    with pytest.raises(FileNotFoundError, match="camera.json"):
        read_frames(tmp_path, "train")
    with pytest.raises(FileNotFoundError, match="leftImg8bit/test"):
        read_frames(tmp_path, "test")


def test_missing_camera_file_or_odd_size_is_named_or_skipped(tmp_path):
    from faults.data import wrong_size_png

    from sdn3d.data.errors import SkipLog

    write_cityscapes_fixture(tmp_path, frames={"train": (("bochum", 0, 1), ("bochum", 0, 2), ("bochum", 0, 3))})
    records = read_frames(tmp_path, "train")
    camera = records[1].aux_path("camera")
    saved = camera.read_bytes()
    camera.unlink()
    with pytest.raises(FileNotFoundError, match=str(camera)):
        read_frames(tmp_path, "train")
    skip = SkipLog()
    assert [r.key for r in read_frames(tmp_path, "train", skip=skip)] == [records[0].key, records[2].key]
    assert skip.skipped_frames == {records[1].key} and skip.files == [str(camera)]
    camera.write_bytes(saved)
    wrong_size_png(records[0].rgb_path, (32, 16))  # the city's first frame is the odd one
    with pytest.raises(DataFormatError, match=str(records[0].rgb_path) + ": image is 32x16, but 2 of the 3"):
        read_frames(tmp_path, "train")
    skip = SkipLog()
    assert [r.key for r in read_frames(tmp_path, "train", skip=skip)] == [records[1].key, records[2].key]
    assert skip.skipped_frames == {records[0].key}
