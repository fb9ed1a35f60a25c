"""Class statistics of a synthetic dataset (``class_stats``) and the street furniture that fills the rare classes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from sdn3d.data.synth import SynthConfig, generate_dataset
from sdn3d.data.synth.class_stats import (
    MIN_SEGMENT_PIXELS,
    PARTS,
    STATISTICS_NAME,
    class_statistics,
    format_table,
    frame_class_counts,
    read_class_statistics,
    shortfalls,
)
from sdn3d.data.synth.classes import CLASS_ID, CLASS_NAMES
from sdn3d.data.synth.layout import build_world
from sdn3d.data.synth.primitives import prism_mesh, regular_polygon
from sdn3d.data.synth.scenery import WORLD_STYLES
from sdn3d.errors import UserInputError
from sdn3d.labels import VKITTI_CLASSES

WORLDS = ("0001", "0002", "0006", "0018", "0020")
TOWNS = ("0001", "0006", "0018")


pytestmark = pytest.mark.usefixtures("one_torch_thread")


def test_generator_classes_are_the_reader_classes() -> None:
    assert CLASS_NAMES == tuple(c.name for c in VKITTI_CLASSES)


def test_frame_counts_pixels_regions_and_instances() -> None:
    pole, sign, road, car, van = (CLASS_ID[n] for n in ("Pole", "TrafficSign", "Road", "Car", "Van"))
    semantic = np.full((12, 16), road, dtype=np.int64)
    semantic[0:6, 0] = pole  # one region ...
    semantic[6, 1] = pole  # ... joined diagonally (8-connectivity)
    semantic[0:5, 10] = pole  # a second region
    semantic[11, 15] = pole  # a speck under MIN_SEGMENT_PIXELS: pixels, no segment
    semantic[8:10, 3:5] = sign  # 4 pixels: exactly the minimum
    instances = np.zeros_like(semantic)
    semantic[0:3, 12:15], instances[0:3, 12:15] = car, car * 1000 + 1  # Car tid 0 ...
    semantic[3:5, 12:15], instances[3:5, 12:15] = car, car * 1000 + 8  # ... touching Car tid 7: two instances
    semantic[9:11, 8:10], instances[9:11, 8:10] = van, van * 1000 + 3
    pixels, segments, ids = frame_class_counts(semantic, instances)
    assert MIN_SEGMENT_PIXELS == 4
    assert pixels.sum() == semantic.size and pixels[pole] == 6 + 1 + 5 + 1 and pixels[sign] == 4
    assert pixels[car] == 15 and pixels[van] == 4
    assert segments[pole] == 2 and segments[sign] == 1 and segments[road] == 1
    assert segments[car] == 2 and segments[van] == 1
    assert ids.tolist() == [car * 1000 + 1, car * 1000 + 8, van * 1000 + 3]
    assert segments[CLASS_ID["Sky"]] == 0 and pixels[CLASS_ID["Sky"]] == 0


def test_prism_is_closed_and_wound_outwards() -> None:
    for polygon in (regular_polygon(3, 0.5, -np.pi / 2), regular_polygon(8, 0.4, np.pi / 8),
                    regular_polygon(12, 0.3)[::-1]):  # either corner order
        verts, faces = prism_mesh(polygon, 0.1, np.array([2.0, -1.5, 7.0]), yaw=0.3)
        k = len(polygon)
        assert verts.shape == (2 * k, 3) and faces.shape == (4 * k - 4, 3)
        tri = verts[faces]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        assert ((normal * (tri.mean(1) - verts.mean(0))).sum(1) > 0).all()
        # Closed: every edge is used once in each direction.
        edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        assert {tuple(e) for e in edges.tolist()} == {tuple(e) for e in edges[:, ::-1].tolist()}
    with pytest.raises(ValueError):
        regular_polygon(2, 1.0)


def _static_classes_near(world: str, seed: int, z_lo: float, z_hi: float) -> set[str]:
    static = build_world(seed, world, 8, (6, 14)).static
    near = (static.face_zmax > z_lo) & (static.face_zmin < z_hi)
    return {CLASS_NAMES[c] for c in np.unique(static.face_class[near])}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_street_furniture_where_it_belongs(seed: int) -> None:
    """Signals at a crossing in the first 70 m of every town world, none on the country road and the motorway;
    poles and signs everywhere; guard rails on the country road, the motorway and the wide road's median."""
    for world in WORLDS:
        near = _static_classes_near(world, seed, 0.0, 70.0)
        assert ("TrafficLight" in near) == (world in TOWNS), (world, near)
        assert {"Pole", "TrafficSign"} <= _static_classes_near(world, seed, -40.0, 300.0), world
        if world != "0018":  # 0018 has rails on about a quarter of its length, anywhere
            assert ("GuardRail" in near) == (world in ("0002", "0006", "0020")), (world, near)
    assert sum(WORLD_STYLES[w].crossing_spacing > 0 for w in WORLDS) >= 3
    assert WORLD_STYLES["0020"].gantry_spacing > 0 and WORLD_STYLES["0002"].utility_pole_spacing > 0


def test_trucks_in_most_worlds() -> None:
    """Parked trucks are scenery: over seeds, most worlds have one within the first 70 m (the 0.1 % goal)."""
    found = [[_static_classes_near(w, seed, 3.0, 70.0) >= {"Truck"} for w in WORLDS] for seed in range(8)]
    assert np.mean(found) > 0.5
    assert all(any(row[i] for row in found) for i in range(len(WORLDS)))


def _small_config(out: Path, **kw) -> SynthConfig:
    base = dict(output_dir=str(out), seed=0, image_size=(312, 96), worlds=WORLDS, variations=("clone",),
                frames_per_sequence=3, cars_per_frame=(6, 14), edit_pairs=1, occluder_pairs=0, workers=1, threads=1)
    base.update(kw)
    return SynthConfig(**base)


@pytest.fixture(scope="module")
def small_dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return generate_dataset(_small_config(tmp_path_factory.mktemp("class_stats") / "data"))


def test_generator_writes_the_statistics_of_its_files(small_dataset: Path) -> None:
    written = read_class_statistics(small_dataset)
    computed = class_statistics(small_dataset)
    assert written.worlds == WORLDS and written.classes == CLASS_NAMES
    for name in ("frames", "image_pixels", "pixels", "frames_with", "segments", "tracks"):
        np.testing.assert_array_equal(getattr(written, name), getattr(computed, name), err_msg=name)
    # 3 regular frames + 1 edit target per world; test part: the last regular frame (floor(0.8 * 3) = 2
    # train) and the edit target.
    np.testing.assert_array_equal(written.frames, [[4] * 5, [2] * 5])
    np.testing.assert_array_equal(written.pixels.sum(-1), written.image_pixels)  # one class per pixel
    assert (written.frames_with <= written.frames[..., None]).all()
    instance = [CLASS_ID["Car"], CLASS_ID["Van"]]
    assert (written.tracks[..., instance] >= 0).all() and (np.delete(written.tracks, instance, -1) == -1).all()
    data = json.loads((small_dataset / STATISTICS_NAME).read_text())
    assert set(data["parts"]) == set(PARTS)


def test_every_class_is_present_in_the_default_worlds(small_dataset: Path) -> None:
    stats = read_class_statistics(small_dataset)
    assert shortfalls(stats, "all", 1e-6, 1) == []
    table = format_table(stats, "test")
    assert all(name in table for name in CLASS_NAMES) and all(world in table for world in WORLDS)


def test_unreadable_statistics_are_a_clear_error(tmp_path: Path) -> None:
    (tmp_path / STATISTICS_NAME).write_text('{"classes": []}')
    with pytest.raises(UserInputError, match=STATISTICS_NAME):
        read_class_statistics(tmp_path)


@pytest.mark.slow
def test_default_dataset_meets_the_class_goal(tmp_path: Path) -> None:
    """conf/synth.yaml's dataset: every class covers >= 0.1 % of the test pixels and shows in >= 3 of 5 worlds."""
    hydra = pytest.importorskip("hydra")
    from sdn3d.cli._config import CONFIG_DIR
    from sdn3d.cli.synth import config_from_hydra

    with hydra.initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        cfg = hydra.compose(config_name="synth", overrides=[f"output_dir={tmp_path / 'data'}"])
    root = generate_dataset(config_from_hydra(cfg))
    stats = read_class_statistics(root)
    assert shortfalls(stats, "test", 0.1, 3) == [], format_table(stats, "test")
