"""The textural branch on the other branches' predictions (issue 18, point 1): the predicted-map cache."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import torch
from helpers.tiny_models import write_checkpoints
from omegaconf import OmegaConf

from datamodules import TexturalDataModule
from sdn3d.data.frames import load_frame
from sdn3d.data.map_cache import MapCache, MapCacheError
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.derender import derender
from sdn3d.errors import UserInputError
from sdn3d.image_ops import instance_label_map
from sdn3d.models import Models
from sdn3d.predicted_maps import build_predicted_maps, map_cache_inputs, predict_frame_maps
from sdn3d.scene.maps import scene_maps

CONF = Path(__file__).resolve().parents[1] / "conf" / "data"
SIZE = (160, 64)


def _source(root: Path) -> SourceConfig:
    cfg = OmegaConf.load(CONF / "synth.yaml")
    cfg.root = str(root)
    cfg.image_size = list(SIZE)
    return SourceConfig.from_mapping(cfg)


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory) -> dict[str, Path]:
    return write_checkpoints(tmp_path_factory.mktemp("ckpts"))


def test_cached_maps_are_the_edit_time_maps_and_are_reused(tiny_synth, ckpts, tmp_path, monkeypatch):
    records = load_split(_source(tiny_synth), "val")
    cache = build_predicted_maps(records, SIZE, ckpts["semantic"], ckpts["geometric"], tmp_path, "val")
    assert cache.directory.name.startswith("val-") and sorted(cache.frames) == sorted(r.key for r in records)
    # The same derender + scene_maps that draw an edit, on the semantic branch's proposals (no ground truth).
    models = Models.from_checkpoints(semantic=ckpts["semantic"], geometric=ckpts["geometric"])
    frame = load_frame(records[0], SIZE, semantic=False, instances=False)
    scene = derender(frame.image, frame.intrinsics, models, proposals="semantic")
    maps = scene_maps(scene)
    cached = cache.load(records[0].key)
    assert torch.equal(cached.semantic, scene.semantic) and torch.equal(cached.instance, maps.instance)
    assert torch.allclose(cached.normal, maps.normal, atol=1e-3)
    drawn = maps.pose.sum(0) > 0
    assert torch.equal(cached.pose_bin >= 0, drawn)
    assert torch.equal(cached.pose_bin[drawn], maps.pose.argmax(0)[drawn])

    def fail(*args, **kwargs):
        raise AssertionError("an up-to-date cache must be reused, not recomputed")

    monkeypatch.setattr("sdn3d.predicted_maps.predict_frame_maps", fail)
    again = build_predicted_maps(records, SIZE, ckpts["semantic"], ckpts["geometric"], tmp_path, "val")
    assert again.directory == cache.directory


def test_other_checkpoints_give_another_cache(tiny_synth, ckpts, tmp_path):
    records = load_split(_source(tiny_synth), "val")
    other = write_checkpoints(tmp_path / "other", seed=1)
    a = build_predicted_maps(records, SIZE, ckpts["semantic"], ckpts["geometric"], tmp_path / "c", "val")
    b = build_predicted_maps(records, SIZE, ckpts["semantic"], other["geometric"], tmp_path / "c", "val")
    assert a.directory != b.directory and a.directory.exists() and b.directory.exists()


def test_corrupt_and_stale_caches_are_errors_naming_the_file(tiny_synth, ckpts, tmp_path):
    records = load_split(_source(tiny_synth), "val")
    cache = build_predicted_maps(records, SIZE, ckpts["semantic"], ckpts["geometric"], tmp_path, "val")
    entry = cache.frames[records[0].key]
    frame_file = cache.directory / entry["file"]
    frame_file.write_bytes(frame_file.read_bytes()[:-7] + b"garbage")
    with pytest.raises(MapCacheError, match=str(frame_file)):
        cache.load(records[0].key)
    with pytest.raises(MapCacheError, match="corrupt"):
        build_predicted_maps(records, SIZE, ckpts["semantic"], ckpts["geometric"], tmp_path, "val").load(
            records[0].key)
    # A manifest that was computed from other inputs than its directory's key says.
    manifest = cache.directory / "manifest.json"
    data = json.loads(manifest.read_text())
    data["inputs"]["min_pixels"] = 1
    manifest.write_text(json.dumps(data))
    inputs = map_cache_inputs(records, SIZE, ckpts["semantic"], ckpts["geometric"])
    with pytest.raises(MapCacheError, match="stale"):
        MapCache(cache.directory, inputs, [r.key for r in records], SIZE)
    manifest.unlink()
    with pytest.raises(MapCacheError, match="manifest.json: missing"):
        MapCache(cache.directory, inputs, [r.key for r in records], SIZE)


def test_datamodule_trains_on_predicted_maps(tiny_synth, ckpts, tmp_path):
    cfg = OmegaConf.load(CONF / "synth.yaml")
    cfg.root = str(tiny_synth)
    dm = TexturalDataModule(cfg, image_size=SIZE, maps="predicted", semantic_checkpoint=str(ckpts["semantic"]),
                            geometric_checkpoint=str(ckpts["geometric"]), map_cache_dir=str(tmp_path))
    dm.setup("fit")
    item = dm.datasets["train"].dataset[0]
    record = dm.datasets["train"].dataset.records[0]
    models = Models.from_checkpoints(semantic=ckpts["semantic"], geometric=ckpts["geometric"])
    expected = predict_frame_maps(record, SIZE, models)
    assert torch.equal(item["instance"], expected.instance)
    label, lmap = instance_label_map(expected.semantic, expected.instance)
    assert torch.equal(item["label"], label) and torch.equal(item["instance_label_map"], lmap)
    gt = load_frame(record, SIZE)
    assert torch.equal(item["image"], gt.image)  # the target stays the frame itself
    assert item["pose"].shape == (24, SIZE[1], SIZE[0])
    assert sorted(p.name.split("-")[0] for p in tmp_path.iterdir()) == ["train", "val"]


def test_predicted_maps_need_both_checkpoints(tiny_synth, ckpts):
    cfg = OmegaConf.load(CONF / "synth.yaml")
    cfg.root = str(tiny_synth)
    with pytest.raises(UserInputError, match="datamodule.geometric_checkpoint"):
        TexturalDataModule(cfg, maps="predicted", semantic_checkpoint=str(ckpts["semantic"]))
    with pytest.raises(UserInputError, match="datamodule.maps"):
        TexturalDataModule(cfg, maps="oracle")


class _OracleSemantic:
    """Stands in for the semantic branch: answers with the frame's own labels and instances."""

    def __init__(self, classes, semantic: torch.Tensor, instance: torch.Tensor) -> None:
        self.classes, self.semantic, self.instance = classes, semantic, instance

    def __call__(self, image):
        from types import SimpleNamespace

        return SimpleNamespace(label=self.semantic[None], instance=self.instance[None])


def test_objects_get_the_geometric_branch_meshes_and_poses(tiny_synth, ckpts):
    record = load_split(_source(tiny_synth), "train")[0]
    models = Models.from_checkpoints(semantic=ckpts["semantic"], geometric=ckpts["geometric"], crop_size=32)
    gt = load_frame(record, SIZE)
    models.semantic = _OracleSemantic(models.semantic.classes, gt.semantic, gt.instances)
    maps = predict_frame_maps(record, SIZE, models, min_pixels=16)
    assert maps.instance.unique().numel() > 1  # the proposals' objects ...
    assert (maps.pose_bin >= 0).any() and maps.normal.abs().sum() > 0  # ... drawn with predicted 3D geometry
    assert torch.equal(maps.pose_bin >= 0, (maps.pose_bin >= 0) & (maps.instance > 0))
