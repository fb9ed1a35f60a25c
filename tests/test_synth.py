"""Synthetic Virtual KITTI 1.3.1 generator: file tree, formats, consistency, determinism, edits."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import torch
from PIL import Image

from sdn3d.data.synth import BENCHMARK_NAME, MANIFEST_NAME, SynthConfig, generate_dataset
from sdn3d.data.synth.class_stats import STATISTICS_NAME
from sdn3d.data.synth.classes import CLASS_COLORS
from sdn3d.data.synth.clip import clip_near
from sdn3d.data.synth.writer import ENCODING_HEADER, EXTRINSICS_HEADER, MOTGT_HEADER
from sdn3d.math3d.camera import VKITTI_INTRINSICS

WORLD = "0001"
VARIATIONS = ("clone", "30-deg-left")
FRAMES, EDITS = 3, 2
WIDTH, HEIGHT = 312, 96


pytestmark = pytest.mark.usefixtures("one_torch_thread")


def _config(out: Path, **kw) -> SynthConfig:
    base = dict(
        output_dir=str(out),
        seed=3,
        image_size=(WIDTH, HEIGHT),
        worlds=(WORLD,),
        variations=VARIATIONS,
        frames_per_sequence=FRAMES,
        cars_per_frame=(10, 14),
        edit_pairs=EDITS,
        occluder_pairs=0,  # tests/test_occluder_removed.py covers those pairs
        workers=1,
        threads=1,
    )
    base.update(kw)
    return SynthConfig(**base)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return generate_dataset(_config(tmp_path_factory.mktemp("synth") / "data"))


def _motgt(root: Path, variation: str) -> list[dict]:
    lines = (root / "vkitti_1.3.1_motgt" / f"{WORLD}_{variation}.txt").read_text().splitlines()
    assert lines[0] == MOTGT_HEADER
    header = lines[0].split()
    return [dict(zip(header, line.split(), strict=True)) for line in lines[1:]]


def _extrinsics(root: Path, variation: str) -> dict[int, np.ndarray]:
    lines = (root / "vkitti_1.3.1_extrinsicsgt" / f"{WORLD}_{variation}.txt").read_text().splitlines()
    assert lines[0] == EXTRINSICS_HEADER
    out = {}
    for line in lines[1:]:
        values = line.split()
        out[int(values[0])] = np.array([float(v) for v in values[1:]]).reshape(4, 4)
    return out


def _encoding(root: Path, variation: str) -> dict[tuple[int, int, int], str]:
    path = root / "vkitti_1.3.1_scenegt" / f"{WORLD}_{variation}_scenegt_rgb_encoding.txt"
    lines = path.read_text().splitlines()
    assert lines[0] == ENCODING_HEADER
    table = {}
    for line in lines[1:]:
        name, r, g, b = line.split()
        color = (int(r), int(g), int(b))
        assert color not in table, f"duplicate colour {color} in {path.name}"
        table[color] = name
    return table


def _project_full(center: np.ndarray) -> np.ndarray:
    k = VKITTI_INTRINSICS
    return np.array([k.fx * center[0] / center[2] + k.cx, k.fy * center[1] / center[2] + k.cy])


def _center(row: dict) -> np.ndarray:
    return np.array([float(row["x3d"]), float(row["y3d"]) - float(row["h3d"]) / 2, float(row["z3d"])])


def test_tree_is_exactly_vkitti_131(dataset: Path) -> None:
    frames = [f"{i:05d}.png" for i in range(FRAMES + EDITS)]
    expected = {BENCHMARK_NAME, MANIFEST_NAME, STATISTICS_NAME, "_SUCCESS"}
    for v in VARIATIONS:
        for kind in ("rgb", "scenegt", "depthgt"):
            expected |= {f"vkitti_1.3.1_{kind}/{WORLD}/{v}/{f}" for f in frames}
        expected |= {
            f"vkitti_1.3.1_motgt/{WORLD}_{v}.txt",
            f"vkitti_1.3.1_extrinsicsgt/{WORLD}_{v}.txt",
            f"vkitti_1.3.1_scenegt/{WORLD}_{v}_scenegt_rgb_encoding.txt",
        }
    found = {p.relative_to(dataset).as_posix() for p in dataset.rglob("*") if p.is_file()}
    assert found == expected
    assert [p.name for p in dataset.parent.iterdir()] == [dataset.name]  # no temporary siblings left


def test_scenegt_colours_depth_and_boxes(dataset: Path) -> None:
    for v in VARIATIONS:
        table = _encoding(dataset, v)
        for name, color in CLASS_COLORS.items():
            assert table[color] == name
        instances = {c: n for c, n in table.items() if ":" in n}
        assert instances and all(n.split(":")[0] in ("Car", "Van") for n in instances.values())
        rows = _motgt(dataset, v)
        for frame in range(FRAMES + EDITS):
            scenegt = np.asarray(Image.open(dataset / "vkitti_1.3.1_scenegt" / WORLD / v / f"{frame:05d}.png"))
            assert scenegt.shape == (HEIGHT, WIDTH, 3) and scenegt.dtype == np.uint8
            colors, counts = np.unique(scenegt.reshape(-1, 3), axis=0, return_counts=True)
            assert all(tuple(c) in table for c in colors.tolist()), "scenegt colour missing from the encoding"
            depth_img = Image.open(dataset / "vkitti_1.3.1_depthgt" / WORLD / v / f"{frame:05d}.png")
            depth = np.asarray(depth_img)
            assert depth_img.mode.startswith("I;16") and depth.dtype == np.uint16 and depth.shape == (HEIGHT, WIDTH)
            sky = (scenegt == CLASS_COLORS["Sky"]).all(-1)
            assert (depth[sky] == 65535).all() and (depth[~sky] > 0).all()
            # Surfaces beyond 655.35 m (the far ground at the horizon) are clipped to 65535 too: rare.
            assert (depth[~sky] == 65535).mean() < 0.01
            by_tid = {int(r["tid"]): r for r in rows if int(r["frame"]) == frame}
            for color, count in zip(colors.tolist(), counts.tolist(), strict=True):
                name = table[tuple(color)]
                if ":" not in name:
                    continue
                tid = int(name.split(":")[1])
                assert tid in by_tid, f"frame {frame}: instance {name} visible but not in motgt"
                r = by_tid[tid]
                ys, xs = np.nonzero((scenegt == color).all(-1))
                # The 2D box is the box of the visible instance pixels.
                assert (int(r["l"]), int(r["t"]), int(r["r"]), int(r["b"])) == (
                    xs.min(),
                    ys.min(),
                    xs.max(),
                    ys.max(),
                )
                assert r["orig_label"] == name.split(":")[0] and count > 0
                # occupr is the real files' quantity: visible pixels / the 2D box's pixel count.
                area = (xs.max() - xs.min() + 1) * (ys.max() - ys.min() + 1)
                assert float(r["occupr"]) == pytest.approx(count / area, abs=1e-6)


def test_unoccluded_cars_read_occupr_as_in_real_files(dataset: Path) -> None:
    """An unoccluded car covers about 0.75-0.85 of its box in real files (0.7-0.93 here), not 1.0; the
    occluded flag follows the true occlusion, so unoccluded cars keep flag 0 and occluded ones get 1 or 2.
    (Boxy vans seen from behind fill up to about 0.96 of their box.)"""
    rows = [r for v in VARIATIONS for r in _motgt(dataset, v)]
    clear = [r for r in rows
             if r["occluded"] == "0" and r["truncated"] == "0" and (int(r["b"]) - int(r["t"]) + 1) >= 12]
    cars = [float(r["occupr"]) for r in clear if r["orig_label"] == "Car"]
    assert len(cars) >= 5 and all(0.6 <= v <= 0.95 for v in cars)
    assert all(0.6 <= float(r["occupr"]) < 0.99 for r in clear)
    assert any(r["occluded"] in ("1", "2") for r in rows)


def test_motgt_values(dataset: Path) -> None:
    only_short = 0  # rows that are DontCare by the height rule alone
    for v in VARIATIONS:
        rows = _motgt(dataset, v)
        poses = _extrinsics(dataset, v)
        assert rows and set(poses) == set(range(FRAMES + EDITS))
        for r in rows:
            left, top, right, bottom = (int(r[k]) for k in "ltrb")
            assert 0 <= left <= right < WIDTH and 0 <= top <= bottom < HEIGHT
            x, y, z, ry = (float(r[k]) for k in ("x3d", "y3d", "z3d", "ry"))
            alpha = math.remainder(ry - math.atan2(x, z), 2 * math.pi)
            assert abs(math.remainder(float(r["alpha"]) - alpha, 2 * math.pi)) < 2e-6
            assert 0.0 < float(r["occupr"]) <= 1.0 and 0.0 <= float(r["truncr"]) <= 1.0
            assert min(float(r[k]) for k in ("w3d", "h3d", "l3d")) > 0
            assert float(r["l3d"]) > float(r["w3d"])  # the file's order is w3d h3d l3d
            # Cars stand on the road: y3d is the ground's height in the camera frame (no pitch / roll).
            assert y == pytest.approx(poses[int(r["frame"])][1, 3], abs=2e-6)
            assert r["rx"] == r["rz"] == "0.000000" and r["moving"] in ("0", "1")
            short = (int(r["b"]) - int(r["t"]) + 1) * 375 / HEIGHT < 25  # the real files' height rule
            heavy = r["truncated"] == "2" or r["occluded"] == "2" or short
            assert r["label"] == ("DontCare" if heavy else r["orig_label"])
            only_short += short and r["truncated"] != "2" and r["occluded"] != "2"
            assert r["orig_label"] in ("Car", "Van")
    assert only_short > 0  # the fixture exercises the height rule


def test_sequences_are_consistent(dataset: Path) -> None:
    """Same tids across frames and variations; parked cars stay put in the world, moving ones move."""
    world_pos: dict[str, dict[tuple[int, int], np.ndarray]] = {}
    for v in VARIATIONS:
        poses = _extrinsics(dataset, v)
        world_pos[v] = {}
        for r in _motgt(dataset, v):
            frame = int(r["frame"])
            if frame >= FRAMES:
                continue
            bottom = np.array([float(r[k]) for k in ("x3d", "y3d", "z3d")])
            rot, t = poses[frame][:3, :3], poses[frame][:3, 3]
            world_pos[v][int(r["tid"]), frame] = rot.T @ (bottom - t)
            assert np.linalg.det(rot) == pytest.approx(1.0, abs=1e-6)
        camera_z = [(-poses[f][:3, :3].T @ poses[f][:3, 3])[2] for f in range(FRAMES)]
        assert np.all(np.diff(camera_z) > 0.5)  # the camera drives forward
    moving = {int(r["tid"]): r["moving"] == "1" for r in _motgt(dataset, "clone")}
    checked = 0
    for (tid, frame), pos in world_pos["clone"].items():
        nxt = world_pos["clone"].get((tid, frame + 1))
        if nxt is not None:
            assert (np.linalg.norm(nxt - pos) > 0.1) == moving[tid]
            checked += 1
        other = world_pos["30-deg-left"].get((tid, frame))
        if other is not None:  # the same car at the same world place in another variation
            np.testing.assert_allclose(other, pos, atol=1e-4)
    assert checked > 0


def test_determinism(dataset: Path, tmp_path: Path) -> None:
    """Same seed, same bytes, whether the sequences are rendered in this process or in two workers."""
    again = generate_dataset(_config(tmp_path / "again", workers=2))
    files = sorted(p.relative_to(dataset) for p in dataset.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(again) for p in again.rglob("*") if p.is_file())
    for rel in files:
        assert (dataset / rel).read_bytes() == (again / rel).read_bytes(), f"{rel} differs between runs"


def test_vkitti1_reader_loads_it(dataset: Path) -> None:
    vkitti1 = pytest.importorskip("sdn3d.data.vkitti1")
    records = vkitti1.read_frames(dataset)
    assert len(records) == len(VARIATIONS) * (FRAMES + EDITS)
    record = records[0]
    assert record.intrinsics == VKITTI_INTRINSICS.resized(WIDTH, HEIGHT)
    semantic, instances = vkitti1.load_semantic(record), vkitti1.load_instances(record)
    depth = vkitti1.load_depth(record)
    assert semantic.shape == instances.shape == depth.shape == (HEIGHT, WIDTH)
    tids = {o.track_id for o in record.objects}
    seen = {int(i % 1000) - 1 for i in np.unique(instances) if i > 0}
    assert seen == tids


def test_edit_benchmark_matches_targets(dataset: Path) -> None:
    edits = pytest.importorskip("sdn3d.data.edit_benchmark")
    entries = edits.load_edit_benchmark(dataset / BENCHMARK_NAME)
    assert len(entries) == len(VARIATIONS) * EDITS
    assert sum(len(e.operations) for e in entries) > 0
    for entry in entries:
        assert entry.world == WORLD and entry.source_frame < FRAMES <= entry.target_frame
        rows = _motgt(dataset, entry.variation)
        src = {int(r["tid"]): r for r in rows if int(r["frame"]) == entry.source_frame}
        tgt = {int(r["tid"]): r for r in rows if int(r["frame"]) == entry.target_frame}
        poses = _extrinsics(dataset, entry.variation)
        np.testing.assert_array_equal(poses[entry.source_frame], poses[entry.target_frame])
        for op in entry.operations:
            # The operation's object: the source car whose projected 3D centre is at `from`.
            tid = min(src, key=lambda t: np.linalg.norm(_project_full(_center(src[t])) - op.from_uv))
            assert np.abs(_project_full(_center(src[tid])) - op.from_uv).max() <= 0.051
            if op.kind == "delete":
                assert tid not in tgt
                continue
            before, after = _center(src[tid]), _center(tgt[tid])
            assert float(tgt[tid]["y3d"]) == pytest.approx(float(src[tid]["y3d"]), abs=1e-6)  # still on the ground
            delta = math.remainder(float(tgt[tid]["ry"]) - float(src[tid]["ry"]) - op.ry, 2 * math.pi)
            assert abs(delta) < 2e-6
            assert np.linalg.norm(before) / np.linalg.norm(after) == pytest.approx(op.zoom, abs=6e-4)
            if op.to_uv is None:
                np.testing.assert_allclose(after, before, atol=1e-5)
            else:
                assert np.abs(_project_full(after) - op.to_uv).max() <= 0.051
                top, left, bottom, right = op.roi
                assert top <= op.to_uv[1] <= bottom and left <= op.to_uv[0] <= right


def test_edit_delete_share_makes_every_pair_a_delete_and_its_default_the_pairs_drawn_before(
        dataset: Path, tmp_path: Path) -> None:
    """``edit_delete_share=1``: every operation of every edit pair deletes its car, and the target frame lacks it
    (a benchmark of deletes alone); 0 makes none; a config that does not name it has the default 0.15, which
    drew the mixed pairs of every earlier tree."""
    from sdn3d.data.edit_benchmark import load_edit_benchmark
    from sdn3d.data.synth.edits import DEFAULT_DELETE_SHARE

    assert _config(tmp_path / "d").edit_delete_share == DEFAULT_DELETE_SHARE == 0.15
    deletes = generate_dataset(_config(tmp_path / "deletes", variations=("clone",), edit_pairs=4,
                                       edit_delete_share=1.0))
    entries = load_edit_benchmark(deletes / BENCHMARK_NAME)
    ops = [op for e in entries for op in e.operations]
    assert len(entries) == 4 and len(ops) >= 4 and all(op.kind == "delete" for op in ops)
    rows = _motgt(deletes, "clone")
    for entry in entries:  # each deleted car (the source car whose projected centre is at `from`) is gone
        src = {int(r["tid"]): r for r in rows if int(r["frame"]) == entry.source_frame}
        tgt = {int(r["tid"]) for r in rows if int(r["frame"]) == entry.target_frame}
        for op in entry.operations:
            tid = min(src, key=lambda t: np.linalg.norm(_project_full(_center(src[t])) - op.from_uv))
            assert tid not in tgt
    default_ops = [op.kind for e in load_edit_benchmark(dataset / BENCHMARK_NAME) for op in e.operations]
    assert "modify" in default_ops
    none = generate_dataset(_config(tmp_path / "none", variations=("clone",), edit_pairs=4, edit_delete_share=0.0))
    assert all(op.kind == "modify" for e in load_edit_benchmark(none / BENCHMARK_NAME) for op in e.operations)


SMALL = dict(variations=("clone",), frames_per_sequence=1, edit_pairs=0, image_size=(64, 24))


def test_overwrite_replaces_only_an_earlier_dataset(tmp_path: Path) -> None:
    """overwrite=true replaces a previous dataset of the generator (it holds the manifest), never an
    unrelated non-empty folder (issue 20: it used to delete any folder, exit 0)."""
    from sdn3d.errors import UserInputError

    out = tmp_path / "busy"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    with pytest.raises(FileExistsError, match="overwrite=true"):
        generate_dataset(_config(out, **SMALL))
    with pytest.raises(UserInputError, match=f"{out}.*holds no {MANIFEST_NAME}.*choose another output_dir"):
        generate_dataset(_config(out, overwrite=True, **SMALL))
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"] and (out / "keep.txt").read_text() == "mine"
    data = generate_dataset(_config(tmp_path / "data", **SMALL))
    (data / "extra.txt").write_text("from an older run")
    generate_dataset(_config(data, overwrite=True, **SMALL))
    assert not (data / "extra.txt").exists() and (data / "_SUCCESS").is_file() and (data / MANIFEST_NAME).is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["busy", "data"]  # no staging trees left


@pytest.mark.parametrize(
    "case, message",
    [
        ("cwd", "is the current working directory"),
        ("cwd_parent", "is a parent of the current working directory"),
        ("home", "is the home directory"),
        ("home_parent", "is a parent of the home directory"),
        ("empty_cwd", "is the current working directory"),
    ],
)
def test_never_replaces_the_working_or_home_directory(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                      case: str, message: str) -> None:
    """Not even with overwrite=true and the generator's marker in it: replacing removes the directory itself."""
    from sdn3d.errors import UserInputError

    work = tmp_path / "top" / "work"
    (tmp_path / "elsewhere").mkdir(parents=True)
    work.mkdir(parents=True)
    for d in (work, work.parent):
        (d / MANIFEST_NAME).write_text("{}")
        (d / "notes.txt").write_text("mine")
    if case.startswith("home"):
        monkeypatch.setenv("HOME", str(work))
        monkeypatch.chdir(tmp_path / "elsewhere")
        out = str(work if case == "home" else work.parent)
    else:
        monkeypatch.chdir(work)
        out = "." if case != "cwd_parent" else ".."
    if case == "empty_cwd":  # an empty directory too: the shell would be left in a deleted directory
        monkeypatch.chdir(tmp_path / "elsewhere")
        out = "."
    with pytest.raises(UserInputError, match=message) as info:
        generate_dataset(_config(out, overwrite=True, **SMALL))
    assert str(Path(out).resolve()) in str(info.value) and "choose" in str(info.value)
    assert isinstance(info.value, FileExistsError)
    assert (work / "notes.txt").is_file() and (work.parent / "notes.txt").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["elsewhere", "top"]
    assert sorted(p.name for p in work.parent.iterdir()) == sorted([MANIFEST_NAME, "notes.txt", "work"])


def test_never_replaces_the_root() -> None:
    from sdn3d.io import OutputDirError, check_output_dir, refuse_unsafe_output_dir

    with pytest.raises(OutputDirError, match="'/' is the file-system root"):
        refuse_unsafe_output_dir("/")
    with pytest.raises(OutputDirError, match="file-system root"):
        check_output_dir("/", MANIFEST_NAME, overwrite=True)


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"worlds": ("1",)}, "4-digit"),
        ({"variations": ("snow",)}, "variations"),
        ({"cars_per_frame": (5, 2)}, "cars_per_frame"),
        ({"image_size": (4, 4)}, "image_size"),
        ({"frames_per_sequence": 0}, "frames_per_sequence"),
        # Badly typed settings name their field (issue 20: raw TypeError / ValueError tracebacks before).
        ({"frames_per_sequence": "abc"}, r"frames_per_sequence must be an integer >= 1, got 'abc' \(str\)"),
        ({"frames_per_sequence": 2.5}, r"frames_per_sequence must be an integer >= 1, got 2.5 \(float\)"),
        ({"frames_per_sequence": True}, "frames_per_sequence must be an integer"),
        ({"image_size": ("a", "b")}, r"image_size must be \[width, height\]: a list of two integers"),
        ({"image_size": 5}, "image_size must be"),
        ({"image_size": (64,)}, "image_size must be"),
        ({"cars_per_frame": ("a", 3)}, "cars_per_frame must be"),
        ({"cars_per_frame": (-1, 3)}, "cars_per_frame must be"),
        ({"edit_pairs": -1}, "edit_pairs must be >= 0, got -1"),
        ({"max_edit_operations": "x"}, "max_edit_operations must be an integer >= 1"),
        ({"edit_delete_share": 1.5}, r"edit_delete_share must be a number in \[0, 1\], got 1.5"),
        ({"edit_delete_share": "all"}, r"edit_delete_share must be a number in \[0, 1\]"),
        ({"edit_delete_share": True}, r"edit_delete_share must be a number in \[0, 1\]"),
        ({"workers": -2}, "workers must be >= 1, got -2"),
        ({"threads": "abc"}, "threads must be an integer >= 1"),
        ({"seed": "abc"}, "seed must be an integer"),
        ({"seed": 1.5}, "seed must be an integer"),
        ({"overwrite": "maybe"}, "overwrite must be true or false"),
        ({"worlds": "0001"}, "worlds must be a list"),
        ({"worlds": ("0001", None)}, "worlds must be a list of names"),
        ({"variations": "clone"}, "variations must be a list"),
        ({"output_dir": None}, "output_dir must be a non-empty path"),
        ({"output_dir": ""}, "output_dir must be a non-empty path"),
        ({"camera_height": -1.0}, "camera_height must be null or metres"),
        ({"camera_pitch": 0.5}, r"camera_pitch must be radians in \[-0.3, 0.3\]"),
        ({"camera_pitch": "down"}, "camera_pitch must be radians"),
    ],
)
def test_config_validation(tmp_path: Path, bad: dict, message: str) -> None:
    from sdn3d.data.synth.generate import SynthConfigError
    from sdn3d.errors import UserInputError

    assert issubclass(SynthConfigError, UserInputError)
    with pytest.raises(SynthConfigError, match=message):
        _config(tmp_path / "x", **bad)


def test_config_normalises_integers(tmp_path: Path) -> None:
    cfg = _config(tmp_path / "x", image_size=[np.int64(64), 24], frames_per_sequence=np.int32(2), seed=-3,
                  worlds=["0001", 1234], cars_per_frame=[1, 2])
    assert cfg.image_size == (64, 24) and type(cfg.image_size[0]) is int
    assert cfg.frames_per_sequence == 2 and type(cfg.frames_per_sequence) is int and cfg.seed == -3
    assert cfg.worlds == ("0001", "1234") and cfg.cars_per_frame == (1, 2)


@pytest.mark.parametrize(
    "override, message",
    [
        ("frames_per_sequence=abc", "frames_per_sequence must be an integer >= 1, got 'abc' (str)"),
        ("image_size=[a,b]", "image_size must be [width, height]: a list of two integers, got ['a', 'b']"),
        ("frames_per_sequence=-3", "frames_per_sequence must be >= 1, got -3"),
        ("overwrite=maybe", "overwrite must be true or false"),
        ("output_dir=null", "output_dir must be a non-empty path"),
    ],
)
def test_cli_rejects_badly_typed_settings_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture,
                                                      monkeypatch: pytest.MonkeyPatch, override: str,
                                                      message: str) -> None:
    """Through ``@hydra.main`` as the console script runs it: exit status 2, one line, nothing written."""
    hydra = pytest.importorskip("hydra")
    monkeypatch.chdir(tmp_path)  # output_dir=null used to become <cwd>/None: keep the checkout clean
    import sdn3d.cli.synth as synth
    from sdn3d.cli._config import CONFIG_DIR

    with hydra.initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        cfg = hydra.compose(config_name="synth", overrides=[f"output_dir={tmp_path / 'd'}", override])
    with pytest.raises(SystemExit) as info:
        synth.main(cfg)
    assert info.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sdn3d-synth: error: ") and message in lines[0], lines
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_clip_near_keeps_the_front_part_with_its_winding() -> None:
    verts = torch.tensor(
        [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 3.0],
            [0.0, 1.0, 3.0],  # one vertex behind
            [0.0, 0.0, 2.0],
            [1.0, 0.0, -2.0],
            [0.0, 1.0, -2.0],  # two behind
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],  # in front
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 1.0, -1.0],
        ]
    )  # behind
    faces = torch.arange(12).view(4, 3)
    out_v, out_f, parent = clip_near(verts, faces, 0.5)
    assert sorted(parent.tolist()) == [0, 0, 1, 2]  # quad, triangle, untouched, dropped
    tri = out_v[out_f]
    assert (tri[..., 2] >= 0.5 - 1e-6).all()

    def normal(t: torch.Tensor) -> torch.Tensor:
        return torch.linalg.cross(t[..., 1, :] - t[..., 0, :], t[..., 2, :] - t[..., 0, :], dim=-1)

    # Same facing as the parent (the plane of each parent is kept, winding too).
    cos = torch.nn.functional.cosine_similarity(normal(tri), normal(verts[faces][parent]), dim=-1)
    assert torch.allclose(cos, torch.ones_like(cos), atol=1e-5)
    # The quad of face 0 covers exactly the part of the triangle at z >= 0.5: area from the
    # cut (z spans 4 along the edges from the back vertex: the cut is at 1.5 / 4 of them).
    area = 0.5 * normal(tri[parent == 0]).norm(dim=-1).sum()
    full = 0.5 * normal(verts[faces[0]][None]).norm(dim=-1)[0]
    assert float(area / full) == pytest.approx(1 - (1.5 / 4) ** 2, rel=1e-5)


def test_hydra_config_composes(tmp_path: Path) -> None:
    hydra = pytest.importorskip("hydra")
    from sdn3d.cli._config import CONFIG_DIR
    from sdn3d.cli.synth import config_from_hydra

    with hydra.initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        cfg = hydra.compose(config_name="synth", overrides=[f"output_dir={tmp_path / 'd'}", "frames_per_sequence=3"])
    config = config_from_hydra(cfg)
    assert config.image_size == (624, 192) and config.frames_per_sequence == 3
    assert config.output_dir == str(tmp_path / "d")


def test_truncation_and_occupancy_of_a_car_leaving_the_frame() -> None:
    from sdn3d.data.synth.scene_render import template_bank
    from sdn3d.data.synth.stats import object_statistics
    from sdn3d.math3d.transforms import object_to_camera
    from sdn3d.render.rasterize import rasterize_meshes
    from sdn3d.render.settings import RasterSettings

    bank, _ = template_bank()
    intr = VKITTI_INTRINSICS.resized(WIDTH, HEIGHT)
    nf = int(bank.num_faces[0])
    dims = torch.tensor([[4.6, 1.45, 1.8], [4.6, 1.45, 1.8]])
    # Car 0 sticks out of the left edge of the frame, car 1 is fully inside.
    centers = torch.tensor([[-5.0, 0.9, 7.0], [1.0, 0.9, 20.0]])
    verts = object_to_camera(bank.verts[0, : int(bank.num_verts[0])], dims, torch.tensor([0.3, -1.2]), centers)
    nv = verts.shape[1]
    faces = torch.cat([bank.faces[0, :nf], bank.faces[0, :nf] + nv])
    owner = torch.cat([torch.zeros(nf, dtype=torch.long), torch.ones(nf, dtype=torch.long)])
    flat = verts.reshape(-1, 3)
    settings = RasterSettings(image_size=(HEIGHT, WIDTH), cull_backfaces=True)
    frags = rasterize_meshes(flat[None], faces[None], intr.matrix(), settings)
    instance = torch.where(frags.pix_to_face[0] >= 0, owner[frags.pix_to_face[0].clamp(min=0)], -1)
    full = torch.bincount(instance[instance >= 0], minlength=2)
    # Hide the left half of car 1's pixels: its occupancy becomes visible / unoccluded.
    cols = torch.arange(WIDTH).expand(HEIGHT, WIDTH)
    hidden = (instance == 1) & (cols < int(cols[instance == 1].float().median()))
    instance = torch.where(hidden, torch.full_like(instance, -1), instance)
    stats = object_statistics(flat, faces, owner, 2, instance, intr, 0.15, 0.1, 1000.0, cull_backfaces=True)
    # Reference truncation: the car alone on a canvas with a wide margin on every side (same pixel grid).
    margin = 3 * WIDTH
    wide = intr.cropped(-margin, -margin, WIDTH + 2 * margin, HEIGHT + 2 * margin)
    ref = (
        rasterize_meshes(
            flat[None],
            faces[None, :nf],
            wide.matrix(),
            RasterSettings(image_size=wide.size, cull_backfaces=True),
        ).pix_to_face[0]
        >= 0
    )
    inside = ref[margin : margin + HEIGHT, margin : margin + WIDTH].sum()
    assert stats.unoccluded.tolist() == [int(inside), int(full[1])]
    assert 0.2 < stats.truncr[0] < 0.95
    assert stats.truncr[0] == pytest.approx(1 - float(inside) / float(ref.sum()), abs=0.03)
    assert stats.truncr[1] == 0.0 and stats.visible_fraction[0] == 1.0
    assert stats.visible_fraction[1] == pytest.approx(float((instance == 1).sum()) / float(full[1]))
    assert 0.3 < stats.visible_fraction[1] < 0.7
    # occupr: visible pixels over the inclusive box of the visible pixels (the motgt row's box).
    for k in (0, 1):
        rows, cols = (instance == k).nonzero(as_tuple=True)
        area = (int(cols.max() - cols.min()) + 1) * (int(rows.max() - rows.min()) + 1)
        assert stats.occupr[k] == pytest.approx(len(rows) / area)
        assert stats.box[k].tolist() == [int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())]
    assert 0.5 < stats.occupr[0] < 0.95  # a car's silhouette does not fill its box


def test_occlusion_shortcut_gives_the_exact_counts(monkeypatch: pytest.MonkeyPatch) -> None:
    """Cars that nothing nearer overlaps on screen skip the draw-alone pass: same statistics."""
    from sdn3d.data.synth import build_world, frame_objects, render_frame, scene_render

    world = build_world(5, "0006", 4, (12, 14))
    intr = VKITTI_INTRINSICS.resized(WIDTH, HEIGHT)
    objects, pose = frame_objects(world, 3, 15.0), world.camera.pose(3, 15.0)
    fast = render_frame(world, objects, pose, intr, "15-deg-right", 0).stats
    monkeypatch.setattr(scene_render, "_occluder_boxes", lambda *args: None)
    full = render_frame(world, objects, pose, intr, "15-deg-right", 0).stats
    assert (fast.visible > 0).sum() >= 3
    np.testing.assert_array_equal(fast.unoccluded, full.unoccluded)
    np.testing.assert_array_equal(fast.truncr, full.truncr)
    np.testing.assert_array_equal(fast.occupr, full.occupr)
    np.testing.assert_array_equal(fast.visible_fraction, full.visible_fraction)
    seen = full.visible > 0
    assert (full.visible_fraction[seen] == 1.0).any() and (full.visible_fraction[seen] < 1.0).any()


def test_edit_benchmark_frames_are_never_trained_on(dataset: Path) -> None:
    """The paper split runs over the regular frames: benchmark sources (their last 20 %) and the appended
    edit targets are test frames, never training or validation frames, whatever the number of edit pairs."""
    import json

    from sdn3d.data.sources import SYNTH_MANIFEST, SourceConfig, edit_target_frames, load_split

    assert SYNTH_MANIFEST == MANIFEST_NAME
    split = {"rule": "paper", "val_fraction": 0.1, "val_gap": 0}
    source = SourceConfig.from_mapping({"kind": "vkitti1", "root": str(dataset), "image_size": [WIDTH, HEIGHT],
                                        "split": split})
    keys = {part: {(r.world, r.variation, r.frame) for r in load_split(source, part)}
            for part in ("train", "val", "test")}
    targets = edit_target_frames(dataset)
    assert len(targets) == len(VARIATIONS) * EDITS
    assert targets <= keys["test"] and not targets & (keys["train"] | keys["val"])
    assert not keys["train"] & keys["test"] and not keys["val"] & keys["test"] and not keys["train"] & keys["val"]
    entries = json.loads((dataset / BENCHMARK_NAME).read_text())
    for e in entries:
        assert (e["world"], e["topic"], int(e["source"])) in keys["test"], e
    # Regular frames: floor(0.8 * FRAMES) of each sequence train or validate (less the gap), the rest test.
    assert len(keys["train"] | keys["val"]) <= len(VARIATIONS) * math.floor(0.8 * FRAMES)
    assert len(keys["test"] - targets) == len(VARIATIONS) * (FRAMES - math.floor(0.8 * FRAMES))
    assert edit_target_frames(dataset / "vkitti_1.3.1_rgb") == set()  # no manifest: a real dataset


def test_unreadable_manifest_is_a_clear_error(tmp_path: Path) -> None:
    from sdn3d.data.sources import edit_target_frames

    (tmp_path / MANIFEST_NAME).write_text('{"sequences": [{"world": "0001"}], ')
    with pytest.raises(ValueError, match=MANIFEST_NAME):
        edit_target_frames(tmp_path)
    (tmp_path / MANIFEST_NAME).write_text('{"sequences": [{"variation": "clone", "edit_target_frames": [3]}]}')
    with pytest.raises(ValueError, match="edit target frames"):
        edit_target_frames(tmp_path)


def test_variations_sharing_the_camera_are_rendered_once_with_the_same_bytes(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """clone and fog share each frame's geometry (one rasterization, lit twice): the files are those of
    rendering each sequence alone."""
    import sys

    from sdn3d.data.synth import generate as gen

    cfg = dict(variations=("clone", "fog", "30-deg-left"), frames_per_sequence=2, edit_pairs=1)
    assert gen.sequence_groups([(WORLD, v) for v in cfg["variations"]]) == [
        (WORLD, ("clone", "fog")), (WORLD, ("30-deg-left",))]
    calls = []
    real = gen.render_geometry
    monkeypatch.setattr(gen, "render_geometry", lambda *a: calls.append(sys._getframe(1).f_code.co_name) or real(*a))
    shared = generate_dataset(_config(tmp_path / "shared", **cfg))
    assert calls.count("generate_sequences") == 2 + 2  # the frames of (clone, fog) once, those of 30-deg-left
    assert calls.count("_edit_targets") >= 3  # each edit target (a rejected edit is drawn again)
    monkeypatch.setattr(gen, "sequence_groups", lambda jobs: [(w, (v,)) for w, v in jobs])
    alone = generate_dataset(_config(tmp_path / "alone", **cfg))
    files = sorted(p.relative_to(shared) for p in shared.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(alone) for p in alone.rglob("*") if p.is_file())
    for rel in files:
        assert (shared / rel).read_bytes() == (alone / rel).read_bytes(), f"{rel} differs"


def test_progress_lines_count_every_frame_from_the_workers(tmp_path: Path) -> None:
    """Not a terminal: one line at the first frame and one at the last (30 s apart at most otherwise)."""
    import io

    stream = io.StringIO()
    generate_dataset(_config(tmp_path / "data", frames_per_sequence=2, edit_pairs=1, workers=2), progress=stream)
    lines = stream.getvalue().splitlines()
    total = len(VARIATIONS) * 3
    assert lines[0].startswith(f"sdn3d-synth: 1/{total} frames (") and "frames/s, ETA " in lines[0]
    assert lines[-1].startswith(f"sdn3d-synth: {total}/{total} frames (100.0%)") and "done in" in lines[-1]
    assert "\r" not in stream.getvalue()


def test_progress_on_a_terminal_rewrites_one_line_with_rate_and_eta() -> None:
    import io

    from sdn3d.data.synth.progress import FrameProgress, format_duration

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    now = [100.0]
    stream = Terminal()
    progress = FrameProgress(10, stream, clock=lambda: now[0])
    now[0] += 2.0
    progress.update(4)  # 2 frames/s: 6 frames left take 3 s
    assert stream.getvalue() == "\r\x1b[2Ksdn3d-synth: 4/10 frames (40.0%), 2.00 frames/s, ETA 3s"
    now[0] += 0.1
    progress.update()  # within 0.2 s of the last report: not redrawn
    assert stream.getvalue().count("\r") == 1
    now[0] += 2.9
    progress.update(5)
    assert stream.getvalue().endswith("\r\x1b[2Ksdn3d-synth: 10/10 frames (100.0%), 2.00 frames/s, done in 5s")
    progress.close()
    assert stream.getvalue().endswith("\n") and "\n" not in stream.getvalue()[:-1]
    assert [format_duration(s) for s in (7, 185, 7440)] == ["7s", "3m05s", "2h04m"]


def test_cli_reports_progress_on_stderr(tmp_path: Path) -> None:
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, "-m", "sdn3d.cli.synth", f"output_dir={tmp_path / 'data'}", "worlds=[\"0001\"]",
         "variations=[clone,fog]", "frames_per_sequence=1", "edit_pairs=0", "occluder_pairs=0", "image_size=[96,32]",
         "workers=1",
         f"hydra.run.dir={tmp_path / 'hydra'}"], capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    assert "sdn3d-synth: 2/2 frames (100.0%)" in proc.stderr and "done in" in proc.stderr


def test_a_pitched_camera_renders_the_road_where_its_camera_json_says(tmp_path: Path) -> None:
    """issue 40: camera_height / camera_pitch render a camera looking down at that height; its camera.json (beside
    the frames, as sdn3d-edit input.camera= reads it), extrinsicsgt, depth and motgt agree: the road seen through
    the depth map lies ``height`` below the camera in its level frame, the cars' bottoms too."""
    import json

    from sdn3d.data import vkitti1
    from sdn3d.data.cityscapes import camera_pose, camera_to_vehicle, read_camera
    from sdn3d.data.records import load_depth
    from sdn3d.labels import VKITTI_CLASSES

    root = tmp_path / "pitched"
    generate_dataset(_config(root, frames_per_sequence=2, edit_pairs=0, occluder_pairs=0, camera_height=1.2,
                             camera_pitch=0.05, variations=("clone", "15-deg-left")))
    manifest = json.loads((root / MANIFEST_NAME).read_text())
    assert manifest["config"]["camera_height"] == 1.2 and manifest["config"]["camera_pitch"] == 0.05
    records = vkitti1.read_frames(root)
    for rec in records:
        intrinsic, extrinsic = read_camera(root / "vkitti_1.3.1_rgb" / rec.world / rec.variation / "camera.json")
        pose = camera_pose(extrinsic)
        assert (pose.height, pose.pitch) == (1.2, 0.05)
        intr = rec.intrinsics
        assert (intrinsic["fx"], intrinsic["v0"]) == pytest.approx((intr.fx, intr.cy))
        # The yaw variations turn the camera about the vertical: Cityscapes' yaw, positive turning left.
        assert extrinsic["yaw"] == pytest.approx(math.radians(15) if rec.variation == "15-deg-left" else 0.0)
        # extrinsicsgt: the world's vertical (y down) seen in the camera is the camera.json's vertical.
        world_to_cam = np.asarray(rec.extrinsics, dtype=np.float64).reshape(4, 4)
        down_cam = world_to_cam[:3, :3] @ [0.0, 1.0, 0.0]
        down_json = camera_to_vehicle(extrinsic)[:3, :3].T @ [0.0, 0.0, -1.0]
        assert down_cam == pytest.approx(down_json, abs=1e-6)
        # The road in the depth map, in the level frame, is 1.2 m below the camera.
        depth = load_depth(rec)
        road = vkitti1.load_semantic(rec) == [c.name for c in VKITTI_CLASSES].index("Road")
        tilt = pose.tilt()
        rows, cols = np.nonzero(road & np.isfinite(depth) & (depth < 30))
        assert len(rows) > 100
        z = depth[rows, cols]
        p_cam = np.stack([(cols - intr.cx) / intr.fx * z, (rows - intr.cy) / intr.fy * z, z], 1)
        heights = (p_cam @ tilt)[:, 1]  # level-frame y
        assert np.median(heights) == pytest.approx(1.2, abs=0.03)
        # motgt: the bottom-face centres (pitched camera frame) are on the road in the level frame.
        for obj in rec.objects:
            assert float((tilt.T @ np.asarray(obj.location))[1]) == pytest.approx(1.2, abs=1e-4)
