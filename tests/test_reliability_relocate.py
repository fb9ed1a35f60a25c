"""Issue 32, runs are relocatable; ``run=`` never answers from the wrong run.

Before: resuming a copied run wrote its new checkpoints, inference export and logs into the absolute directory its
``config.yaml`` recorded (creating it when the original was gone, mixing into it when not), and the copy's summary
named stale files; ``run=`` on a copied tree loaded the original's files by their recorded absolute paths; a
``summary.json`` that could not be read was skipped, so ``run=`` silently served an older run of that branch. Now
every path a run writes or reads later is taken from the run directory it is resumed or loaded from: the saved
config refers to ``${run_dir}`` (older, fully resolved configs are rebased), the checkpoint callbacks' recorded
paths are rebased when the checkpoint is loaded, and ``sdn3d.runs`` reads a summary's files from its own directory.

One tiny semantic run (2 epochs of 1 batch on the 160x64 synthetic data) is trained per module; each test copies it.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import torch
from helpers.tiny_training import resume, train_tiny
from omegaconf import OmegaConf

from sdn3d.errors import UserInputError
from sdn3d.runs import find_run_checkpoints
from sdn3d.training.resume import resolve_resume


@pytest.fixture(scope="module")
def trained(tiny_synth, tmp_path_factory) -> Path:
    """A finished run (status ok, 2 of 2 epochs, tested) with its inference export and CSV logs."""
    run_dir = tmp_path_factory.mktemp("trained") / "run"
    assert train_tiny(tiny_synth, run_dir)["status"] == "ok"
    return run_dir


def test_the_saved_config_refers_to_the_run_directory(trained):
    text = (trained / "config.yaml").read_text()
    assert "dirpath: ${run_dir}/checkpoints" in text and "save_dir: ${run_dir}" in text
    assert "default_root_dir: ${run_dir}" in text and "data: ${data}" in text
    assert text.count(str(trained)) == 1  # run_dir itself, which resume= sets to where the run is


def test_a_copied_run_resumes_into_itself_with_the_original_deleted(trained, tmp_path):
    original, copy = tmp_path / "original", tmp_path / "archive" / "copy"
    shutil.copytree(trained, original)
    saved = original / "config.yaml"  # as the run was saved where it trained
    saved.write_text(saved.read_text().replace(str(trained), str(original)))
    shutil.copytree(original, copy)
    shutil.rmtree(original)
    summary = resume(copy, "trainer.max_epochs=3")
    assert not original.exists()  # nothing written where the run was trained
    assert summary["status"] == "ok" and summary["epoch"] == 3 and summary["run_dir"] == str(copy.resolve())
    for key in ("best_ckpt", "last_ckpt"):
        assert summary[key].startswith(str(copy.resolve()) + "/checkpoints/"), summary[key]
    last = torch.load(copy / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)
    assert last["epoch"] == 3
    states = [s for k, s in last["callbacks"].items() if k.startswith("ModelCheckpoint")]
    assert states and all(s["dirpath"] == str((copy / "checkpoints").resolve()) for s in states)
    # the best-checkpoint selection carried over (rebased, not restarted): one best file, the one recorded
    best = [s for s in states if s.get("best_k_models")]
    assert best and all(Path(p).parent == (copy / "checkpoints").resolve() for s in best for p in s["best_k_models"])
    assert len(list((copy / "checkpoints").glob("best-*.ckpt"))) == 1
    assert (copy / "csv" / "metrics.csv").is_file()
    chosen, missing = find_run_checkpoints(copy.parent)  # run= serves the copy's own files
    assert not missing.get("semantic")
    assert chosen["semantic"]["path"] == str((copy / "checkpoints" / "inference.pt").resolve())
    assert chosen["semantic"]["export"] and chosen["semantic"]["checkpoint"].startswith(str(copy.resolve()))


def test_run_on_a_copy_loads_the_copys_files_not_the_originals(trained, tmp_path):
    copy = tmp_path / "runs" / "semantic"
    shutil.copytree(trained, copy)  # the original is still there, at the paths the copy's summary records
    recorded = json.loads((copy / "summary.json").read_text())
    assert recorded["best_ckpt"].startswith(str(trained.resolve()))
    chosen, _ = find_run_checkpoints(copy.parent)
    assert chosen["semantic"]["checkpoint"] == str((copy / Path(recorded["best_ckpt"]).relative_to(trained)).resolve())
    assert chosen["semantic"]["path"] == str((copy / "checkpoints" / "inference.pt").resolve())


def test_a_run_saved_with_absolute_paths_is_rebased_onresume(trained, tmp_path):
    """A config.yaml written before runs were relocatable: every path resolved, under the run_dir it trained in."""
    run = tmp_path / "moved"
    shutil.copytree(trained, run)
    old = "/somewhere/else/run"
    config = OmegaConf.load(trained / "config.yaml")
    config.run_dir = old
    (run / "config.yaml").write_text(OmegaConf.to_yaml(config, resolve=True))
    assert f"dirpath: {old}/checkpoints" in (run / "config.yaml").read_text()
    cfg = resolve_resume(OmegaConf.create({"resume": str(run)}), [f"resume={run}"])
    assert cfg.run_dir == str(run) and cfg.trainer.default_root_dir == str(run)
    assert cfg.callbacks.model_checkpoint.dirpath == cfg.callbacks.step_checkpoint.dirpath == f"{run}/checkpoints"
    assert cfg.logger.csv.save_dir == str(run)
    assert cfg.data.root == config.data.root  # a path outside the run directory stays as it was
    assert old not in OmegaConf.to_yaml(cfg, resolve=True)


def test_run_refuses_an_unreadable_summary_instead_of_serving_an_older_run(trained, tmp_path):
    runs = tmp_path / "runs"
    older, newer = runs / "semantic" / "older", runs / "semantic" / "newer"
    shutil.copytree(trained, older)
    shutil.copytree(trained, newer)
    (newer / "summary.json").write_text('{"branch": "semantic", "status": "ok", "finis')  # a damaged record
    with pytest.raises(UserInputError, match=rf"run summary '{newer / 'summary.json'}' is unreadable .*may record a "
                                             r"branch's newest run, so no run is chosen"):
        find_run_checkpoints(runs)
    assert find_run_checkpoints(older)[0]["semantic"]["checkpoint"].startswith(str(older.resolve()))
