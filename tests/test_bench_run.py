"""Issue 28, one vocabulary across the commands: ``sdn3d-bench run=<dir>`` as ``sdn3d-edit run=``.

Before: ``sdn3d-bench`` had no ``run=`` (``Could not override 'run'``): three checkpoint paths by hand. Now: the
branches' checkpoints come from the ``sdn3d-train`` summaries under a training output directory (the same choice
as ``sdn3d-edit``'s, :func:`sdn3d.runs.checkpoints_from_run`), ``checkpoints.<branch>=`` given explicitly wins, each
branch's file is printed on stderr and recorded in ``results.json`` (``info.checkpoints``); a run that lacks a
branch the benchmark needs stops with exit 2 before anything is written.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from helpers.tiny_models import write_checkpoints

from sdn3d.cli.bench import main


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory) -> dict[str, Path]:
    return write_checkpoints(tmp_path_factory.mktemp("bench_run_ckpts"))


def _train_run(run_dir: Path, branch: str, ckpt: Path, status: str = "ok",
               finished: str = "2026-01-01T10:00:00+00:00") -> Path:
    """A ``sdn3d-train`` run directory: ``checkpoints/{best,last}`` (copies of ``ckpt``) and its summary.json."""
    (run_dir / "checkpoints").mkdir(parents=True)
    last = shutil.copy(ckpt, run_dir / "checkpoints" / "last.ckpt")
    best = shutil.copy(ckpt, run_dir / "checkpoints" / "best-epoch001.ckpt")
    (run_dir / "summary.json").write_text(json.dumps({
        "branch": branch, "run_dir": str(run_dir), "best_ckpt": str(best), "last_ckpt": str(last),
        "status": status, "finished": finished}))
    return run_dir


def _demo(root: Path, ckpts: dict[str, Path], branches=("semantic", "geometric", "textural")) -> Path:
    """The layout ``sdn3d-demo`` writes: ``<root>/runs/<branch>/summary.json`` and the demo's own summary."""
    for branch in branches:
        _train_run(root / "runs" / branch, branch, ckpts[branch])
    (root / "summary.json").write_text(json.dumps({"stages": {}, "wall_s": 1.0}))
    return root


def _args(tiny_synth: Path, out: Path, *extra: str) -> list[str]:
    return [f"data.root={tiny_synth}", "data.image_size=[160,64]", "compose=photo", "geometric.crop_size=32",
            "geometric.min_pixels=1", "limit=1", "examples=1", f"output_dir={out}", *extra]


def test_bench_takes_the_checkpoints_of_a_training_output_directory(tiny_synth, ckpts, tmp_path, capsys):
    run = _demo(tmp_path / "demo", ckpts)
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, f"run={run}", "proposals=gt")) == 0
    err = capsys.readouterr().err
    report = json.loads((out / "results.json").read_text())
    used = report["info"]["checkpoints"]
    assert report["info"]["run"] == str(run)
    for branch in ("semantic", "geometric", "textural"):
        expected = (run / "runs" / branch / "checkpoints" / "best-epoch001.ckpt").resolve()
        assert used[branch]["path"] == str(expected) and used[branch]["which"] == "best", used[branch]
        assert used[branch]["from"] == str(run / "runs" / branch / "summary.json")
        assert used[branch]["finished"].startswith("2026-01-01") and used[branch]["export"] is False
        assert f"sdn3d-bench: {branch} checkpoint: {expected} (best checkpoint of the run finished " in err
    # the files loaded are the run's: the config records them, the generator's row names the run's textural file
    assert report["config"]["checkpoints"]["geometric"] == used["geometric"]["path"]
    assert report["info"]["generators"]["3d-sdn"]["checkpoint"] == used["textural"]["path"]
    assert report["summary"]["gt"]["evaluated"] == 1


def test_an_explicit_checkpoint_wins_over_the_runs(tiny_synth, ckpts, tmp_path, capsys):
    run = _demo(tmp_path / "demo", ckpts)
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, f"run={run}", "proposals=gt", f"checkpoints.textural={ckpts['textural']}")) == 0
    err = capsys.readouterr().err
    report = json.loads((out / "results.json").read_text())
    used = report["info"]["checkpoints"]
    assert used["textural"] == {"path": str(ckpts["textural"]), "from": "checkpoints.textural"}
    assert f"sdn3d-bench: textural checkpoint: {ckpts['textural']} (given)" in err
    assert report["info"]["generators"]["3d-sdn"]["checkpoint"] == str(ckpts["textural"])
    assert used["geometric"]["which"] == "best" and used["geometric"]["from"].startswith(str(run))


def test_without_run_the_given_checkpoints_are_recorded(tiny_synth, ckpts, tmp_path):
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, "proposals=gt", f"checkpoints.geometric={ckpts['geometric']}",
                      f"checkpoints.textural={ckpts['textural']}")) == 0
    report = json.loads((out / "results.json").read_text())
    assert report["info"]["run"] is None
    assert report["info"]["checkpoints"] == {
        "semantic": None, "geometric": {"path": str(ckpts["geometric"]), "from": "checkpoints.geometric"},
        "textural": {"path": str(ckpts["textural"]), "from": "checkpoints.textural"}}


@pytest.mark.parametrize(("case", "extra", "message"), [
    ("missing", (), r"run '.*nowhere' does not exist"),
    ("no_semantic", (), r"run '.*demo' lacks the semantic branch the benchmark needs \(semantic: no run\); found "
                        r"geometric: best-epoch001.ckpt \(best\); textural: .*give checkpoints.semantic=<file>"),
    ("failed_textural", ("proposals=gt",),
     r"lacks the textural branch the benchmark needs \(textural: 1 run\(s\) \(status failed\) but none ok"),
])
def test_a_run_without_a_needed_branch_exits_2_writing_nothing(tiny_synth, ckpts, tmp_path, capsys, case, extra,
                                                                message):
    run = tmp_path / ("nowhere" if case == "missing" else "demo")
    if case == "no_semantic":
        _demo(run, ckpts, ("geometric", "textural"))
    elif case == "failed_textural":
        _demo(run, ckpts, ("geometric",))
        _train_run(run / "runs" / "textural", "textural", ckpts["textural"], status="failed")
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, f"run={run}", *extra)) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-bench: error: run ") and err.count("\n") == 1 and re.search(message, err), err
    assert not out.exists()


def test_the_oracle_row_alone_needs_no_semantic_branch_in_the_run(tiny_synth, ckpts, tmp_path, capsys):
    run = _demo(tmp_path / "demo", ckpts, ("geometric", "textural"))
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, f"run={run}", "proposals=gt")) == 0
    assert "sdn3d-bench: semantic checkpoint: none" in capsys.readouterr().err
    assert json.loads((out / "results.json").read_text())["info"]["checkpoints"]["semantic"] is None


def test_a_second_run_replaces_only_its_own_outputs(tiny_synth, ckpts, tmp_path, capsys):
    """Issue 42 (2): sdn3d-bench replaces an earlier result only when the directory holds nothing but the files its
    results.json lists (``outputs``), and never when it holds one of its inputs (the benchmark file): a user's file
    there is named and kept, exit 2, the earlier result untouched. Before: both were deleted with the old result."""
    out = tmp_path / "bench"
    args = _args(tiny_synth, out, "proposals=gt", f"checkpoints.geometric={ckpts['geometric']}",
                 f"checkpoints.textural={ckpts['textural']}", "overwrite=true")
    assert main(args) == 0
    report = json.loads((out / "results.json").read_text())
    assert set(report["outputs"]) == {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert main(args) == 0  # its own outputs only: replaced
    (out / "notes.txt").write_text("mine")
    before = (out / "results.json").read_bytes()
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "'notes.txt'" in err and "refusing to replace it" in err and "Traceback" not in err, err
    assert (out / "notes.txt").read_text() == "mine" and (out / "results.json").read_bytes() == before
    # its own benchmark file inside the output directory: refused, kept
    (out / "notes.txt").unlink()
    bench_file = out / "mine.json"
    shutil.copy(tiny_synth / "vkitti_edit_benchmark.json", bench_file)
    assert main([*args, f"benchmark={bench_file}"]) == 2
    err = capsys.readouterr().err
    assert f"benchmark {str(bench_file)!r} lies inside output_dir" in err, err
    assert bench_file.is_file() and (out / "results.json").read_bytes() == before
    bench_file.unlink()
    # a result of the version before (its results.json lists no outputs) is replaced if it holds its files only
    report = json.loads(before)
    del report["outputs"]
    (out / "results.json").write_text(json.dumps(report))
    assert main(args) == 0 and "outputs" in json.loads((out / "results.json").read_text())
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".bench.")]  # no staging left behind


def test_a_run_where_every_entry_failed_exits_1(tiny_synth, ckpts, tmp_path, capsys, monkeypatch):
    """Issue 42 (9): before, sdn3d-bench exited 0 when every entry failed; now 1, naming the first error (the
    results, which list every entry's error, are written)."""
    import sdn3d.evaluation.edit_benchmark as evaluation

    def failing(entries, records, models, settings, *args, **kwargs):
        return [evaluation.EntryResult(index=i, key=f"k{i}", operations=1, errors={"3d-sdn": "no object at the point"})
                for i in range(2)]

    monkeypatch.setattr(evaluation, "run_benchmark", failing)
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, "proposals=gt", f"checkpoints.geometric={ckpts['geometric']}",
                      f"checkpoints.textural={ckpts['textural']}")) == 1
    err = capsys.readouterr().err
    assert "sdn3d-bench: error: every one of the 2 evaluations failed (first: entry 0 k0: no object at the point)" \
        in err, err
    assert (out / "results.json").is_file()


def test_a_kind_short_of_its_entries_is_warned_about_once(tiny_synth, ckpts, tmp_path, capsys):
    """Session 24: a synthetic benchmark whose sequences could not all get their occluder-removed pair scored that
    kind on fewer entries, or none, without a word. tiny_synth's one sequence has no pair (its partly hidden cars
    have no car in front to delete): sdn3d-bench counts its file against the dataset's manifest and warns once
    (stderr), and records it (results.json, table1.md)."""
    out = tmp_path / "bench"
    assert main(_args(tiny_synth, out, "proposals=gt", f"checkpoints.geometric={ckpts['geometric']}",
                      f"checkpoints.textural={ckpts['textural']}")) == 0
    err = capsys.readouterr().err
    warnings = [line for line in err.splitlines() if "warning" in line]
    assert warnings == ["sdn3d-bench: warning: 0 of the 1 'occluder_removed' benchmark entries asked for were made "
                        "(1 missing in 0001/clone: the partly hidden cars of test frames 6-7 have no car in front that "
                        "a point can pick (nearer, its box overlapping, its centre in the frame and 12 px from any "
                        "other's)); each missing one is an entry without operations, which sdn3d-bench skips"], err
    report = json.loads((out / "results.json").read_text())
    assert report["info"]["benchmark_short"] == {"occluder_removed": {"asked": 1, "made": 0, "short": [
        {"world": "0001", "variation": "clone", "missing": 1, "reason": "no_occluder",
         "why": warnings[0].split("0001/clone: ")[1].split("); each")[0]}]}}  # the edit pair was made
    assert "**Fewer entries than asked for.** 0 of the 1 'occluder_removed'" in (out / "table1.md").read_text()
