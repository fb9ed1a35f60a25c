"""Virtual KITTI 1.3.1 reader on fixtures written in the exact on-disk format."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sdn3d.data.errors import DataFormatError, MissingDataError
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.data.records import (
    ObjectAnnotation,
    load_depth,
    load_instances,
    load_rgb,
    load_semantic,
    visible_pixel_counts,
)
from sdn3d.data.splits import paper_split
from sdn3d.data.vkitti1 import (
    MOTGT_HEADER,
    paper_object_filter,
    parse_encoding,
    parse_extrinsics,
    parse_motgt,
    read_frames,
)
from sdn3d.labels import VKITTI_CLASS_INDEX, VKITTI_CLASSES, split_instance_ids
from sdn3d.math3d.camera import VKITTI_INTRINSICS


@pytest.fixture(scope="module")
def reference_tree(tmp_path_factory, real_vkitti_frame):
    """Frame 0006/30-deg-right/00043 at the native 1242x375 size; its RGB is the real Virtual KITTI frame
    (tests/data)."""
    root = tmp_path_factory.mktemp("vkitti1_ref")
    truth = write_vkitti1_fixture(
        root, world="0006", variation="30-deg-right", frames=(43,), size=(1242, 375), rgb_image=real_vkitti_frame
    )
    return root, truth


@pytest.fixture()
def small_tree(tmp_path):
    truth = write_vkitti1_fixture(tmp_path, world="0001", variation="clone", frames=(0, 1, 2))
    return tmp_path, truth


def test_class_table_is_the_official_vkitti1_list():
    names = [c.name for c in VKITTI_CLASSES]
    assert names == ["Terrain", "Sky", "Tree", "Vegetation", "Building", "Road", "GuardRail", "TrafficSign",
                     "TrafficLight", "Pole", "Misc", "Truck", "Car", "Van"]  # fmt: skip
    colors = {c.name: c.color for c in VKITTI_CLASSES}
    assert colors["Terrain"] == (210, 0, 200) and colors["GuardRail"] == (255, 100, 255)
    assert colors["Road"] == (100, 60, 100) and colors["Truck"] == (160, 60, 60)
    assert [c.id for c in VKITTI_CLASSES] == list(range(14))
    assert {c.name for c in VKITTI_CLASSES if c.has_instances} == {"Car", "Van"}


def test_reference_frame_loads_with_native_size_and_intrinsics(reference_tree, real_vkitti_frame):
    root, truth = reference_tree
    (record,) = read_frames(root)
    assert (record.world, record.variation, record.frame) == ("0006", "30-deg-right", 43)
    assert record.intrinsics == VKITTI_INTRINSICS
    rgb = load_rgb(record)
    assert rgb.shape == (375, 1242, 3) and rgb.dtype == np.uint8
    np.testing.assert_array_equal(rgb, np.asarray(Image.open(real_vkitti_frame).convert("RGB")))
    semantic, instances, depth = load_semantic(record), load_instances(record), load_depth(record)
    assert semantic.dtype == np.int64 and instances.dtype == np.int64 and depth.dtype == np.float32
    np.testing.assert_array_equal(semantic, truth[0].semantic)
    np.testing.assert_array_equal(instances, truth[0].instances)
    np.testing.assert_array_equal(depth, truth[0].depth)
    assert record.objects == truth[0].objects
    np.testing.assert_allclose(record.extrinsics_matrix(), truth[0].extrinsics)


def test_instance_ids_encode_class_and_track(reference_tree):
    root, _ = reference_tree
    (record,) = read_frames(root)
    instances, semantic = load_instances(record), load_semantic(record)
    counts = visible_pixel_counts(instances)
    classes, k = split_instance_ids(np.array(sorted(counts)))
    tids = {o.track_id: o.label for o in record.objects}
    # k = tid + 1; the class part is Car (12) or Van (13) as the motgt's original label says.
    assert sorted((k - 1).tolist()) == sorted(tids)
    for cls, tid in zip(classes.tolist(), (k - 1).tolist(), strict=True):
        orig = next(o.orig_label for o in record.objects if o.track_id == tid)
        assert cls == VKITTI_CLASS_INDEX[orig]
    # Every instance pixel carries its class in the semantic map; no instance outside Car/Van.
    np.testing.assert_array_equal(semantic[instances > 0], instances[instances > 0] // 1000)
    assert not np.isin(semantic[instances == 0], [12, 13]).any()


def test_motgt_dims_are_reordered_and_boxes_match_projections(reference_tree):
    root, _ = reference_tree
    motgt = root / "vkitti_1.3.1_motgt" / "0006_30-deg-right.txt"
    header, first = motgt.read_text().splitlines()[:2]
    cols = dict(zip(header.split(), first.split(), strict=True))
    obj = parse_motgt(motgt)[43][0]
    # Files store w3d h3d l3d; records hold (l, h, w).
    assert obj.dims == (float(cols["l3d"]), float(cols["h3d"]), float(cols["w3d"]))
    assert obj.box2d == tuple(float(cols[c]) for c in "ltrb")
    assert (obj.truncr, obj.occupr) == (float(cols["truncr"]), float(cols["occupr"]))
    k = VKITTI_INTRINSICS
    for o in parse_motgt(motgt)[43]:
        # Observation angle convention and projected 3D box == stored 2D box (when not truncated).
        alpha = math.remainder(o.ry - math.atan2(o.location[0], o.location[2]), 2 * math.pi)
        assert math.isclose(o.alpha, alpha, abs_tol=2e-6)
        l, h, w = o.dims
        corners = np.array([[a, b, c] for a in (-0.5, 0.5) for b in (-0.5, 0.5) for c in (-0.5, 0.5)])
        cos, sin = math.cos(o.ry), math.sin(o.ry)
        rot = np.array([[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]])
        pts = corners * [l, h, w] @ rot.T + np.array(o.center)
        u, v = k.fx * pts[:, 0] / pts[:, 2] + k.cx, k.fy * pts[:, 1] / pts[:, 2] + k.cy
        if o.truncr == 0:
            np.testing.assert_allclose(o.box2d, [u.min(), v.min(), u.max(), v.max()], atol=1.0)


def test_reference_fixture_car_sits_under_the_edit_example_point(reference_tree):
    root, _ = reference_tree
    (record,) = read_frames(root)
    k = record.intrinsics
    centres = {o.track_id: o.center for o in record.objects}
    uv = {t: (k.fx * c[0] / c[2] + k.cx, k.fy * c[1] / c[2] + k.cy) for t, c in centres.items()}
    nearest = min(uv, key=lambda t: math.dist(uv[t], (552, 251)))
    assert nearest == 0 and math.dist(uv[0], (552, 251)) < 2.0


def test_small_sequence_rescales_intrinsics_and_keeps_frame_order(small_tree):
    root, truth = small_tree
    records = read_frames(root)
    assert [r.frame for r in records] == [0, 1, 2]
    assert records[0].intrinsics == VKITTI_INTRINSICS.resized(64, 32)
    for record, expected in zip(records, truth, strict=True):
        assert load_rgb(record).shape == (32, 64, 3)
        np.testing.assert_array_equal(load_semantic(record), expected.semantic)
        np.testing.assert_array_equal(load_instances(record), expected.instances)
        assert record.objects == expected.objects
    # The camera advances 0.8 m per frame: world->camera translations differ accordingly.
    t = [np.linalg.inv(r.extrinsics_matrix())[:3, 3] for r in records]
    np.testing.assert_allclose(np.diff([p[2] for p in t]), [0.8, 0.8], atol=1e-6)
    # The fixture's first frame shows every class of the list.
    assert np.unique(load_semantic(records[0])).tolist() == list(range(len(VKITTI_CLASSES)))


def test_subsets_and_missing_modalities(small_tree):
    root, _ = small_tree
    assert read_frames(root, worlds=["0001"], variations=["clone"])[0].key == "vkitti1/0001/clone/00000"
    with pytest.raises(FileNotFoundError, match="0002"):
        read_frames(root, worlds=["0002"])
    with pytest.raises(MissingDataError, match="vkitti_1.3.1_rgb"):
        read_frames(root / "nowhere")
    for sub in ("vkitti_1.3.1_depthgt", "vkitti_1.3.1_motgt", "vkitti_1.3.1_extrinsicsgt"):
        path = root / sub
        path.rename(root / f"{sub}.off")
    records = read_frames(root, annotations=False)
    assert records[0].depth_path is None and records[0].objects == () and records[0].extrinsics is None
    with pytest.raises(DataFormatError, match="no depth"):
        load_depth(records[0])
    with pytest.raises(FileNotFoundError, match="motgt"):
        read_frames(root)


def test_unknown_scenegt_colour_names_file_colour_and_count(small_tree):
    root, _ = small_tree
    record = read_frames(root)[1]
    image = np.asarray(Image.open(record.semantic_path)).copy()
    image[:3, :4] = (1, 2, 3)
    Image.fromarray(image).save(record.semantic_path)
    with pytest.raises(DataFormatError) as info:
        load_semantic(record)
    message = str(info.value)
    assert str(record.semantic_path) in message and "rgb(1, 2, 3) x 12 px" in message
    assert "scenegt_rgb_encoding.txt" in message


def test_encoding_file_errors(tmp_path):
    path = tmp_path / "enc.txt"
    path.write_text("Category(:id) r g b\nSky 90 200 255\nCar:0 90 200 255\n")
    with pytest.raises(DataFormatError, match=r"enc.txt:3: colour \(90, 200, 255\) already used on line 2"):
        parse_encoding(path)
    path.write_text("Category(:id) r g b\nPlanet 1 2 3\n")
    with pytest.raises(DataFormatError, match="enc.txt:2: unknown category 'Planet'"):
        parse_encoding(path)
    path.write_text("Category r g b\nSky 90 200 255\n")
    with pytest.raises(DataFormatError, match="enc.txt:1: .*header"):
        parse_encoding(path)


@pytest.mark.parametrize("ending", ["0 0 0 1", "0 0.1 0.2 1"])
def test_extrinsics_header_wording_of_published_files_is_accepted(tmp_path, ending):
    """Published extrinsicsgt files word the header's last four columns differently: the data rows are
    validated (count, numbers, last row 0 0 0 1), not that wording."""
    path = tmp_path / "0001_clone.txt"
    head = "frame r1,1 r1,2 r1,3 t1 r2,1 r2,2 r2,3 t2 r3,1 r3,2 r3,3 t3"
    path.write_text(f"{head} {ending}\n0 1 0 0 0.5 0 1 0 1.5 0 0 1 -2 0 0 0 1\n")
    expected = (1.0, 0.0, 0.0, 0.5, 0.0, 1.0, 0.0, 1.5, 0.0, 0.0, 1.0, -2.0, 0.0, 0.0, 0.0, 1.0)
    assert parse_extrinsics(path)[0] == expected
    path.write_text(f"{head} {ending}\n0 1 0 0 0.5 0 1 0 1.5 0 0 1 -2 0 0.1 0.2 1\n")
    with pytest.raises(DataFormatError, match=r"0001_clone.txt:2: last matrix row must be 0 0 0 1"):
        parse_extrinsics(path)
    path.write_text(f"frame {head[6:].replace('t3', 'z3')} {ending}\n")
    with pytest.raises(DataFormatError, match=r"0001_clone.txt:1: extrinsics file header must be 'frame r1,1 .* t3 "
                                              r"followed by 4 more columns'"):
        parse_extrinsics(path)
    path.write_text(f"{head} 0 0 1\n")  # a column short
    with pytest.raises(DataFormatError, match="0001_clone.txt:1: extrinsics file header"):
        parse_extrinsics(path)


def test_malformed_motgt_line_names_file_and_line(small_tree):
    root, _ = small_tree
    motgt = root / "vkitti_1.3.1_motgt" / "0001_clone.txt"
    lines = motgt.read_text().splitlines()
    assert lines[0].split() == list(MOTGT_HEADER)
    fields = lines[2].split()
    fields[10] = "wide"  # w3d
    motgt.write_text("\n".join([*lines[:2], " ".join(fields), *lines[3:]]) + "\n")
    expected = r"0001_clone.txt:3: column 11 \('w3d'\): expected a number, got 'wide'"
    with pytest.raises(DataFormatError, match=expected):
        read_frames(root)
    motgt.write_text("\n".join([*lines[:3], "0 1 Car", *lines[3:]]) + "\n")
    with pytest.raises(DataFormatError, match="0001_clone.txt:4: motgt file line has 3 fields, expected 25"):
        read_frames(root)


def test_unreadable_and_missing_images(small_tree):
    root, _ = small_tree
    records = read_frames(root)
    records[0].rgb_path.write_bytes(b"\x89PNG\r\n\x1a\nnot really")
    with pytest.raises(DataFormatError, match=str(records[0].rgb_path)):
        load_rgb(records[0])
    records[1].depth_path.unlink()
    with pytest.raises(FileNotFoundError, match=str(records[1].depth_path)):
        load_depth(records[1])
    # A depth map saved as 8-bit is a format error, not silently rescaled.
    Image.fromarray(np.zeros((32, 64), np.uint8)).save(records[2].depth_path)
    with pytest.raises(DataFormatError, match="16-bit"):
        load_depth(records[2])
    # Label images must have the sequence's image size.
    Image.fromarray(np.zeros((10, 12, 3), np.uint8)).save(records[2].semantic_path)
    with pytest.raises(DataFormatError, match="image is 12x10, expected 64x32"):
        load_semantic(records[2])


def _obj(truncr: float, occupr: float, occluded: int | None = None) -> ObjectAnnotation:
    return ObjectAnnotation(0, "Car", (0, 0, 10, 10), (4, 1.5, 1.8), (0, 1.6, 10), 0.0, 0.0, truncr, occupr,
                            occluded=occluded)


@pytest.mark.parametrize(
    ("pixels", "truncr", "occupr", "occluded", "keep"),
    [(257, 0.0, 1.0, None, True), (256, 0.0, 1.0, None, False), (5000, 0.69, 0.31, None, True),
     (5000, 0.7, 1.0, None, False),
     # occupr is visible / box area (an unoccluded car: about 0.8), so 70 % occlusion is occupr = 0.3 * 0.8
     (5000, 0.0, 0.239, None, False), (5000, 0.0, 0.241, None, True), (5000, 0.0, 0.3, None, True),
     (5000, 0.0, 0.241, 1, True), (5000, 0.0, 0.85, 0, True),
     # the occluded flag, where the format has it: "largely occluded" is dropped whatever occupr says
     (5000, 0.0, 0.85, 2, False)],
)  # fmt: skip
def test_paper_object_filter_thresholds(pixels, truncr, occupr, occluded, keep):
    assert paper_object_filter(_obj(truncr, occupr, occluded), pixels) is keep


def test_fixture_occupr_is_box_occupancy_and_flag_follows_visible_share(tmp_path):
    """As in the real files: occupr = visible pixels / box area (an unoccluded car well below 1), while the
    occluded flag says how much of the car itself is hidden (0 for the unoccluded cars)."""
    truth = write_vkitti1_fixture(tmp_path, frames=(3,), size=(310, 94))  # frame 3: the van is half hidden
    (record,) = read_frames(tmp_path)
    ids = truth[0].instances
    flags = {}
    for obj in record.objects:
        visible = int(((ids > 0) & (ids % 1000 == obj.track_id + 1)).sum())
        left, top, right, bottom = obj.box2d
        assert obj.occupr == pytest.approx(visible / ((right - left + 1) * (bottom - top + 1)), abs=1e-6)
        flags[obj.track_id] = obj.occluded
        if obj.occluded == 0 and obj.truncr == 0:
            assert 0.6 <= obj.occupr <= 0.95
    assert flags[0] == 0 and flags[3] >= 1  # track 0 is in the clear, the van (track 3) is behind track 1


def test_occlusion_estimate_reads_occupr_as_box_occupancy():
    from sdn3d.data.vkitti1 import UNOCCLUDED_OCCUPR, occlusion_estimate

    assert occlusion_estimate(_obj(0.0, UNOCCLUDED_OCCUPR)) == 0.0  # a typical unoccluded car
    assert occlusion_estimate(_obj(0.0, 0.95)) == 0.0  # boxier than typical: still unoccluded, clipped at 0
    assert occlusion_estimate(_obj(0.0, 0.4)) == pytest.approx(0.5)
    assert occlusion_estimate(_obj(0.0, 0.0)) == 1.0


def test_paper_split_first_or_last_80_percent_per_sequence(tmp_path):
    write_vkitti1_fixture(tmp_path, world="0001", variation="clone", frames=range(10))
    write_vkitti1_fixture(tmp_path, world="0002", variation="fog", frames=range(5))
    frames = read_frames(tmp_path, annotations=False)
    train, test = paper_split(frames, "train"), paper_split(frames, "test")
    by_world = {w: [r.frame for r in train if r.world == w] for w in ("0001", "0002")}
    assert by_world == {"0001": list(range(8)), "0002": list(range(4))}
    assert [(r.world, r.frame) for r in test] == [("0001", 8), ("0001", 9), ("0002", 4)]
    last = paper_split(frames, "train", first=False)
    assert [r.frame for r in last if r.world == "0001"] == list(range(2, 10))
    assert {r.key for r in last} | {r.key for r in paper_split(frames, "test", first=False)} == {
        r.key for r in frames
    }
    with pytest.raises(ValueError, match="part"):
        paper_split(frames, "val")


def test_reader_decodes_a_full_resolution_frame_without_per_pixel_python(reference_tree):
    """The instance decode is vectorised: the Python calls it makes on a 1242x375 frame (466k pixels) are counted
    (cProfile), not timed, so the check does not depend on the machine or its load (its speed is a benchmark's)."""
    import cProfile
    import pstats

    root, _ = reference_tree
    (record,) = read_frames(root)
    profiler = cProfile.Profile()
    profiler.runcall(load_instances, record)
    calls = pstats.Stats(profiler).total_calls
    assert calls < 1242 * 375 // 100, calls


def test_paths_follow_the_official_layout(reference_tree):
    root, _ = reference_tree
    (record,) = read_frames(root)
    paths = {"rgb": record.rgb_path, "scenegt": record.semantic_path, "depth": record.depth_path,
             "enc": record.aux_path("encoding")}  # fmt: skip
    rel = {k: Path(p).relative_to(root).as_posix() for k, p in paths.items()}
    assert rel == {
        "rgb": "vkitti_1.3.1_rgb/0006/30-deg-right/00043.png",
        "scenegt": "vkitti_1.3.1_scenegt/0006/30-deg-right/00043.png",
        "depth": "vkitti_1.3.1_depthgt/0006/30-deg-right/00043.png",
        "enc": "vkitti_1.3.1_scenegt/0006_30-deg-right_scenegt_rgb_encoding.txt",
    }


# -- issue 20: the size of a sequence, bad rows and the skip policy ------------------------------------------------
@pytest.mark.parametrize("fault", ["wrong_size", "zero_byte", "corrupt"])
def test_bad_first_frame_is_the_file_named(tmp_path, fault):
    from faults.data import corrupt_png, wrong_size_png, zero_byte

    from sdn3d.data.errors import SkipLog

    write_vkitti1_fixture(tmp_path, frames=(0, 1, 2, 3))
    good = read_frames(tmp_path)
    first = good[0].rgb_path
    {"wrong_size": lambda p: wrong_size_png(p, (40, 20)), "zero_byte": zero_byte, "corrupt": corrupt_png}[fault](first)
    with pytest.raises(DataFormatError, match=str(first)) as info:
        read_frames(tmp_path)  # the sequence's size is the one its frames agree on, not frame 0's
    assert str(good[1].rgb_path) not in str(info.value)
    skip = SkipLog()
    records = read_frames(tmp_path, skip=skip)
    assert len(records) == 4 and skip.skipped_frames == {good[0].key} and skip.files == [str(first)]
    assert all(r.intrinsics == VKITTI_INTRINSICS.resized(64, 32) for r in records)
    assert load_rgb(records[1]).shape == (32, 64, 3)  # the good frames are not blamed


def test_nonpositive_dimensions_name_file_and_line_or_are_skipped(small_tree):
    from faults.data import bad_motgt_row, negative_dims

    from sdn3d.data.errors import SkipLog

    root, truth = small_tree
    motgt = root / "vkitti_1.3.1_motgt" / "0001_clone.txt"
    negative_dims(motgt, row=0, dims=(1.8, 0.0, 4.2))
    with pytest.raises(DataFormatError, match=r"0001_clone.txt:2: object dimensions must be positive, got length 4.2, "
                                              r"height 0, width 1.8"):
        read_frames(root)
    other = len(truth[0].objects)  # the first row of frame 1: its frame number can not even be read
    bad_motgt_row(motgt, row=other, column="frame", value="x")
    skip = SkipLog()
    records = read_frames(root, skip=skip)
    assert len(records[0].objects) == len(truth[0].objects) - 1
    assert len(records[1].objects) == len(truth[1].objects) - 1
    assert [(i.kind, i.line, i.frame) for i in skip.items] == [("object", 2, records[0].key),
                                                               ("object", other + 2, None)]
    assert skip.files == [f"{motgt}:2", f"{motgt}:{other + 2}"]
    # KITTI's DontCare rows carry -1 -1 -1 (no 3D box): not an error
    bad_motgt_row(motgt, row=other, column="frame", value="1")
    negative_dims(motgt, row=0, dims=(-1, -1, -1))
    bad_motgt_row(motgt, row=0, column="label", value="DontCare")
    assert len(read_frames(root)[0].objects) == len(truth[0].objects)


# -- issue 16, point 4: indexing at Virtual KITTI scale -------------------------------------------------------------
def test_fast_motgt_path_gives_the_checked_path_values(tmp_path, monkeypatch):
    """Well-formed files are converted in one pass; the result equals the column-by-column checked path."""
    import sdn3d.data.vkitti1 as vk1

    write_vkitti1_fixture(tmp_path, frames=(0, 1, 3, 7), size=(310, 94))
    motgt = tmp_path / "vkitti_1.3.1_motgt" / "0001_clone.txt"
    fast = vk1.parse_motgt(motgt)
    monkeypatch.setattr(vk1, "_motgt_values", lambda rows: None)
    checked = vk1.parse_motgt(motgt)
    assert fast == checked and sum(len(v) for v in fast.values()) >= 8
    assert all(type(o.track_id) is int and type(o.occluded) is int and type(o.moving) is bool
               for objs in fast.values() for o in objs)


@pytest.mark.parametrize(("column", "value", "message"), [
    ("occupr", "nan", r"0001_clone.txt:3: column 21 \('occupr'\): expected a finite number, got 'nan'"),
    ("tid", "1.5", r"0001_clone.txt:3: column 2 \('tid'\): expected an integer, got '1.5'"),
    ("moving", "maybe", r"0001_clone.txt:3: column 23 \('moving'\): expected a boolean"),
    ("x3d", "1,5", r"0001_clone.txt:3: column 14 \('x3d'\): expected a number, got '1,5'"),
])
def test_a_bad_value_in_a_large_file_still_names_file_line_and_column(tmp_path, column, value, message):
    from faults.data import bad_motgt_row

    write_vkitti1_fixture(tmp_path, frames=(0, 1, 2))
    bad_motgt_row(tmp_path / "vkitti_1.3.1_motgt" / "0001_clone.txt", row=1, column=column, value=value)
    with pytest.raises(DataFormatError, match=message):
        read_frames(tmp_path)


def test_png_sizes_read_from_the_header_agree_with_pillow(tmp_path):
    from sdn3d.data.imageio import _png_size, image_size

    arrays = {"rgb": np.zeros((7, 9, 3), np.uint8), "grey16": np.zeros((5, 4), np.uint16),
              "grey": np.zeros((3, 11), np.uint8)}
    for name, array in arrays.items():
        Image.fromarray(array).save(tmp_path / f"{name}.png")
        assert _png_size(tmp_path / f"{name}.png") == image_size(tmp_path / f"{name}.png") == array.shape[1::-1]
    Image.fromarray(arrays["rgb"]).convert("P").save(tmp_path / "palette.png")
    assert _png_size(tmp_path / "palette.png") == (9, 7)
    Image.fromarray(arrays["rgb"]).save(tmp_path / "photo.jpg")
    assert _png_size(tmp_path / "photo.jpg") is None and image_size(tmp_path / "photo.jpg") == (9, 7)
    data = bytearray((tmp_path / "rgb.png").read_bytes())
    data[20] ^= 1  # the height, without fixing the IHDR checksum: Pillow reads (and refuses) it
    (tmp_path / "bad_crc.png").write_bytes(bytes(data))
    assert _png_size(tmp_path / "bad_crc.png") is None
    with pytest.raises(DataFormatError, match="bad_crc.png"):
        image_size(tmp_path / "bad_crc.png")


def test_index_benchmark_tree_is_read_whole(tmp_path):
    """benchmarks/index_frames.py builds the release's tree (here at 1 %); read_frames indexes all of it."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "index_frames.py"
    spec = importlib.util.spec_from_file_location("index_bench", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert 10 * sum(module.WORLD_FRAMES.values()) == 21260  # 10 variations of each world
    frames = module.build_tree(tmp_path, objects=3, scale=0.01)
    records = read_frames(tmp_path)
    assert len(records) == frames == 10 * sum(max(1, round(n * 0.01)) for n in module.WORLD_FRAMES.values())
    assert all(len(r.objects) == 3 and r.intrinsics == VKITTI_INTRINSICS for r in records)
    assert records[0].semantic_path == records[0].instance_path is not None and records[0].depth_path is not None


def test_decode_benchmark_prints_what_it_measured(monkeypatch, capsys):
    """benchmarks/decode_frame.py times the full-resolution decode and says what it measured; a bad --runs is one
    line and exit 2."""
    import importlib.util
    import json
    import sys

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "decode_frame.py"
    spec = importlib.util.spec_from_file_location("decode_bench", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(sys, "argv", [str(path), "--runs", "1"])
    module.main()
    report = json.loads(capsys.readouterr().out)
    assert report["pixels"] == 1242 * 375 and len(report["runs_s"]) == 1 and report["median_s"] > 0
    assert 0 < report["python_calls_per_decode"] < report["pixels"] // 100
    monkeypatch.setattr(sys, "argv", [str(path), "--runs", "0"])
    with pytest.raises(SystemExit) as refused:
        module.main()
    assert refused.value.code == 2 and "--runs must be at least 1" in capsys.readouterr().err
