"""The Hydra configs compose: every experiment for every branch it has a recipe for, the demo's budgets,
command-line overrides over experiments, the renderer group, fault policies and the refinement settings."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest
import yaml
from hydra import compose, initialize_config_dir
from hydra.errors import MissingConfigException
from hydra.utils import get_class, instantiate
from omegaconf import OmegaConf

REPO = Path(__file__).resolve().parents[1]
CONF = REPO / "conf"
BRANCHES = ("semantic", "geometric", "textural")
EXPERIMENTS = sorted(p.stem for p in (CONF / "experiment").glob("*.yaml"))


def _compose(overrides: list[str], name: str = "train"):
    from sdn3d.cli._schemas import register

    register(name)  # the inference configs' structured schemas (conf/edit.yaml etc. name them first)
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        return compose(name, overrides=overrides)


def _recipe(experiment: str, branch: str) -> str:
    """The recipe an experiment picks for a branch (its `override /recipe: ${branch}_<name>` line)."""
    text = (CONF / "experiment" / f"{experiment}.yaml").read_text()
    match = re.search(r"override /recipe: \$\{branch\}_(\w+)", text)
    assert match, f"experiment/{experiment}.yaml picks no recipe"
    return f"{branch}_{match.group(1)}"


PAIRS = [(b, e) for e in EXPERIMENTS for b in BRANCHES if (CONF / "recipe" / f"{_recipe(e, b)}.yaml").is_file()]


def test_the_documented_experiments_exist():
    for name in ("demo", "table2", "table2_large", "semantic_cpu", "semantic_cpu_fullres", "semantic_gpu",
                 "paper_vkitti", "paper_cityscapes", "demo_short", "demo_medium", "demo_long"):
        assert name in EXPERIMENTS
    assert ("geometric", "table2") in PAIRS and ("semantic", "table2") not in PAIRS
    assert ("geometric", "table2_large") in PAIRS and ("textural", "table2_large") not in PAIRS
    assert all((b, e) in PAIRS for b in BRANCHES for e in ("demo", "paper_vkitti", "paper_cityscapes",
                                                           "demo_short", "demo_medium", "demo_long"))


@pytest.mark.parametrize(("branch", "experiment"), PAIRS)
def test_every_experiment_composes_for_its_branches(branch, experiment, tmp_path):
    cfg = _compose([f"branch={branch}", f"experiment={experiment}", f"run_dir={tmp_path}"])
    resolved = OmegaConf.to_container(cfg, resolve=True)  # every interpolation resolves
    assert resolved["branch_name"] == branch
    assert "preset" not in resolved and "presets" not in resolved
    for node in ("model", "datamodule", "trainer"):
        get_class(resolved[node]["_target_"])  # importable
    assert resolved["model"]["_target_"].startswith("lightning_modules.")
    assert resolved["datamodule"]["_target_"].startswith("datamodules.")
    # the fault policies reach the constructors
    assert resolved["model"]["nonfinite"] == resolved["fault"]["nonfinite"] == "stop"
    assert resolved["datamodule"]["corrupt_sample"] == resolved["fault"]["corrupt_sample"] == "fail"
    # the experiment's recipe is applied over the branch defaults
    recipe = OmegaConf.load(CONF / "recipe" / f"{_recipe(experiment, branch)}.yaml")
    for key in ("model", "datamodule", "trainer"):
        for field, value in (recipe.get(key) or {}).items():
            assert resolved[key][field] == OmegaConf.to_container(OmegaConf.create({"v": value}))["v"], (key, field)


@pytest.mark.parametrize("experiment", [e for e in EXPERIMENTS if any(p[1] == e for p in PAIRS)])
def test_an_experiment_a_branch_lacks_fails_naming_what_exists(experiment, tmp_path):
    for branch in BRANCHES:
        if (branch, experiment) in PAIRS:
            continue
        with pytest.raises(MissingConfigException, match=f"recipe/{_recipe(experiment, branch)}") as err:
            _compose([f"branch={branch}", f"experiment={experiment}", f"run_dir={tmp_path}"])
        others = [b for b in BRANCHES if (b, experiment) in PAIRS]
        assert all(_recipe(experiment, b) in str(err.value) for b in others)


@pytest.mark.parametrize("branch", BRANCHES)
def test_the_command_line_wins_over_the_experiment(branch, tmp_path):
    assert _compose([f"branch={branch}", "experiment=demo", f"run_dir={tmp_path}"]).trainer.max_epochs != 7
    cfg = _compose([f"branch={branch}", "experiment=demo", "trainer.max_epochs=7", "datamodule.batch_size=5",
                    f"run_dir={tmp_path}"])
    assert cfg.trainer.max_epochs == 7 and cfg.datamodule.batch_size == 5
    # whatever the order on the command line
    cfg = _compose([f"branch={branch}", "trainer.max_epochs=7", "experiment=demo_long", f"run_dir={tmp_path}"])
    assert cfg.trainer.max_epochs == 7
    # a multirun job gets its values escaped; they arrive as typed
    cfg = _compose([f"branch={branch}", "experiment=demo", "trainer.max_time=00\\:01\\:00\\:00", f"run_dir={tmp_path}"])
    assert cfg.trainer.max_time == "00:01:00:00"


def test_no_experiment_is_the_branch_defaults(tmp_path):
    cfg = _compose(["branch=semantic", f"run_dir={tmp_path}"])
    assert cfg.trainer.max_epochs == 25 and list(cfg.data.image_size) == [624, 192]


# What each budget trains (the values conf/demo.yaml and conf/budget/*.yaml passed as override lists before).
BUDGETS = {
    "short": {"semantic": {"trainer.max_epochs": 14, "model.lr": 0.004, "trainer.limit_train_batches": None,
                           "model.decoder": "skip", "model.optimizer": "adamw", "model.class_weighting": "enet",
                           "model.channels": [16, 16, 32, 64, 64, 128, 128, 128], "data.image_size": [312, 96]},
              "geometric": {"model.pred_epochs": 8, "model.joint_epochs": 2, "trainer.max_epochs": 10,
                            "trainer.limit_train_batches": 4, "datamodule.crop_size": 64},
              "textural": {"model.lr_constant_epochs": 4, "model.lr_decay_epochs": 4, "trainer.max_epochs": 8,
                           "trainer.limit_train_batches": 10, "model.ngf": 16, "datamodule.maps": "gt"}},
    "medium": {"semantic": {"trainer.max_epochs": 30, "model.lr": 0.002, "model.decoder": "skip",
                            "model.optimizer": "adamw", "data.image_size": [312, 96],
                            "trainer.check_val_every_n_epoch": 3},
               "geometric": {"model.pred_epochs": 40, "model.joint_epochs": 20, "trainer.max_epochs": 60},
               "textural": {"trainer.max_epochs": 12, "trainer.limit_train_batches": 1.0,
                            "trainer.limit_val_batches": 16, "trainer.limit_test_batches": 1.0,
                            "datamodule.maps": "predicted"}},
    "long": {"semantic": {"data.image_size": [624, 192], "trainer.max_epochs": 40, "model.lr": 0.01,
                          "trainer.limit_train_batches": 1.0, "trainer.check_val_every_n_epoch": 5},
             "geometric": {"model.pred_epochs": 40, "model.joint_epochs": 20, "trainer.max_epochs": 60},
             "textural": {"model.ngf": 32, "model.n_blocks": 6, "datamodule.image_size": [624, 192],
                          "datamodule.batch_size": 1, "trainer.max_epochs": 12, "trainer.log_every_n_steps": 50,
                          "datamodule.maps": "predicted"}},
}


@pytest.mark.parametrize("budget", sorted(BUDGETS))
def test_the_demo_passes_experiments_and_machine_options_only(budget, tmp_path):
    from sdn3d.cli.demo import _train_command

    demo = _compose([f"budget={budget}", "device=cuda"], "demo")
    assert list(demo.train.common) == [] and all(list(demo.train[b]) == [] for b in BRANCHES)  # user hooks
    for branch in demo.train.branches:
        cmd = _train_command(branch, demo, tmp_path / "data", tmp_path / "runs")[3:]
        assert cmd[:2] == [f"branch={branch}", f"experiment=demo_{budget}"]
        assert {o.split("=")[0] for o in cmd[2:]} == {"data.root", "seed", "threads", "datamodule.num_workers",
                                                      "hydra.run.dir", "summary_file", "trainer"}
        cfg = OmegaConf.to_container(_compose([o for o in cmd if not o.startswith("hydra.")]
                                              + [f"run_dir={tmp_path}"]), resolve=True)
        assert cfg["trainer"]["accelerator"] == "gpu" and cfg["data"]["root"] == str((tmp_path / "data").resolve())
        for key, value in BUDGETS[budget][branch].items():
            node, field = key.split(".")
            assert cfg[node][field] == value, (budget, branch, key)
    assert sorted(demo.train.branches) == sorted(BUDGETS[budget])
    # every budget's data has a weather variation beside clear weather (issue 40: proposals must hold on rain or fog)
    assert "clone" in demo.synth.variations and {"rain", "fog"} & set(demo.synth.variations)


def test_the_demo_gives_the_textural_run_the_upstream_checkpoints(tmp_path):
    """3D-SDN's order: the textural branch trains on the maps the semantic and geometric branches predict."""
    from sdn3d.cli.demo import _train_command

    demo = _compose(["budget=medium"], "demo")
    upstream = {"semantic": str(tmp_path / "s.ckpt"), "geometric": str(tmp_path / "g.ckpt")}
    cmd = _train_command("textural", demo, tmp_path / "data", tmp_path / "runs", upstream)
    assert f"datamodule.semantic_checkpoint={upstream['semantic']}" in cmd
    assert f"datamodule.geometric_checkpoint={upstream['geometric']}" in cmd
    assert f"datamodule.map_cache_dir={tmp_path / 'runs' / 'map_cache'}" in cmd
    assert not any(o.startswith("datamodule.semantic") for o in _train_command("geometric", demo, tmp_path / "data",
                                                                              tmp_path / "runs", upstream))


def test_renderer_group_maps_field_for_field_onto_the_settings():
    from sdn3d.render.settings import RasterSettings, SoftSilhouetteSettings

    cfg = _compose(["branch=geometric", "renderer.soft.sigma=0.5", "run_dir=x"])
    for node, cls in ((cfg.renderer.soft, SoftSilhouetteSettings), (cfg.renderer.hard, RasterSettings)):
        assert get_class(node._target_) is cls
        fields = {f.name for f in dataclasses.fields(cls)} - {"image_size"}  # image_size: per call
        assert set(node) - {"_target_"} == fields
        settings = instantiate(node, image_size=(48, 64))
        assert isinstance(settings, cls) and settings.image_size == (48, 64)
    defaults = _compose(["branch=geometric", "run_dir=x"]).renderer
    assert instantiate(defaults.soft, image_size=(8, 8)) == SoftSilhouetteSettings((8, 8))  # the code's defaults
    assert instantiate(defaults.hard, image_size=(8, 8)) == RasterSettings((8, 8))
    # sigma is set once: the geometric branch and sdn3d-edit's refinement follow it
    assert cfg.model.sigma == 0.5
    assert _compose(["renderer.soft.sigma=0.5"], "edit").refine.sigma == 0.5
    demo = _compose([], "render_demo")
    assert demo.fit.sigma == demo.renderer.soft.sigma == 1.0
    assert _compose(["renderer.soft.sigma=2.0"], "render_demo").fit.sigma == 2.0


def test_edit_refinement_is_the_papers_and_on_for_cityscapes_only():
    from sdn3d.editing.settings import refine_settings
    from sdn3d.errors import UserInputError
    from sdn3d.geometric.refine import RefineSettings

    assert refine_settings(_compose(["data=vkitti"], "edit")) is None  # off for Virtual KITTI, as in the paper
    assert refine_settings(_compose(["input.image=x.png"], "edit")) is None
    settings = refine_settings(_compose(["data=cityscapes"], "edit"))
    assert settings == RefineSettings()  # the paper's Cityscapes setting: Adam lr 0.03, 16 steps
    assert settings.params == ("rotation", "offset", "log_scale", "phi")
    assert refine_settings(_compose(["input.image=x.png", "input.camera=c.json"], "edit")) == settings
    assert refine_settings(_compose(["data=cityscapes", "refine.enabled=false"], "edit")) is None
    forced = refine_settings(_compose(["data=vkitti", "refine.enabled=true", "refine.iterations=3"], "edit"))
    assert forced.iterations == 3
    with pytest.raises(UserInputError, match="refine.enabled must be auto, true or false"):
        refine_settings(_compose(["refine.enabled=maybe"], "edit"))


def test_fault_policies_are_constructor_arguments(tmp_path):
    from datamodules import GeometricDataModule, SemanticDataModule, TexturalDataModule
    from lightning_modules.textural import TexturalModule
    from sdn3d.training.resume import resolve_resume

    for branch, cls in (("semantic", SemanticDataModule), ("geometric", GeometricDataModule),
                        ("textural", TexturalDataModule)):
        cfg = _compose([f"branch={branch}", "fault.corrupt_sample=skip", f"run_dir={tmp_path}"])
        dm = instantiate(cfg.datamodule)
        assert isinstance(dm, cls) and dm.corrupt_sample == "skip"
    cfg = _compose(["branch=textural", "experiment=demo", "fault.nonfinite=skip", f"run_dir={tmp_path}"])
    model = instantiate(cfg.model)
    assert isinstance(model, TexturalModule) and model.nonfinite == "skip"
    assert "nonfinite" not in model.hparams  # a run policy, not a hyperparameter of the checkpoint
    # resume: the saved (resolved) config's policies follow fault.* given on the command line again
    run = tmp_path / "run"
    (run / "checkpoints").mkdir(parents=True)
    (run / "checkpoints" / "last.ckpt").write_bytes(b"x")
    (run / "config.yaml").write_text(OmegaConf.to_yaml(cfg, resolve=True))
    resumed = resolve_resume(OmegaConf.create({"resume": str(run)}), ["fault.nonfinite=skip",
                                                                      "fault.corrupt_sample=skip"])
    assert resumed.model.nonfinite == "skip" and resumed.datamodule.corrupt_sample == "skip"
    resumed = resolve_resume(OmegaConf.create({"resume": str(run)}), [])
    assert resumed.model.nonfinite == "skip" and resumed.datamodule.corrupt_sample == "fail"  # as saved


ABLATIONS = sorted(p.stem for p in (CONF / "ablation").glob("*.yaml"))


@pytest.mark.parametrize("ablation", ABLATIONS)
@pytest.mark.parametrize("experiment", ["demo", "table2"])
def test_every_ablation_composes_and_names_its_module(ablation, experiment, tmp_path):
    """One sweep gives all of Table 2: each ablation picks the geometric branch's LightningModule
    (ablation.module), and the summary's `ablation` field reads its name."""
    cfg = _compose(["branch=geometric", f"ablation={ablation}", f"experiment={experiment}", f"run_dir={tmp_path}"])
    resolved = OmegaConf.to_container(cfg, resolve=True)
    assert resolved["ablation"]["name"] == ablation
    module = get_class(resolved["model"]["_target_"])
    assert resolved["model"]["_target_"] == resolved["ablation"]["module"]
    assert module.__name__ == ("Deep3DBoxModule" if ablation == "deep3dbox" else "GeometricModule")
    # the experiment's recipe still sets the budget, and the fault policies still reach the module
    recipe = OmegaConf.load(CONF / "recipe" / f"geometric_{experiment}.yaml")
    assert resolved["model"]["pred_epochs"] == recipe.model.pred_epochs
    assert resolved["model"]["nonfinite"] == resolved["fault"]["nonfinite"]
    if ablation == "deep3dbox":
        assert resolved["model"]["num_bins"] == 2 and resolved["model"]["single_cad"] is True
        assert resolved["model"]["reproj"] is False and resolved["model"]["rotation"] == "yaw_quaternion"
    else:
        assert "num_bins" not in resolved["model"]


def test_the_table2_sweep_holds_the_deep3dbox_row():
    assert {"full", "no_reproj", "full_quaternion", "no_tau", "single_cad", "deep3dbox"} <= set(ABLATIONS)



def test_demo_config_is_typed_by_its_schema_and_its_modes_parse_into_enums():
    """conf/demo.yaml names DemoSchema (sdn3d.cli._schemas): every budget composes, a wrong type is refused naming
    the key, and the example edits' and benchmark's modes are read once, into enums (sdn3d.cli.demo.edit_modes)."""
    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import bench_proposals, edit_modes
    from sdn3d.editing.appearance import Appearance
    from sdn3d.editing.compose import Compose
    from sdn3d.errors import UserInputError
    from sdn3d.proposals import Proposals

    for budget in ("short", "medium", "long"):
        cfg = compose_config([f"budget={budget}"], "demo")
        assert cfg.gpu_budget is (budget == "long") and cfg.budget_name == budget
    modes = edit_modes(compose_config([], "demo"))
    assert (modes.appearance, modes.compose.mode, modes.proposals) == (Appearance.PHOTO, Compose.EDITED,
                                                                       Proposals.SEMANTIC)
    generator = edit_modes(compose_config(["edits.appearance=generator", "edits.compose=full",
                                           "edits.proposals=gt"], "demo"))
    assert generator.appearance is Appearance.GENERATOR and generator.compose.mode is Compose.FULL
    assert bench_proposals(compose_config([], "demo"), {"semantic": "s.ckpt"}) == [Proposals.SEMANTIC, Proposals.GT]
    with pytest.raises(UserInputError, match="seed must be an integer, got 'abc'"):
        compose_config(["seed=abc"], "demo")
    with pytest.raises(UserInputError, match="edits.proposals must be one of"):
        edit_modes(compose_config(["edits.proposals=boxes"], "demo"))
    with pytest.raises(UserInputError, match="edits.appearance must be one of"):
        edit_modes(compose_config(["edits.appearance=paint"], "demo"))


@pytest.mark.parametrize("name", ["edit", "bench", "app"])
def test_the_photo_settings_of_a_config_are_the_librarys_defaults(name):
    """conf's ``photo:`` sections list every photo setting with the library's default (a user reads the YAML to learn
    what the library does; a setting added to PhotoSettings but not to the YAML cannot be given on the command line)."""
    from sdn3d.editing.photo.settings import PhotoSettings

    photo = OmegaConf.to_container(_compose([], name).photo)
    assert PhotoSettings.from_mapping(photo) == PhotoSettings()
    if name != "bench":  # the benchmark's own fill aside, every field is listed
        assert set(photo) >= {f.name for f in dataclasses.fields(PhotoSettings)} - {"mask_erode_px", "inpaint_radius",
                                                                                   "max_level"}


def _named_schemas(name: str) -> set[str]:
    """The ``*_schema`` entries of ``conf/<name>.yaml``'s defaults list and of the configs it composes."""
    from sdn3d.io import yaml_loader

    defaults = yaml.load((CONF / f"{name}.yaml").read_text(), Loader=yaml_loader()).get("defaults") or []
    found: set[str] = set()
    for entry in defaults:
        if isinstance(entry, str) and entry.endswith("_schema"):
            found.add(entry)
        elif isinstance(entry, str) and (CONF / f"{entry}.yaml").is_file():
            found |= _named_schemas(entry)
    return found


@pytest.mark.parametrize("name", sorted(p.stem for p in CONF.glob("*.yaml")))
def test_each_config_registers_exactly_the_schemas_its_defaults_name(name):
    from sdn3d.cli._schemas import CONFIG_SCHEMAS, SCHEMAS

    assert set(CONFIG_SCHEMAS.get(name, ())) == _named_schemas(name)
    assert set(CONFIG_SCHEMAS.get(name, ())) <= set(SCHEMAS)


@pytest.mark.parametrize(("name", "schemas"), [("edit", {"edit_schema"}), ("app", {"edit_schema", "app_schema"}),
                                              ("bench", {"bench_schema"}), ("demo", {"demo_schema"})])
def test_composing_a_config_stores_only_its_own_schemas(name, schemas):
    """compose_config stores the schemas its config names and no other (each costs milliseconds at every call:
    an edit stored all four, 0.03 CPU s; session 22 fitcost2)."""
    from hydra.core.config_store import ConfigStore

    from sdn3d.cli._config import compose_config
    from sdn3d.cli._schemas import SCHEMAS

    repo = ConfigStore.instance().repo
    kept = {f"{s}.yaml": repo.pop(f"{s}.yaml") for s in SCHEMAS if f"{s}.yaml" in repo}
    try:
        compose_config([], name)
        stored = {s for s in SCHEMAS if f"{s}.yaml" in repo}
    finally:
        repo.update(kept)
    assert stored == schemas


@pytest.mark.parametrize("name", ["edit", "app"])
def test_the_box_fit_a_config_lists_is_the_librarys_default_fit(name):
    """conf/edit.yaml's ``box_objects.fit`` (app.yaml composes it) gives FitSettings' defaults field for field, so
    the edit, the app and the benchmark (``FitSettings()``) fit alike."""
    from sdn3d.geometric.fit import FitSettings

    listed = OmegaConf.to_container(_compose([], name).box_objects.fit)
    default = FitSettings()
    assert {k: getattr(default, k) for k in listed} == {k: tuple(v) if isinstance(v, list) else v
                                                       for k, v in listed.items()}
