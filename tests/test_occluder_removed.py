"""The synthetic benchmark's "occluder removed" entries (issue 18, point 3): a car in front of a partly hidden one
is deleted, and the target frame shows the hidden car (more of it) where the deleted car stood."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from sdn3d.data.edit_benchmark import BenchmarkEntry, load_edit_benchmark, save_edit_benchmark
from sdn3d.data.synth import BENCHMARK_NAME, MANIFEST_NAME, SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import load_instances, read_frames
from sdn3d.errors import UserInputError
from sdn3d.resources import paper_benchmark_path


@pytest.fixture(scope="module")
def occluder_data(tmp_path_factory):
    root = tmp_path_factory.mktemp("occluder") / "vkitti"
    generate_dataset(SynthConfig(output_dir=str(root), seed=0, image_size=(312, 96), worlds=("0018",),
                                 variations=("clone",), frames_per_sequence=20, cars_per_frame=(10, 16), edit_pairs=1,
                                 occluder_pairs=2))
    return root


def test_occluder_removed_entries_reveal_the_hidden_car(occluder_data):
    entries = load_edit_benchmark(occluder_data / BENCHMARK_NAME)
    assert [e.kind for e in entries][:1] == ["edit"] and len(entries) == 3
    removed = [e for e in entries if e.kind == "occluder_removed"]
    assert removed, "world 0018's test frames have partly hidden cars behind others"
    frames = {(r.variation, r.frame): r for r in read_frames(occluder_data)}
    for entry in removed:
        assert [op.kind for op in entry.operations] == ["delete"]
        assert entry.target_frame >= 21  # after the edit pair's target (frame 20)
        source = load_instances(frames[("clone", entry.source_frame)])
        target = load_instances(frames[("clone", entry.target_frame)])
        ids, before = np.unique(source[source > 0], return_counts=True)
        after = {i: int((target == i).sum()) for i in ids}
        gone = [i for i in ids if after[i] == 0]
        assert len(gone) >= 1  # the occluder
        gain = max(after[i] / b for i, b in zip(ids, before, strict=True) if after[i] > 0)
        assert gain >= 1.2  # some car shows at least a fifth more of itself


def test_entry_kind_round_trips_and_the_paper_file_is_all_edits(tmp_path):
    path = tmp_path / "bench.json"
    save_edit_benchmark([BenchmarkEntry("0001", "clone", 3, 9, (), "occluder_removed"),
                         BenchmarkEntry("0001", "clone", 3, 8, ())], path)
    raw = json.loads(path.read_text())
    assert raw[0]["kind"] == "occluder_removed" and "kind" not in raw[1]  # the paper's format stays as it is
    assert [e.kind for e in load_edit_benchmark(path)] == ["occluder_removed", "edit"]
    assert {e.kind for e in load_edit_benchmark(paper_benchmark_path())} == {"edit"}
    raw[0]["kind"] = "teleport"
    path.write_text(json.dumps(raw))
    with pytest.raises(ValueError, match=r"kind.*teleport"):
        load_edit_benchmark(path)


@pytest.fixture(scope="module")
def no_hidden_car(tmp_path_factory):
    """A sequence without cars: no pair of either kind can be drawn (main wrote their entries without operations
    and said nothing)."""
    root = tmp_path_factory.mktemp("no_hidden_car") / "vkitti"
    generate_dataset(SynthConfig(output_dir=str(root), seed=0, image_size=(160, 64), worlds=("0001",),
                                 variations=("clone",), frames_per_sequence=5, cars_per_frame=(0, 0), edit_pairs=1,
                                 occluder_pairs=2))
    return root


def test_pairs_that_cannot_be_drawn_are_counted_with_their_reason(no_hidden_car):
    manifest = json.loads((no_hidden_car / MANIFEST_NAME).read_text())
    counts = manifest["benchmark_entries"]
    assert counts["occluder_removed"] == {"asked": 2, "made": 0, "short": [
        {"world": "0001", "variation": "clone", "missing": 2, "reason": "no_hidden_car",
         "why": "no partly hidden car in test frame 4 (at most 80% visible, >= 20 pixels, truncation <= 0.3, "
                "beyond 3 m)"}]}
    assert counts["edit"] == {"asked": 1, "made": 0, "short": [
        {"world": "0001", "variation": "clone", "missing": 1, "reason": "no_editable_car",
         "why": "no car of source frame 4 can be edited"}]}
    # the entries are still written (frame numbers stay), without operations: what sdn3d-bench skips
    entries = load_edit_benchmark(no_hidden_car / BENCHMARK_NAME)
    assert [(e.kind, e.is_identity, e.target_frame) for e in entries] == [("edit", True, 5), ("edit", True, 6),
                                                                           ("edit", True, 7)]


def test_the_generator_warns_when_a_kind_is_short(tmp_path, capsys):
    generate_dataset(SynthConfig(output_dir=str(tmp_path / "vkitti"), seed=0, image_size=(96, 32), worlds=("0001",),
                                 variations=("clone",), frames_per_sequence=2, cars_per_frame=(0, 0), edit_pairs=0,
                                 occluder_pairs=1))
    err = capsys.readouterr().err.splitlines()
    assert err == ["sdn3d-synth: warning: 0 of the 1 'occluder_removed' benchmark entries asked for were made (1 "
                   "missing in 0001/clone: no partly hidden car in test frame 1 (at most 80% visible, >= 20 "
                   "pixels, truncation <= 0.3, beyond 3 m)); each missing one is an entry without operations, which "
                   "sdn3d-bench skips"]


def test_a_complete_benchmark_is_not_short(occluder_data):
    from sdn3d.data.synth.entry_report import benchmark_shortfall

    counts = json.loads((occluder_data / MANIFEST_NAME).read_text())["benchmark_entries"]
    assert counts == {"edit": {"asked": 1, "made": 1, "short": []},
                      "occluder_removed": {"asked": 2, "made": 2, "short": []}}
    assert benchmark_shortfall(occluder_data / BENCHMARK_NAME, load_edit_benchmark(occluder_data / BENCHMARK_NAME)) \
        == {}


def test_the_benchmark_counts_its_file_against_the_manifest(no_hidden_car, tmp_path):
    from sdn3d.data.synth.entry_report import benchmark_shortfall, shortfall_lines

    entries = load_edit_benchmark(no_hidden_car / BENCHMARK_NAME)
    short = benchmark_shortfall(no_hidden_car / BENCHMARK_NAME, entries)
    assert {k: (c.asked, c.made, [s["reason"] for s in c.short]) for k, c in short.items()} == {
        "edit": (1, 0, ["no_editable_car"]), "occluder_removed": (2, 0, ["no_hidden_car"])}
    # a manifest written before the counts existed: asked from its config, the reasons unknown
    old = tmp_path / "old"
    old.mkdir()
    manifest = json.loads((no_hidden_car / MANIFEST_NAME).read_text())
    del manifest["benchmark_entries"]
    (old / MANIFEST_NAME).write_text(json.dumps(manifest))
    shutil.copy(no_hidden_car / BENCHMARK_NAME, old / BENCHMARK_NAME)
    short = benchmark_shortfall(old / BENCHMARK_NAME, entries)
    assert {k: (c.asked, c.made, c.short) for k, c in short.items()} == {"edit": (1, 0, ()),
                                                                         "occluder_removed": (2, 0, ())}
    assert "the reasons are not recorded" in shortfall_lines(short, "sdn3d-bench")[0]
    # a benchmark file that is not the dataset's own (another name, the paper's): nothing to count against
    shutil.copy(no_hidden_car / BENCHMARK_NAME, old / "mine.json")
    assert benchmark_shortfall(old / "mine.json", entries) == {}
    assert benchmark_shortfall(paper_benchmark_path(), load_edit_benchmark(paper_benchmark_path())) == {}
    (old / MANIFEST_NAME).write_text("{not json")
    with pytest.raises(UserInputError, match="synth_manifest.json.*cannot read the benchmark's entry counts"):
        benchmark_shortfall(old / BENCHMARK_NAME, entries)


def test_when_the_drawn_pair_reveals_too_little_the_other_pairs_are_tried(tmp_path):
    """Seed 13's one test frame has 5 candidate pairs; the drawn one reveals too little of its hidden car, and main
    wrote an entry without operations. Now the frame's other pairs are tried, and 4 of them reveal enough."""
    root = tmp_path / "vkitti"
    generate_dataset(SynthConfig(output_dir=str(root), seed=13, image_size=(312, 96), worlds=("0018",),
                                 variations=("clone",), frames_per_sequence=5, cars_per_frame=(10, 16), edit_pairs=0,
                                 occluder_pairs=1))
    (entry,) = load_edit_benchmark(root / BENCHMARK_NAME)
    assert entry.kind == "occluder_removed" and [op.kind for op in entry.operations] == ["delete"]
    assert (entry.source_frame, entry.target_frame) == (4, 5)
    frames = {r.frame: r for r in read_frames(root)}
    source, target = load_instances(frames[4]), load_instances(frames[5])
    ids, before = np.unique(source[source > 0], return_counts=True)
    gains = [int((target == i).sum()) / b for i, b in zip(ids, before, strict=True)]
    assert sorted(gains)[0] == 0 and max(gains) >= 1.2  # the occluder gone, a car revealed by a fifth or more
    counts = json.loads((root / MANIFEST_NAME).read_text())["benchmark_entries"]
    assert counts["occluder_removed"] == {"asked": 1, "made": 1, "short": []}
