"""Inference exports (issue 19): weights-only files per branch, loadable without Lightning wherever a checkpoint
is, preferred by ``run=`` when made from the selected checkpoint, written by ``sdn3d-train`` and
``sdn3d-export-weights``; and the edit path never imports Lightning, torchmetrics or TensorBoard."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from faults.checkpoints import hydra_config_with_target, truncated_copy
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d import inference_export
from sdn3d.cli.export_weights import main as export_main
from sdn3d.errors import UserInputError
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.inference_export import (
    EXPORT_FORMAT,
    EXPORT_NAME,
    EXPORT_VERSION,
    load_branch_weights,
    module_with_weights,
)
from sdn3d.models import Models
from sdn3d.runs import export_checkpoint, export_run_checkpoint, find_run_checkpoints
from sdn3d.semantic.predict import SemanticPredictor
from sdn3d.textural.renderer import TexturalRenderer

BRANCHES = ("semantic", "geometric", "textural")
LOADERS = {"semantic": SemanticPredictor.from_checkpoint, "geometric": GeometricPredictor.from_checkpoint,
           "textural": TexturalRenderer.from_checkpoint}
REPO = Path(__file__).resolve().parents[1]
#: What a training module's checkpoint carries besides the predictor's weights.
TRAINING_STATE = ("optimizer_states", "loops", "callbacks", "lr_schedulers")


def _with_training_state(path: Path, seed: int) -> Path:
    """Turn a tiny ``{'state_dict', 'hyper_parameters'}`` file into what Lightning writes: optimizer moments,
    loop and callback state, and (textural) the discriminator's weights."""
    ckpt = torch.load(path, weights_only=True)
    generator = torch.Generator().manual_seed(seed)
    moments = {i: {"exp_avg": torch.randn(v.shape, generator=generator), "exp_avg_sq": torch.rand(v.shape)}
               for i, v in enumerate(ckpt["state_dict"].values()) if v.is_floating_point()}
    ckpt |= {"epoch": 3, "global_step": 12, "pytorch-lightning_version": "2.6.6",
             "optimizer_states": [{"state": moments, "param_groups": [{"lr": 1e-3, "params": list(moments)}]}],
             "loops": {"fit_loop": {"epoch_progress": {"current": 3}}}, "callbacks": {"ModelCheckpoint": {}},
             "lr_schedulers": []}
    if any(k.startswith("generator.") for k in ckpt["state_dict"]):
        ckpt["state_dict"]["discriminator.scale0.weight"] = torch.randn(8, 4, 4, 4, generator=generator)
    torch.save(ckpt, path)
    return path


def _training_run(root: Path, seed: int = 0) -> dict[str, Path]:
    """Per branch a ``sdn3d-train`` run directory: ``<root>/<branch>/checkpoints/best.ckpt`` (training state
    included), ``summary.json`` (status ok, that best checkpoint) and, for geometric, ``config.yaml``."""
    tiny = write_checkpoints(root / "tiny", seed)
    out = {}
    for branch in BRANCHES:
        run = root / branch
        ckpt = run / "checkpoints" / "best.ckpt"
        ckpt.parent.mkdir(parents=True)
        shutil.move(tiny[branch], ckpt)
        _with_training_state(ckpt, seed)
        (run / "summary.json").write_text(json.dumps({
            "branch": branch, "status": "ok", "best_ckpt": str(ckpt), "last_ckpt": None,
            "finished": "2026-01-01T00:00:00+00:00", "metrics": {"val/miou": 0.9, "val/pq": 0.9}}))
        out[branch] = ckpt
    hydra_config_with_target(root / "geometric" / "config.yaml", root / "instantiated", crop_size=48, margin=0.2)
    return out


@pytest.fixture
def run(tmp_path) -> tuple[Path, dict[str, Path]]:
    return tmp_path / "run", _training_run(tmp_path / "run")


def test_export_holds_the_predictor_weights_only_and_records_its_source(run, tmp_path):
    _, ckpts = run
    for branch, ckpt in ckpts.items():
        export = export_checkpoint(ckpt)
        assert export == ckpt.parent / EXPORT_NAME
        content = torch.load(export, weights_only=True)
        original = torch.load(ckpt, weights_only=True)
        assert content["format"] == EXPORT_FORMAT and content["format_version"] == EXPORT_VERSION
        assert content["branch"] == branch
        assert not set(TRAINING_STATE) & set(content), sorted(content)
        wanted = {k for k in original["state_dict"] if not k.startswith(("discriminator.",))}
        assert set(content["state_dict"]) == wanted
        for key in wanted:
            assert torch.equal(content["state_dict"][key], original["state_dict"][key]), key
        assert content["hyper_parameters"] == original["hyper_parameters"]
        source = content["source"]
        assert source["sha256"] == hashlib.sha256(ckpt.read_bytes()).hexdigest()
        assert (source["file"], source["size"], source["epoch"], source["global_step"]) == \
            (ckpt.name, ckpt.stat().st_size, 3, 12)
        assert export.stat().st_size < 0.6 * ckpt.stat().st_size, (export.stat().st_size, ckpt.stat().st_size)
        assert content["settings"] == ({"crop_size": 48, "margin": 0.2} if branch == "geometric" else {})
    assert not (tmp_path / "run" / "instantiated").exists()  # the run config is read, never instantiated


def test_predictions_from_an_export_equal_those_from_its_checkpoint(run):
    _, ckpts = run
    exports = {b: export_checkpoint(c, c.parent / f"{b}.pt") for b, c in ckpts.items()}
    image = torch.rand(1, 3, 64, 160)
    a, b = SemanticPredictor.from_checkpoint(ckpts["semantic"]), SemanticPredictor.from_checkpoint(exports["semantic"])
    seg_a, seg_b = a(image), b(image)
    assert torch.equal(seg_a.probability, seg_b.probability) and torch.equal(seg_a.instance, seg_b.instance)

    crops, boxes = torch.rand(3, 3, 32, 32), torch.tensor([[10.0, 20, 40, 50], [60, 10, 90, 40], [5, 5, 30, 60]])
    intrinsics = torch.tensor([[93.0, 124.0, 79.5, 31.5]]).expand(3, 4)
    geo_a = GeometricPredictor.from_checkpoint(ckpts["geometric"]).predict(crops, None, boxes, intrinsics)
    geo_b = GeometricPredictor.from_checkpoint(exports["geometric"]).predict(crops, None, boxes, intrinsics)
    assert geo_a.keys() == geo_b.keys() and all(torch.equal(geo_a[k], geo_b[k]) for k in geo_a)

    label = torch.randint(0, 14, (1, 64, 160))
    L = label.clone()
    tex_a = TexturalRenderer.from_checkpoint(ckpts["textural"])
    tex_b = TexturalRenderer.from_checkpoint(exports["textural"])
    assert torch.equal(tex_a.reconstruct(image, label, L), tex_b.reconstruct(image, label, L))


def test_the_network_takes_over_the_weights_without_random_initialisation(run):
    """module_with_weights builds with unallocated parameters: no tensor is left without storage, the
    non-persistent buffers (made from constants) are right, and the weights are the file's, not copies."""
    _, ckpts = run
    weights = load_branch_weights(export_checkpoint(ckpts["geometric"]), "geometric")
    predictor = GeometricPredictor.from_weights(weights)
    net = predictor.net
    assert not any(t.is_meta for t in [*net.parameters(), *net.buffers()])
    assert torch.equal(net.templates, torch.arange(8)) and torch.allclose(net.mean.flatten(),
                                                                          torch.tensor([0.485, 0.456, 0.406]))
    some = next(k for k in weights.state_dict if k.endswith("weight"))
    assert net.get_parameter(some[len("net."):]).data_ptr() == weights.state_dict[some].data_ptr()

    class ComputedBuffer(torch.nn.Module):  # a buffer computed from an initialised parameter: the ordinary way
        def __init__(self) -> None:
            super().__init__()
            self.weight = torch.nn.Parameter(torch.empty(3))
            torch.nn.init.ones_(self.weight)
            self.register_buffer("doubled", self.weight.detach() * 2, persistent=False)

    built = module_with_weights(ComputedBuffer, {"weight": torch.full((3,), 5.0)}, "x.pt")
    assert torch.equal(built.doubled, torch.full((3,), 2.0)) and torch.equal(built.weight, torch.full((3,), 5.0))
    with pytest.raises(UserInputError, match="'x.pt'.*do not fit"):
        module_with_weights(ComputedBuffer, {"weight": torch.zeros(4)}, "x.pt")


def test_bad_exports_are_clear_errors_naming_the_file(run, tmp_path):
    _, ckpts = run
    export = export_checkpoint(ckpts["semantic"], tmp_path / "semantic.pt")
    for branch in ("geometric", "textural"):
        with pytest.raises(UserInputError, match="holds the semantic branch") as info:
            LOADERS[branch](export)
        assert str(export) in str(info.value) and f"not the {branch} branch" in str(info.value)
    content = torch.load(export, weights_only=True)
    cases = {"newer.pt": content | {"format_version": EXPORT_VERSION + 1},
             "no_branch.pt": content | {"branch": "audio"},
             "not_tensors.pt": content | {"state_dict": {"net.x": [1.0]}},
             "other_weights.pt": content | {"state_dict": {"discriminator.x": torch.zeros(1)}},
             "empty.pt": content | {"state_dict": {}},
             "hparams_list.pt": content | {"hyper_parameters": [1]},
             "no_source.pt": {k: v for k, v in content.items() if k != "source"}}
    for name, bad in cases.items():
        torch.save(bad, tmp_path / name)
        with pytest.raises(UserInputError) as info:
            SemanticPredictor.from_checkpoint(tmp_path / name)
        assert str(tmp_path / name) in str(info.value) and "\n" not in str(info.value), (name, info.value)
    assert "format_version" in str(pytest.raises(UserInputError, SemanticPredictor.from_checkpoint,
                                                 tmp_path / "newer.pt").value)
    cut = truncated_copy(export, tmp_path / "cut.pt", 0.5)
    with pytest.raises(UserInputError, match="could not read checkpoint"):
        SemanticPredictor.from_checkpoint(cut)
    torch.save({"format": "something else", "weights": torch.zeros(2)}, tmp_path / "other.pt")
    with pytest.raises(UserInputError, match="nor an sdn3d inference export"):
        SemanticPredictor.from_checkpoint(tmp_path / "other.pt")
    torch.save({"state_dict": {"w": torch.zeros(2)}}, tmp_path / "nothing.ckpt")
    with pytest.raises(UserInputError, match="holds none of the branches"):
        export_checkpoint(tmp_path / "nothing.ckpt")
    with pytest.raises(UserInputError, match="would replace the checkpoint"):
        export_checkpoint(ckpts["textural"], ckpts["textural"])
    assert ckpts["textural"].is_file()


def test_a_copied_geometric_export_keeps_its_run_crop_settings(run, tmp_path):
    _, ckpts = run
    export = export_checkpoint(ckpts["geometric"], tmp_path / "elsewhere" / "geometric.pt")
    assert not (export.parent.parent / "config.yaml").exists()
    models = Models.from_checkpoints(geometric=export)
    assert (models.crop_size, models.margin) == (48, 0.2)
    assert Models.from_checkpoints(geometric=export, crop_size=40, margin=0.1).crop_size == 40
    content = torch.load(export, weights_only=True)
    torch.save(content | {"settings": {"crop_size": "big"}}, tmp_path / "bad_settings.pt")
    with pytest.raises(UserInputError, match="bad_settings.pt"):
        Models.from_checkpoints(geometric=tmp_path / "bad_settings.pt")


def test_the_traffic_side_reaches_the_geometric_branchs_lamp_cue_and_a_bad_one_is_named(run):
    """geometric.traffic (sdn3d-edit, sdn3d-bench): which end a car cut by the image border shows is read by the
    loaded predictor's lamp cue; right-hand by default; a wrong value is refused by its key."""
    from sdn3d.geometric.lamps import Traffic

    _, ckpts = run
    assert Models.from_checkpoints(geometric=ckpts["geometric"]).geometric.lamp_cue.traffic is Traffic.RIGHT
    for side in ("left", "none", Traffic.RIGHT):
        assert Models.from_checkpoints(geometric=ckpts["geometric"], traffic=side).geometric.lamp_cue.traffic == side
    with pytest.raises(UserInputError, match=r"geometric.traffic must be one of right, left, none, got 'up'"):
        Models.from_checkpoints(geometric=ckpts["geometric"], traffic="up")


def test_the_semantic_predictor_runs_at_its_runs_training_size_from_the_run_or_a_copied_export(run, tmp_path):
    """The semantic run's config says the frames it trained on (``data.image_size``, unless the datamodule's own
    ``image_size`` says otherwise); the loaded predictor feeds its network images resized to about that many pixels
    at their own aspect (the demo's branch, trained at 312x96, found a quarter of the cars at 624x192), and a copied
    export keeps the size; a bad size is refused naming the file."""
    root, ckpts = run
    config = root / "semantic" / "config.yaml"
    config.write_text("data:\n  image_size: [96, 32]\ndatamodule:\n  image_size: null\n")
    seen = []

    def network_input_sizes(predictor: SemanticPredictor, *sizes: tuple[int, int]) -> list[tuple[int, int]]:
        seen.clear()
        hook = predictor.net.register_forward_pre_hook(lambda _, args: seen.append(tuple(args[0].shape[-2:])))
        try:
            for w, h in sizes:
                out = predictor(torch.rand(3, h, w))
                assert out.label.shape == out.instance.shape == (1, h, w)
        finally:
            hook.remove()
        return [(w, h) for h, w in seen]

    sem = Models.from_checkpoints(semantic=ckpts["semantic"]).semantic
    assert sem.trained_size == (96, 32)
    assert network_input_sizes(sem, (192, 64), (96, 32), (120, 64)) == [(96, 32), (96, 32), (72, 40)]
    config.write_text("data:\n  image_size: [96, 32]\ndatamodule:\n  image_size: [64, 48]\n")
    export = export_checkpoint(ckpts["semantic"], tmp_path / "elsewhere" / "semantic.pt")
    config.unlink()
    assert torch.load(export, weights_only=True)["settings"] == {"image_size": [64, 48]}
    sem = Models.from_checkpoints(semantic=export).semantic
    assert sem.trained_size == (64, 48) and network_input_sizes(sem, (128, 96)) == [(64, 48)]
    # without a size anywhere the network sees the image as it is (as before)
    assert Models.from_checkpoints(semantic=ckpts["semantic"]).semantic.trained_size is None
    # a user's semantic.size wins over the run's (a real photo may want another scale)
    config.write_text("data:\n  image_size: [96, 32]\n")
    sem = Models.from_checkpoints(semantic=ckpts["semantic"], semantic_size=[128, 40]).semantic
    assert network_input_sizes(sem, (192, 64), (64, 64)) == [(128, 40), (128, 40)]
    with pytest.raises(UserInputError, match=r"semantic.size must be \[W, H\], two positive integers, got \[0, 40\]"):
        Models.from_checkpoints(semantic=ckpts["semantic"], semantic_size=(0, 40))
    config.write_text("data:\n  image_size: [96, -32]\n")
    with pytest.raises(UserInputError, match=r"config.yaml.*data.image_size must be \[W, H\], two positive"):
        Models.from_checkpoints(semantic=ckpts["semantic"])
    content = torch.load(export, weights_only=True)
    torch.save(content | {"settings": {"image_size": "big"}}, tmp_path / "bad_size.pt")
    with pytest.raises(UserInputError, match="bad_size.pt.*settings image_size"):
        Models.from_checkpoints(semantic=tmp_path / "bad_size.pt")


def test_run_lookup_prefers_an_export_made_from_the_selected_checkpoint(run, tmp_path, monkeypatch, caplog):
    root, ckpts = run
    chosen, _ = find_run_checkpoints(root)
    assert all(chosen[b]["path"] == str(ckpts[b].resolve()) and not chosen[b]["export"] for b in BRANCHES)
    exports = {b: export_run_checkpoint(root / b / "summary.json") for b in BRANCHES}
    hashed = []
    real_sha = inference_export.file_sha256
    monkeypatch.setattr(inference_export, "file_sha256", lambda p: hashed.append(Path(p)) or real_sha(p))
    chosen, _ = find_run_checkpoints(root)
    for b in BRANCHES:
        assert chosen[b]["path"] == str(exports[b]) and chosen[b]["export"], chosen[b]
        assert chosen[b]["checkpoint"] == str(ckpts[b].resolve()) and chosen[b]["which"] == "best"
    assert hashed == []  # unchanged checkpoints (name, size, time) are not hashed

    os.utime(ckpts["geometric"], ns=(1, 1))  # same bytes, another time (a copy): the SHA-256 decides, and matches
    chosen, _ = find_run_checkpoints(root)
    assert chosen["geometric"]["export"] and hashed == [ckpts["geometric"].resolve()]

    other = _training_run(tmp_path / "other", seed=1)  # the checkpoint replaced by another one: a stale export
    shutil.copy(other["semantic"], ckpts["semantic"])
    shutil.copy(other["textural"], ckpts["textural"])
    (ckpts["textural"].parent / EXPORT_NAME).write_bytes(b"not an export")
    with caplog.at_level("WARNING", logger="sdn3d.runs"):
        chosen, _ = find_run_checkpoints(root)
    for b in ("semantic", "textural"):
        assert chosen[b]["path"] == str(ckpts[b].resolve()) and not chosen[b]["export"]
    warned = " ".join(r.getMessage() for r in caplog.records)
    assert f"ignoring {ckpts['semantic'].parent / EXPORT_NAME}" in warned and "best.ckpt" in warned
    assert f"ignoring {ckpts['textural'].parent / EXPORT_NAME}" in warned
    assert chosen["geometric"]["export"]


def test_export_weights_cli(run, tmp_path, capsys):
    root, ckpts = run
    assert export_main([str(ckpts["textural"])]) == 0
    assert (ckpts["textural"].parent / EXPORT_NAME).is_file()
    assert export_main([str(ckpts["semantic"]), str(tmp_path / "sem.pt")]) == 0
    assert load_branch_weights(tmp_path / "sem.pt", "semantic").is_export
    assert "sem.pt" in capsys.readouterr().out
    assert export_main(["--run", str(root)]) == 0
    out = capsys.readouterr().out
    assert all(str(ckpts[b]) in out and str(ckpts[b].parent / EXPORT_NAME) in out for b in BRANCHES), out
    garbage = tmp_path / "garbage.ckpt"
    garbage.write_bytes(b"no checkpoint")
    cases = (([str(garbage)], str(garbage)), ([], "give a checkpoint"),
             ([str(tmp_path / "missing.ckpt")], "missing.ckpt"), (["--run", str(tmp_path / "nope")], "nope"))
    for argv, needle in cases:
        assert export_main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith("sdn3d-export-weights: error:") and needle in err and err.count("\n") == 1, err


#: Packages the editing path must never import (training only).
TRAINING_PACKAGES = ("lightning", "lightning_fabric", "pytorch_lightning", "lightning_utilities", "torchmetrics",
                     "tensorboard", "lightning_modules", "datamodules")


def test_edit_from_exports_imports_no_training_package(run, tmp_path):
    """A whole sdn3d-edit call from run= with exports, in a fresh interpreter: which packages it imported."""
    root, _ = run
    assert export_main(["--run", str(root)]) == 0
    rgb = np.random.default_rng(0).integers(0, 256, (64, 160, 3), dtype=np.uint8)
    Image.fromarray(rgb).save(tmp_path / "street.png")
    (tmp_path / "ops.yaml").write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    args = [f"input.image={tmp_path / 'street.png'}", "image_size=[160,64]", f"edits={tmp_path / 'ops.yaml'}",
            "input.intrinsics={fx:93,fy:124,cx:79.5,cy:31.5}", f"run={root}", f"output_dir={tmp_path / 'out'}"]
    code = ("import sys\n"
            "from sdn3d.cli.edit import main\n"
            f"code = main({args!r})\n"
            f"found = sorted(m for m in sys.modules if m.split('.')[0] in {TRAINING_PACKAGES!r})\n"
            "print('FOUND', code, *found)\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                            env={**os.environ, "OMP_NUM_THREADS": "1"})
    line = next((x for x in result.stdout.splitlines() if x.startswith("FOUND")), None)
    assert line is not None, result.stderr[-3000:]
    assert line.split()[1:] == ["0"], line
    loaded = json.loads((tmp_path / "out" / "edit.json").read_text())["checkpoints"]
    assert all(loaded[b]["path"].endswith(EXPORT_NAME) and loaded[b]["export"] for b in BRANCHES), loaded


def test_an_edit_call_maps_each_export_and_unpickles_it_once(run, tmp_path, monkeypatch):
    """sdn3d-edit (one call, one process) maps the weights (``torch.load(mmap=True)``) and unpickles each inference
    export once, though two steps read it (its source record when run= is resolved, its weights when the models
    load); the library's default, which sdn3d-app's loading keeps, reads each file whole."""
    from sdn3d.cli.edit import main as edit_main

    root, _ = run
    assert export_main(["--run", str(root)]) == 0
    exports = {b: (root / b / "checkpoints" / EXPORT_NAME).resolve() for b in BRANCHES}
    loads = []
    real_load = torch.load

    def recorded_load(f, *args, **kwargs):
        loads.append((Path(f).resolve(), kwargs.get("mmap")))
        return real_load(f, *args, **kwargs)

    monkeypatch.setattr(torch, "load", recorded_load)
    rgb = np.random.default_rng(0).integers(0, 256, (64, 160, 3), dtype=np.uint8)
    Image.fromarray(rgb).save(tmp_path / "street.png")
    (tmp_path / "ops.yaml").write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    assert edit_main([f"input.image={tmp_path / 'street.png'}", "image_size=[160,64]", f"edits={tmp_path / 'ops.yaml'}",
                      "input.intrinsics={fx:93,fy:124,cx:79.5,cy:31.5}", f"run={root}",
                      f"output_dir={tmp_path / 'out'}"]) == 0
    assert sorted(x for x in loads if x[0] in exports.values()) == sorted((p, True) for p in exports.values()), loads
    loads.clear()
    Models.from_checkpoints(**exports)
    assert sorted(loads) == sorted((p, False) for p in exports.values()), loads


def test_training_writes_the_export_of_its_selected_checkpoint(tiny_synth, tmp_path):
    from hydra import compose, initialize_config_dir

    from lightning_modules.train import run_training

    run_dir = tmp_path / "run"
    overrides = ["branch=geometric", "experiment=demo", f"data.root={tiny_synth}", "data.image_size=[160,64]",
                 f"run_dir={run_dir}", f"summary_file={tmp_path / 'summary.jsonl'}",  # not outputs/ in the repo
                 "trainer.max_epochs=1", "trainer.limit_train_batches=1",
                 "trainer.limit_val_batches=1", "trainer.enable_progress_bar=false", "~callbacks.progress_bar",
                 "logger=none", "test_after_fit=false", "datamodule.batch_size=4", "datamodule.crop_size=32",
                 "datamodule.min_pixels=0"]
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        cfg = compose("train", overrides=overrides)
    summary = run_training(cfg, [])
    export = run_dir / "checkpoints" / EXPORT_NAME
    selected = Path(summary["best_ckpt"] or summary["last_ckpt"])
    weights = load_branch_weights(export, "geometric")
    assert weights.source["file"] == selected.name and weights.settings["crop_size"] == 32
    assert weights.source["sha256"] == hashlib.sha256(selected.read_bytes()).hexdigest()
    chosen, _ = find_run_checkpoints(run_dir)
    assert chosen["geometric"]["path"] == str(export) and chosen["geometric"]["checkpoint"] == str(selected)
