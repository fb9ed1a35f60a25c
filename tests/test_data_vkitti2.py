"""Virtual KITTI 2.0.3 reader on fixtures written in the exact on-disk format."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sdn3d.data.errors import DataFormatError
from sdn3d.data.fixtures import VKITTI2_BASELINE, VKITTI2_COLORS, write_vkitti2_fixture
from sdn3d.data.records import load_depth, load_instances, load_rgb, load_semantic
from sdn3d.data.splits import paper_split
from sdn3d.data.vkitti2 import BBOX_HEADER, POSE_HEADER, parse_colors, read_frames, scene_to_world
from sdn3d.labels import IGNORE_INDEX, VKITTI_CLASS_INDEX


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    root = tmp_path_factory.mktemp("vkitti2")
    return root, write_vkitti2_fixture(root, scene="Scene06", variation="fog", frames=(0, 1))


def _truth(truth, camera):
    return [f for f in truth if f.camera == camera]


@pytest.mark.parametrize("camera", [0, 1, "Camera_1"])
def test_records_match_what_was_written(tree, camera):
    root, truth = tree
    records = read_frames(root, camera=camera)
    name = f"Camera_{camera}" if isinstance(camera, int) else camera
    expected = _truth(truth, name)
    assert [(r.world, r.variation, r.camera, r.frame) for r in records] == [
        ("Scene06", "fog", name, 0), ("Scene06", "fog", name, 1)
    ]  # fmt: skip
    for record, exp in zip(records, expected, strict=True):
        assert record.intrinsics == exp.intrinsics
        # The README: instance maps are 8-bit indexed PNGs holding trackID + 1.
        assert Image.open(record.instance_path).mode == "P"
        rgb = load_rgb(record)
        assert rgb.shape == (32, 64, 3) and rgb.dtype == np.uint8
        np.testing.assert_array_equal(load_semantic(record), exp.semantic)
        np.testing.assert_array_equal(load_instances(record), exp.instances)
        np.testing.assert_array_equal(load_depth(record), exp.depth)
        assert record.objects == exp.objects
        np.testing.assert_allclose(record.extrinsics_matrix(), exp.extrinsics)


def test_bbox_columns_are_left_right_top_bottom(tree):
    root, _ = tree
    seq = root / "Scene06" / "fog"
    header, first = (seq / "bbox.txt").read_text().splitlines()[:2]
    assert header.split() == list(BBOX_HEADER)
    values = dict(zip(BBOX_HEADER, first.split(), strict=True))
    obj = next(o for o in read_frames(root)[0].objects if o.track_id == int(values["trackID"]))
    assert obj.box2d == tuple(float(values[c]) for c in ("left", "top", "right", "bottom"))
    assert obj.box2d[0] <= obj.box2d[2] and obj.box2d[1] <= obj.box2d[3]
    assert obj.num_pixels == int(values["number_pixels"])
    assert obj.moving is (values["isMoving"] == "True")
    pose = dict(zip(POSE_HEADER, (seq / "pose.txt").read_text().splitlines()[1].split(), strict=True))
    assert obj.dims == (float(pose["length"]), float(pose["height"]), float(pose["width"]))
    assert obj.location == tuple(float(pose[f"camera_space_{c}"]) for c in "XYZ")


def test_occupancy_ratio_is_pixels_over_box_area(tree):
    """Real bbox.txt rows satisfy occupancy_ratio = number_pixels / ((right - left) * (bottom - top))
    (e.g. 41767 / (253 * 215) = 0.7678463 for ``0 0 0 988 1241 159 374 41767 0.4230517 0.7678463``)."""
    root, truth = tree
    lines = (root / "Scene06" / "fog" / "bbox.txt").read_text().splitlines()[1:]
    rows = [dict(zip(BBOX_HEADER, line.split(), strict=True)) for line in lines]
    assert len(rows) >= 4
    for row in rows:
        left, right, top, bottom = (int(row[c]) for c in ("left", "right", "top", "bottom"))
        expected = int(row["number_pixels"]) / ((right - left) * (bottom - top))
        assert float(row["occupancy_ratio"]) == pytest.approx(expected, abs=1e-6)
    record = read_frames(root)[0]
    for obj in record.objects:
        l, t, r, b = obj.box2d
        assert obj.occupr == pytest.approx(obj.num_pixels / ((r - l) * (b - t)), abs=1e-6)


def test_visible_pixels_match_instance_map(tree):
    root, _ = tree
    record = read_frames(root)[0]
    instances = load_instances(record)
    for obj in record.objects:
        assert obj.num_pixels == int((instances % 1000 == obj.track_id + 1).sum())
        assert instances[instances % 1000 == obj.track_id + 1][0] // 1000 == VKITTI_CLASS_INDEX[obj.label]


def test_right_camera_sees_objects_shifted_by_the_baseline(tree):
    root, _ = tree
    left, right = read_frames(root, camera=0)[0], read_frames(root, camera=1)[0]
    by_tid = {o.track_id: o for o in right.objects}
    for obj in left.objects:
        if obj.track_id in by_tid:
            dx = obj.location[0] - by_tid[obj.track_id].location[0]
            assert dx == pytest.approx(VKITTI2_BASELINE, abs=2e-6)
    # Same world point, two cameras: p_right = p_left - (baseline, 0, 0).
    point = np.array([1.0, 2.0, 30.0, 1.0])
    diff = left.extrinsics_matrix() @ point - right.extrinsics_matrix() @ point
    np.testing.assert_allclose(diff[:3], [VKITTI2_BASELINE, 0, 0], atol=1e-6)


def test_colors_table_maps_names_and_undefined(tree):
    root, _ = tree
    table = parse_colors(root / "Scene06" / "fog" / "colors.txt")
    assert len(table.keys) == len(VKITTI2_COLORS) == 15
    record = read_frames(root)[0]
    semantic = load_semantic(record)
    assert (semantic[:2, :2] == IGNORE_INDEX).all() and (semantic == IGNORE_INDEX).sum() == 4
    # GuardRail is 250,100,255 in VKITTI 2 (255,100,255 in VKITTI 1) and still decodes to GuardRail.
    classgt = np.asarray(Image.open(record.semantic_path))
    guard = semantic == VKITTI_CLASS_INDEX["GuardRail"]
    assert guard.any() and (classgt[guard] == (250, 100, 255)).all()


@pytest.mark.parametrize("mode", ["L", "I;16"])
def test_instance_png_modes(tmp_path, mode):
    truth = write_vkitti2_fixture(tmp_path, frames=(0,), instance_mode=mode)
    record = read_frames(tmp_path)[0]
    assert Image.open(record.instance_path).mode == mode
    np.testing.assert_array_equal(load_instances(record), truth[0].instances)


def test_readme_lowercase_segmentation_folders(tmp_path):
    """The README spells the folders classsegmentation / instancesegmentation; the archives use camel case."""
    truth = write_vkitti2_fixture(tmp_path, frames=(0,))
    frames_dir = tmp_path / "Scene01" / "clone" / "frames"
    for name in ("classSegmentation", "instanceSegmentation"):
        (frames_dir / name).rename(frames_dir / name.lower())
    record = read_frames(tmp_path)[0]
    assert record.semantic_path.parent.parent.name == "classsegmentation"
    np.testing.assert_array_equal(load_semantic(record), truth[0].semantic)
    np.testing.assert_array_equal(load_instances(record), truth[0].instances)


def test_format_errors_name_file_and_line(tmp_path):
    write_vkitti2_fixture(tmp_path, frames=(0,))
    seq = tmp_path / "Scene01" / "clone"
    pose = (seq / "pose.txt").read_text().splitlines()
    (seq / "pose.txt").write_text("\n".join(pose[:1] + pose[2:]) + "\n")  # drop frame 0 track 0
    expected = r"bbox.txt:2: no row in .*pose.txt for frame 0 camera 0 track 0"
    with pytest.raises(DataFormatError, match=expected):
        read_frames(tmp_path)
    (seq / "pose.txt").write_text("\n".join(pose) + "\n")
    bbox = (seq / "bbox.txt").read_text().splitlines()
    bbox[1] = bbox[1].replace("True", "maybe")
    (seq / "bbox.txt").write_text("\n".join(bbox) + "\n")
    with pytest.raises(DataFormatError, match=r"bbox.txt:2: column 11 \('isMoving'\)"):
        read_frames(tmp_path)
    colors = (seq / "colors.txt").read_text().replace("Misc", "Rubble")
    (seq / "colors.txt").write_text(colors)
    record = read_frames(tmp_path, annotations=False)[0]
    with pytest.raises(DataFormatError, match="colors.txt:12: unknown category 'Rubble'"):
        load_semantic(record)


def test_instance_value_without_track_is_reported(tmp_path):
    write_vkitti2_fixture(tmp_path, frames=(0,))
    record = read_frames(tmp_path)[0]
    values = np.asarray(Image.open(record.instance_path)).copy()
    values[0, :3] = 42
    Image.fromarray(values).save(record.instance_path)
    with pytest.raises(DataFormatError, match=r"42 \(track 41\) x 3 px"):
        load_instances(record)


def test_without_textgt_uses_nominal_intrinsics(tmp_path):
    write_vkitti2_fixture(tmp_path, frames=(0, 1, 2, 3, 4))
    for name in ("bbox.txt", "pose.txt", "intrinsic.txt", "extrinsic.txt"):
        (tmp_path / "Scene01" / "clone" / name).unlink()
    with pytest.raises(FileNotFoundError, match="intrinsic.txt"):
        read_frames(tmp_path)
    records = read_frames(tmp_path, annotations=False)
    assert records[0].objects == () and records[0].extrinsics is None
    assert records[0].intrinsics.width == 64 and records[0].intrinsics.fx == pytest.approx(725 * 64 / 1242)
    assert [r.frame for r in paper_split(records, "test")] == [4]


def test_scene_names_and_camera_argument():
    assert scene_to_world("Scene06") == "0006" and scene_to_world("Scene20") == "0020"
    with pytest.raises(ValueError, match="Scene06"):
        scene_to_world("world6")
    with pytest.raises(ValueError, match="camera"):
        read_frames("/nonexistent", camera=2)


def test_bad_first_frame_and_nonpositive_dimensions_are_named(tmp_path):
    from sdn3d.data.errors import SkipLog

    write_vkitti2_fixture(tmp_path, frames=(0, 1, 2))
    records = read_frames(tmp_path)
    Image.new("RGB", (40, 20)).save(records[0].rgb_path, format="JPEG")
    with pytest.raises(DataFormatError, match=str(records[0].rgb_path) + r": image is 40x20, but 2 of the 3 frames"):
        read_frames(tmp_path)
    skip = SkipLog()
    assert [r.intrinsics.size for r in read_frames(tmp_path, skip=skip)] == [(32, 64)] * 3
    assert skip.skipped_frames == {records[0].key}
    records[0].rgb_path.write_bytes(records[1].rgb_path.read_bytes())
    pose = tmp_path / "Scene01" / "clone" / "pose.txt"
    lines = pose.read_text().splitlines()
    fields = lines[1].split()
    fields[POSE_HEADER.index("length")] = "-4.2"
    pose.write_text("\n".join([lines[0], " ".join(fields), *lines[2:]]) + "\n")
    with pytest.raises(DataFormatError, match=r"pose.txt:2: object dimensions must be positive, got length -4.2"):
        read_frames(tmp_path)
    skip = SkipLog()
    records = read_frames(tmp_path, skip=skip)
    assert [i.kind for i in skip.items] == ["object"] and skip.items[0].frame == records[0].key


def test_alpha_is_kept_as_stored_even_outside_pi(tmp_path):
    """Real VKITTI 2 pose files have a few alphas outside [-pi, pi]: read as stored, not refused, not wrapped."""
    write_vkitti2_fixture(tmp_path, scene="Scene06", variation="fog", frames=(0,))
    pose = next(tmp_path.rglob("pose.txt"))
    lines = pose.read_text().splitlines()
    header, first = lines[0].split(), lines[1].split()
    first[header.index("alpha")] = "3.3000001"
    pose.write_text("\n".join([lines[0], " ".join(first), *lines[2:]]) + "\n")
    objects = {o.track_id: o for o in read_frames(tmp_path)[0].objects}
    assert objects[int(first[header.index("trackID")])].alpha == pytest.approx(3.3000001)
