"""Split rules: three disjoint parts for every kind and rule, validation never from test, the released ranges
put the paper's whole editing benchmark in test."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import FrameRecord
from sdn3d.data.sources import SourceConfig, split_records
from sdn3d.data.splits import RELEASED_RANGES, carve_validation, released_split, released_world
from sdn3d.errors import UserInputError
from sdn3d.math3d.camera import Intrinsics
from sdn3d.resources import paper_benchmark_path

K = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375)
#: Frames per world of Virtual KITTI 1.3.1 (21,260 images over 10 variations).
VKITTI_FRAMES = {"0001": 447, "0002": 233, "0006": 270, "0018": 339, "0020": 837}


def _records(dataset: str = "vkitti1", frames: dict[str, int] | None = None,
             variations: tuple[str, ...] = ("clone", "fog")) -> list[FrameRecord]:
    worlds = frames or VKITTI_FRAMES
    name = (lambda w: f"Scene{int(w):02d}") if dataset == "vkitti2" else (lambda w: w)
    return [FrameRecord(dataset, name(w), v, i, K, Path(f"{w}/{v}/{i:05d}.png"))
            for w, n in worlds.items() for v in variations for i in range(n)]


def _parts(records, split) -> dict[str, set[str]]:
    return {part: {r.key for r in split_records(records, split, part)} for part in ("train", "val", "test")}


def _check_disjoint(parts: dict[str, set[str]]) -> None:
    for a, b in itertools.combinations(parts, 2):
        assert not parts[a] & parts[b], (a, b)
    assert all(parts.values())


@pytest.mark.parametrize("dataset", ["vkitti1", "vkitti2"])
@pytest.mark.parametrize("split", [
    {"rule": "released", "val_fraction": 0.1, "val_gap": 5},
    {"rule": "paper", "fraction": 0.8, "first": True, "val_fraction": 0.1, "val_gap": 5},
    {"rule": "paper", "fraction": 0.8, "first": False, "val_fraction": 0.2, "val_gap": 0},
])
def test_three_disjoint_parts_with_a_gap(dataset, split):
    records = _records(dataset)
    parts = _parts(records, split)
    _check_disjoint(parts)
    by_key = {r.key: r for r in records}
    # No validation frame lies within val_gap frames of a training frame of its sequence.
    train = {(by_key[k].world, by_key[k].variation, by_key[k].frame) for k in parts["train"]}
    for key in parts["val"]:
        r = by_key[key]
        near = {(r.world, r.variation, r.frame + d) for d in range(-split["val_gap"], split["val_gap"] + 1)}
        assert not near & train, key
    # Every frame is in one part, or is a gap frame (val_gap per sequence).
    unused = len(records) - sum(len(p) for p in parts.values())
    assert unused == split["val_gap"] * len({(r.world, r.variation) for r in records})


def test_released_ranges_are_the_released_codes():
    parts = _parts(_records(), {"rule": "released", "val_fraction": 0.1, "val_gap": 5})
    frames = {part: {(k.split("/")[1], int(k.split("/")[-1])) for k in keys} for part, keys in parts.items()}
    for world, ((t0, t1), (s0, s1)) in RELEASED_RANGES.items():
        assert {f for w, f in frames["test"] if w == world} == set(range(s0, s1 + 1))
        train_val = {f for w, f in frames["train"] | frames["val"] if w == world}
        assert min(train_val) == t0 and max(train_val) == t1
    assert released_world("Scene06") == "0006" == released_world("0006")


def test_all_92_pairs_of_the_paper_benchmark_fall_in_test():
    entries = load_edit_benchmark(paper_benchmark_path())
    assert len({(e.world, e.variation, frozenset((e.source_frame, e.target_frame))) for e in entries}) >= 92
    variations = tuple(sorted({e.variation for e in entries}))
    records = _records(variations=variations)
    test = {r.key for r in split_records(records, {"rule": "released", "val_fraction": 0.1, "val_gap": 5}, "test")}
    for e in entries:
        for frame in (e.source_frame, e.target_frame):
            assert f"vkitti1/{e.world}/{e.variation}/{frame:05d}" in test, (e.world, frame)
    # The old global "first 80 %" rule trained on many of them.
    paper_train = {r.key for r in split_records(records, {"rule": "paper", "fraction": 0.8, "first": True,
                                                          "val_fraction": 0.1, "val_gap": 5}, "train")}
    assert any(f"vkitti1/{e.world}/{e.variation}/{e.source_frame:05d}" in paper_train for e in entries)


def test_released_rule_refuses_other_data():
    with pytest.raises(UserInputError, match="'0042'"):
        released_split(_records(frames={"0042": 3}), "train")
    with pytest.raises(UserInputError, match="frame 447 of world 0001 is in neither released range"):
        released_split(_records(frames={"0001": 448}), "test")
    # short (synthetic) sequences would test on nothing: refused, with the rule to use instead
    with pytest.raises(UserInputError, match="sequence 0001/clone has frames 0-15, all in the released training range"
                                             ".*split.rule=paper"):
        released_split(_records(frames={"0001": 16}), "train")


def test_carve_validation_small_groups_and_cityscapes_order():
    seq = [FrameRecord("vkitti1", "0001", "clone", i, K, Path(f"{i}.png")) for i in range(3)]
    assert carve_validation(seq, 0.1, 5) == (seq, [])  # too short: all train
    train, val = carve_validation(seq, 0.1, 1)
    assert [r.frame for r in train] == [0] and [r.frame for r in val] == [2]
    city = [FrameRecord("cityscapes", "aachen", "train", 19, K, Path(f"{s}.png"), sequence=s) for s in (5, 1, 3, 2, 4)]
    train, val = carve_validation(city, 0.2, 1)  # ordered by sequence: 1 2 3 train, 4 gap, 5 validates
    assert [r.sequence for r in train] == [1, 2, 3] and [r.sequence for r in val] == [5]


@pytest.mark.parametrize(("kind", "split", "message"), [
    ("vkitti1", {"val": "test"}, "split.val is no longer a setting"),
    ("vkitti1", {"rule": "paper", "test": "test"}, "split.test is no longer a setting"),
    ("cityscapes", {"val": "val"}, "split.val is no longer a setting"),
    ("cityscapes", {"test": "train"}, "same folder"),
    ("vkitti1", {"rule": "folders"}, "not for kind"),
    ("vkitti1", {"rule": "released", "fraction": 0.5}, r"takes .* not \['fraction'\]"),
    ("vkitti1", {"val_fraction": 1.0}, "val_fraction"),
    ("vkitti2", {"val_gap": -1}, "val_gap"),
    ("vkitti1", {"rule": "random"}, "split.rule must be one of"),
])
def test_split_settings_are_checked(kind, split, message):
    with pytest.raises(UserInputError, match=message):
        SourceConfig(kind=kind, root=".", split=split)


def test_defaults_per_kind():
    assert SourceConfig(kind="vkitti1", root=".").split == {"rule": "released", "val_fraction": 0.1, "val_gap": 5}
    assert SourceConfig(kind="vkitti2", root=".").split["rule"] == "released"
    paper = SourceConfig(kind="vkitti1", root=".", split={"rule": "paper"}).split
    assert paper == {"rule": "paper", "fraction": 0.8, "first": True, "val_fraction": 0.1, "val_gap": 5}
    assert SourceConfig(kind="cityscapes", root=".").split["test"] == "val"
