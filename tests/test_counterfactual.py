"""Counterfactual pairs of sdn3d-synth (issue 41 item 4): a test frame re-rendered with one car turned in place or
deleted, with the masks to score it; off by default, the rest of the dataset unchanged either way."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sdn3d.data.synth import BENCHMARK_NAME, MANIFEST_NAME, SynthConfig, generate_dataset
from sdn3d.data.synth.counterfactual import PAIRS_DIR, PAIRS_FORMAT, PAIRS_NAME, SHADOW_THRESHOLD

pytestmark = pytest.mark.usefixtures("one_torch_thread")
TURNS = (0, 15, 45, 90, 180)


def _config(out: Path, **kw) -> SynthConfig:
    base = dict(output_dir=str(out), seed=3, image_size=(160, 64), worlds=("0001", "0006"), variations=("clone",),
                frames_per_sequence=5, cars_per_frame=(6, 10), edit_pairs=1, occluder_pairs=0, workers=1, threads=1,
                counterfactual_cars=2, counterfactual_turns=TURNS)
    base.update(kw)
    return SynthConfig(**base)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return generate_dataset(_config(tmp_path_factory.mktemp("cf") / "data"))


def _png(root: Path, name: str) -> np.ndarray:
    return np.asarray(Image.open(root / name))


def _mask(root: Path, name: str) -> np.ndarray:
    mask = _png(root, name)
    assert mask.dtype == np.uint8 and mask.ndim == 2 and set(np.unique(mask).tolist()) <= {0, 255}
    return mask == 255


def _pairs(root: Path) -> list[dict]:
    index = json.loads((root / PAIRS_NAME).read_text())
    assert index["format"] == PAIRS_FORMAT and index["version"] == 1
    assert index["image_size"] == [160, 64] and index["shadow_threshold"] == SHADOW_THRESHOLD
    return index["pairs"]


def test_pairs_exist_with_their_files(dataset: Path) -> None:
    pairs = _pairs(dataset)
    targets = {(p["world"], p["variation"], p["frame"], p["instance_id"]) for p in pairs}
    assert len(targets) == 4  # 2 per sequence
    assert len(pairs) == len(targets) * (len(TURNS) + 1)
    manifest = json.loads((dataset / MANIFEST_NAME).read_text())
    assert manifest["counterfactual_pairs"] == PAIRS_NAME and manifest["config"]["counterfactual_cars"] == 2
    for p in pairs:
        assert p["frame"] == 4 and p["kind"] in ("turn", "delete")  # the test part of 5 frames: frame 4
        assert (p["angle_deg"] in TURNS) == (p["kind"] == "turn")
        for key in ("source", "source_mask", "target", "target_mask", "vacated", "shadow"):
            assert (dataset / p[key]).is_file(), p[key]
        assert p["target"].startswith(f"{PAIRS_DIR}/{p['world']}/{p['variation']}/00004_{p['instance_id']}/")
        assert p["instance_id"] // 1000 in (12, 13) and p["instance_id"] % 1000 == p["track_id"] + 1
        # The source mask is the car's pixels in the written scene ground truth (its instance colour there).
        source_mask = _mask(dataset, p["source_mask"])
        assert source_mask.sum() == p["pixels"]["source_mask"] >= 40
        for key in ("target_mask", "vacated", "shadow"):
            assert _mask(dataset, p[key]).sum() == p["pixels"][key]


def test_zero_turn_reproduces_the_source_frame(dataset: Path) -> None:
    for p in (p for p in _pairs(dataset) if p["angle_deg"] == 0):
        assert np.array_equal(_png(dataset, p["target"]), _png(dataset, p["source"]))
        assert np.array_equal(_mask(dataset, p["target_mask"]), _mask(dataset, p["source_mask"]))
        assert p["pixels"]["vacated"] == p["pixels"]["shadow"] == 0 and p["ry_target"] == p["ry_source"]


def test_turned_car_changes_its_mask_and_only_the_pair_regions(dataset: Path) -> None:
    for p in (p for p in _pairs(dataset) if p["kind"] == "turn" and p["angle_deg"] != 0):
        source, target = _png(dataset, p["source"]), _png(dataset, p["target"])
        before, after = _mask(dataset, p["source_mask"]), _mask(dataset, p["target_mask"])
        if p["angle_deg"] == 90:
            assert not np.array_equal(before, after) and (before ^ after).sum() >= 5
        assert np.array_equal(_mask(dataset, p["vacated"]), before & ~after)
        region = before | after | _mask(dataset, p["shadow"])
        change = np.abs(source.astype(int) - target.astype(int)).max(-1)
        assert change[~region].max(initial=0) <= SHADOW_THRESHOLD


def test_delete_differs_only_in_the_vacated_region_and_shadow_band(dataset: Path) -> None:
    shadows = 0
    for p in (p for p in _pairs(dataset) if p["kind"] == "delete"):
        source, target = _png(dataset, p["source"]), _png(dataset, p["target"])
        vacated, shadow = _mask(dataset, p["vacated"]), _mask(dataset, p["shadow"])
        assert not _mask(dataset, p["target_mask"]).any()
        assert np.array_equal(vacated, _mask(dataset, p["source_mask"]))  # the whole car is gone
        assert not (vacated & shadow).any()
        change = np.abs(source.astype(int) - target.astype(int)).max(-1)
        assert change[~(vacated | shadow)].max(initial=0) <= SHADOW_THRESHOLD
        assert (change[vacated] > 0).mean() > 0.5  # the car's pixels show what was behind it
        shadows += int(shadow.sum())
    assert shadows > 0  # the deleted cars' shadows went with them


def _files(root: Path, skip: tuple[str, ...] = ()) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and not p.relative_to(root).as_posix().startswith(skip)}


def test_same_seed_same_pairs_and_the_dataset_is_unchanged_without_them(dataset: Path, tmp_path: Path) -> None:
    again = generate_dataset(_config(tmp_path / "again", workers=2))
    assert _files(again) == _files(dataset)
    off = generate_dataset(_config(tmp_path / "off", counterfactual_cars=0))
    assert not (off / PAIRS_NAME).exists() and not (off / PAIRS_DIR).exists()
    manifest = json.loads((off / MANIFEST_NAME).read_text())
    assert "counterfactual_pairs" not in manifest and not any(k.startswith("counterfactual") for k in
                                                                 manifest["config"])
    skip = (PAIRS_NAME, PAIRS_DIR, MANIFEST_NAME)
    assert _files(off, skip) == _files(dataset, skip)  # frames, tables, benchmark: the same bytes
    assert (off / BENCHMARK_NAME).read_bytes() == (dataset / BENCHMARK_NAME).read_bytes()


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"counterfactual_cars": -1}, "counterfactual_cars must be >= 0"),
        ({"counterfactual_cars": 1.5}, "counterfactual_cars must be an integer"),
        ({"counterfactual_turns": "90"}, "counterfactual_turns must be a list"),
        ({"counterfactual_turns": (90, 90)}, "counterfactual_turns must be a list of distinct"),
        ({"counterfactual_turns": (400,)}, "counterfactual_turns"),
        ({"counterfactual_turns": (True,)}, "counterfactual_turns"),
        ({"counterfactual_delete": "yes"}, "counterfactual_delete must be true or false"),
    ],
)
def test_config_validation(tmp_path: Path, bad: dict, message: str) -> None:
    from sdn3d.data.synth.generate import SynthConfigError

    with pytest.raises(SynthConfigError, match=message):
        _config(tmp_path / "x", **bad)


def test_turn_angles_normalise_and_the_cli_knows_the_keys(tmp_path: Path) -> None:
    cfg = _config(tmp_path / "x", counterfactual_turns=[15.0, 22.5, np.int64(-45)])
    assert cfg.counterfactual_turns == (15, 22.5, -45) and type(cfg.counterfactual_turns[0]) is int
    hydra = pytest.importorskip("hydra")
    from sdn3d.cli._config import CONFIG_DIR
    from sdn3d.cli.synth import config_from_hydra

    with hydra.initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        composed = hydra.compose(config_name="synth", overrides=[f"output_dir={tmp_path / 'd'}",
                                                                  "counterfactual_cars=3"])
    config = config_from_hydra(composed)
    assert config.counterfactual_cars == 3 and config.counterfactual_turns == (15, 45, 90, 180)
    assert config.counterfactual_delete is True
    assert SynthConfig(output_dir="x").counterfactual_cars == 0  # off by default
