"""Issue 32, the documented exit status 2 for every configuration mistake.

Before: a Hydra override typo (an unknown key, bad override syntax, a group option that does not exist) made the
``@hydra.main`` tools (``sdn3d-train``, ``sdn3d-synth``, ``sdn3d-render-demo``) print Hydra's several lines and exit
1, where the documentation (and every other sdn3d tool) says 2; ``sdn3d-bench`` with an empty entry list, or with
every entry's points outside the frame, exited 0 after writing empty tables. Now: one line naming the key, exit 2;
the benchmark stops before any work unless ``allow_empty=true``.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.tiny_models import write_checkpoints

from sdn3d.cli.bench import main as bench_main

TYPOS = [("train", "trainer.max_epoch=3", r"Could not override 'trainer.max_epoch'"),
         ("train", "trainer.max_epochs=[1", r"bad override 'trainer.max_epochs=[1'"),
         ("train", "branch=semantik", r"Could not find 'branch/semantik' Available options in 'branch': geometric"),
         ("synth", "frames_per_sequenc=3", r"Could not override 'frames_per_sequenc'"),
         ("synth", "seed=[1", r"bad override 'seed=[1'"),
         ("render_demo", "bogus_key=1", r"Could not override 'bogus_key'")]


def _tool(module: str, args: list[str], cwd: Path, **env: str) -> subprocess.CompletedProcess:
    environ = {k: v for k, v in os.environ.items() if k != "HYDRA_FULL_ERROR"} | {"OMP_NUM_THREADS": "1", **env}
    return subprocess.run([sys.executable, "-m", f"sdn3d.cli.{module}", *args], cwd=cwd, env=environ,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize(("module", "override", "message"), TYPOS, ids=[f"{m}:{o}" for m, o, _ in TYPOS])
def test_hydra_override_mistakes_exit_2_in_one_line_naming_the_key(tmp_path, module, override, message):
    proc = _tool(module, [override, f"hydra.run.dir={tmp_path / 'run'}"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    tool = module.replace("_", "-")
    assert len(lines) == 1 and lines[0].startswith(f"sdn3d-{tool}: error: "), proc.stderr
    assert message in lines[0] and "Traceback" not in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing written: not even Hydra's run directory


def test_a_user_who_asked_for_hydras_full_error_gets_it(tmp_path):
    proc = _tool("synth", ["frames_per_sequenc=3"], tmp_path, HYDRA_FULL_ERROR="1")
    assert proc.returncode == 1 and "Traceback" in proc.stderr and "frames_per_sequenc" in proc.stderr


def _bench_args(tiny_synth: Path, tmp_path: Path, benchmark: Path, *extra: str) -> list[str]:
    ckpts = write_checkpoints(tmp_path / "ckpt")
    return [f"data.root={tiny_synth}", "data.image_size=[160,64]", f"benchmark={benchmark}",
            f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
            "proposals=gt", "compose=photo", "geometric.crop_size=32", "geometric.min_pixels=1",
            f"output_dir={tmp_path / 'bench'}", *extra]


def test_bench_refuses_an_empty_benchmark_unless_asked_not_to(tiny_synth, tmp_path, capsys):
    empty = tmp_path / "empty.json"
    empty.write_text("[]")
    assert bench_main(_bench_args(tiny_synth, tmp_path, empty)) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"sdn3d-bench: error: benchmark '{empty}' has nothing to evaluate: it lists no entry; give another "
                   "benchmark (or the right frame_size), or allow_empty=true to write empty tables anyway")
    assert not (tmp_path / "bench").exists()
    shipped = tiny_synth / "vkitti_edit_benchmark.json"
    assert bench_main(_bench_args(tiny_synth, tmp_path, shipped, "limit=0")) == 2
    assert re.search(r"none of its \d+ entries is chosen \(include_identity=False, limit=0\)", capsys.readouterr().err)
    assert bench_main(_bench_args(tiny_synth, tmp_path, empty, "allow_empty=true")) == 0
    report = json.loads((tmp_path / "bench" / "results.json").read_text())
    assert report["summary"]["gt"]["entries"] == 0


def test_bench_refuses_a_benchmark_whose_points_all_lie_outside_the_frame(tiny_synth, tmp_path, capsys):
    entries = json.loads((tiny_synth / "vkitti_edit_benchmark.json").read_text())
    for entry in entries:
        for op in entry["operations"]:
            op["from"] = {"u": 5000, "v": 5000}
            if op.get("to"):
                op["to"] = {"u": -900, "v": 6000}
    outside = tmp_path / "outside.json"
    outside.write_text(json.dumps(entries))
    assert bench_main(_bench_args(tiny_synth, tmp_path, outside)) == 2
    assert re.search(r"every point of its \d+ chosen entries lies outside the 1242x375 frame \(frame_size\)",
                     capsys.readouterr().err)
    assert not (tmp_path / "bench").exists()
    # the same entries in a frame where they lie inside: evaluated
    assert bench_main(_bench_args(tiny_synth, tmp_path, outside, "frame_size=[10000,10000]")) == 0
