"""The synthetic benchmark's "occluder removed" entries (issue 18, point 3): a car in front of a partly hidden one
is deleted, and the target frame shows the hidden car (more of it) where the deleted car stood."""

from __future__ import annotations

import json

import numpy as np
import pytest

from sdn3d.data.edit_benchmark import BenchmarkEntry, load_edit_benchmark, save_edit_benchmark
from sdn3d.data.synth import BENCHMARK_NAME, SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import load_instances, read_frames
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
