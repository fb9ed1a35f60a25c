"""Wrong and corrupt checkpoints (issue 20, item 6): every one is a :class:`UserInputError` naming the file
(and, for another branch's checkpoint, the branch it holds); ``sdn3d-edit`` prints it in one line, exits 2."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from faults.checkpoints import (
    RANDOM_SEEDS,
    WRONG_BRANCH_PAIRS,
    code_running_pickle,
    foreign_zip,
    hydra_config_with_target,
    random_bytes,
    truncated_copy,
)
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d import io as sdn3d_io
from sdn3d.cli.edit import main
from sdn3d.errors import UserInputError
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.io import load_lightning_checkpoint
from sdn3d.models import Models, geometric_crop_settings
from sdn3d.semantic.predict import SemanticPredictor
from sdn3d.textural.renderer import TexturalRenderer

LOADERS = {"semantic": SemanticPredictor.from_checkpoint, "geometric": GeometricPredictor.from_checkpoint,
           "textural": TexturalRenderer.from_checkpoint, "any": load_lightning_checkpoint}
pytestmark = pytest.mark.filterwarnings("ignore:Detected pickle protocol:UserWarning")


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _bad_file(loader, path) -> UserInputError:
    with pytest.raises(UserInputError) as info:
        loader(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message, message
    return info.value


@pytest.mark.parametrize("seed", RANDOM_SEEDS)
def test_random_bytes_are_a_clear_error_keeping_the_cause(tmp_path, seed):
    path = random_bytes(tmp_path / f"noise{seed}.ckpt", seed)
    for loader in LOADERS.values():
        error = _bad_file(loader, path)
        assert "could not read checkpoint" in str(error) and error.__cause__ is not None


@pytest.mark.parametrize("branch", ["semantic", "geometric", "textural"])
def test_truncated_real_checkpoints(tmp_path, ckpts, branch):
    for keep in (0.01, 0.3, 0.9, 0.999):
        path = truncated_copy(ckpts[branch], tmp_path / f"{branch}_{keep}.ckpt", keep)
        error = _bad_file(LOADERS[branch], path)
        assert error.__cause__ is not None


def test_a_zip_that_is_not_a_torch_file(tmp_path):
    path = foreign_zip(tmp_path / "archive.ckpt")
    for loader in LOADERS.values():
        assert "not a loadable PyTorch file" in str(_bad_file(loader, path))


@pytest.mark.parametrize("zipped", [False, True], ids=["pickle", "torch-zip"])
def test_a_pickle_that_would_run_code_is_refused_without_running(tmp_path, zipped):
    marker = tmp_path / "code_ran"
    path = code_running_pickle(tmp_path / "evil.ckpt", marker, zipped=zipped)
    for loader in LOADERS.values():
        error = _bad_file(loader, path)
        assert "weights-only loading refused it" in str(error) and "weights_only=False" not in str(error)
        assert not marker.exists()


def test_checkpoint_branch_tells_the_branches_apart(ckpts):
    checkpoint_branch = sdn3d_io.checkpoint_branch
    for branch, path in ckpts.items():
        ckpt = load_lightning_checkpoint(path)
        assert checkpoint_branch(ckpt) == branch
        assert checkpoint_branch({"state_dict": {}, "hyper_parameters": ckpt["hyper_parameters"]}) == branch
    assert checkpoint_branch({"state_dict": {"w": torch.zeros(1)}}) is None


@pytest.mark.parametrize("held, expected", WRONG_BRANCH_PAIRS)
def test_each_branch_as_every_other_names_the_branch_it_holds(ckpts, held, expected):
    path = ckpts[held]
    error = _bad_file(LOADERS[expected], path)
    assert f"holds the {held} branch" in str(error) and f"not the {expected} branch" in str(error)
    with pytest.raises(UserInputError, match=f"holds the {held} branch"):
        Models.from_checkpoints(**{expected: path}, crop_size=32, margin=0.1)


def test_malformed_checkpoint_contents(tmp_path, ckpts):
    cases = {"list_state.ckpt": {"state_dict": [1, 2]}, "no_weights.ckpt": {"state_dict": {"w": torch.zeros(1)}},
             "hparams_list.ckpt": {"state_dict": {}, "hyper_parameters": [1]}}
    for name, content in cases.items():
        torch.save(content, tmp_path / name)
        for branch in ("semantic", "geometric", "textural"):
            _bad_file(LOADERS[branch], tmp_path / name)
    textural = load_lightning_checkpoint(ckpts["textural"])
    torch.save({"state_dict": textural["state_dict"], "hyper_parameters": {"ngf": 4}}, tmp_path / "no_classes.ckpt")
    assert "'classes'" in str(_bad_file(TexturalRenderer.from_checkpoint, tmp_path / "no_classes.ckpt"))
    with pytest.raises(UserInputError, match="does not exist"):
        sdn3d_io.load_torch_file(tmp_path / "missing.pt", "code_bank")


def test_run_config_is_read_not_instantiated(tmp_path, ckpts):
    run = tmp_path / "run"
    paths = write_checkpoints(run / "checkpoints")
    marker = tmp_path / "instantiated"
    hydra_config_with_target(run / "config.yaml", marker, crop_size=48, margin=0.2)
    assert geometric_crop_settings(paths["geometric"]) == (48, 0.2)
    assert Models.from_checkpoints(geometric=paths["geometric"]).crop_size == 48
    assert not marker.exists()
    for text in ("datamodule: {crop_size: 48, margin: 0.2", "datamodule:\n  crop_size: 48\n  margin: wide\n",
                 "datamodule:\n  crop_size: true\n"):
        (run / "config.yaml").write_text(text)
        with pytest.raises(UserInputError, match="config.yaml"):
            geometric_crop_settings(paths["geometric"])
        # Given explicitly, the crop settings need no config: the broken file is not read.
        assert Models.from_checkpoints(geometric=paths["geometric"], crop_size=40, margin=0.1).crop_size == 40
    (run / "config.yaml").write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(UserInputError, match="config.yaml"):
        geometric_crop_settings(paths["geometric"])


# -- through sdn3d-edit -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def image_args(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("edit_input")
    rgb = np.random.default_rng(0).integers(0, 256, (64, 160, 3), dtype=np.uint8)
    Image.fromarray(rgb).save(tmp / "street.png")
    (tmp / "ops.yaml").write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    return [f"input.image={tmp / 'street.png'}", "image_size=[160,64]", f"edits={tmp / 'ops.yaml'}",
            "geometric.crop_size=32",
            "input.intrinsics={fx:93,fy:124,cx:79.5,cy:31.5}"]  # 160x64 is not Virtual KITTI's shape: camera given


def _edit_fails(args, capsys, *needles):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-edit: error:") and err.count("\n") == 1, err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


@pytest.mark.parametrize("held, expected", WRONG_BRANCH_PAIRS)
def test_edit_cli_wrong_branch_exits_2_naming_file_and_branch(ckpts, image_args, tmp_path, capsys, held, expected):
    given = dict(ckpts) | {expected: ckpts[held]}
    args = image_args + [f"checkpoints.{k}={v}" for k, v in given.items()] + [f"output_dir={tmp_path / 'out'}"]
    _edit_fails(args, capsys, str(ckpts[held]), f"holds the {held} branch", f"not the {expected} branch")
    assert not (tmp_path / "out").exists()


def test_edit_cli_corrupt_files_exit_2(ckpts, image_args, tmp_path, capsys):
    marker = tmp_path / "code_ran"
    bad = [random_bytes(tmp_path / f"noise{s}.ckpt", s) for s in RANDOM_SEEDS[:4]]
    bad += [truncated_copy(ckpts["geometric"], tmp_path / "cut.ckpt"), foreign_zip(tmp_path / "z.ckpt"),
            code_running_pickle(tmp_path / "evil.ckpt", marker, zipped=True)]
    for path in bad:
        for branch in ("geometric", "textural"):
            given = dict(ckpts) | {branch: path}
            args = image_args + [f"checkpoints.{k}={v}" for k, v in given.items()] + [f"output_dir={tmp_path / 'o'}"]
            _edit_fails(args, capsys, str(path))
    assert not marker.exists() and not (tmp_path / "o").exists()
    # The code bank (JSON) is a user-named file too: random bytes, a checkpoint or a torch file are not one.
    args = image_args + [f"checkpoints.{k}={v}" for k, v in ckpts.items()] + [f"output_dir={tmp_path / 'o'}"]
    for path in (bad[1], bad[-1]):
        _edit_fails(args + [f"code_bank={path}"], capsys, "code_bank", str(path))
    torch.save({"12": torch.zeros(5)}, tmp_path / "flat_bank.pt")
    _edit_fails(args + [f"code_bank={tmp_path / 'flat_bank.pt'}"], capsys, "code_bank")
    assert not marker.exists()


def test_bench_cli_wrong_or_corrupt_checkpoint_exits_2(tiny_synth, ckpts, tmp_path, capsys):
    from sdn3d.cli.bench import main as bench_main

    noise = random_bytes(tmp_path / "noise.ckpt", RANDOM_SEEDS[2])
    for given, needles in [({"geometric": ckpts["semantic"]}, ("holds the semantic branch", "not the geometric")),
                           ({"textural": ckpts["geometric"]}, ("holds the geometric branch", "not the textural")),
                           ({"geometric": noise}, ("could not read checkpoint",))]:
        paths = {"geometric": ckpts["geometric"], "textural": ckpts["textural"]} | given
        args = [f"data.root={tiny_synth}", "data.image_size=[160,64]", "geometric.crop_size=32", "proposals=gt",
                *(f"checkpoints.{k}={v}" for k, v in paths.items()), f"output_dir={tmp_path / 'bench'}"]
        assert bench_main(args) == 2
        err = capsys.readouterr().err
        assert err.startswith("sdn3d-bench: error:") and err.count("\n") == 1, err
        assert str(next(iter(given.values()))) in err and all(n in err for n in needles), err
    assert not (tmp_path / "bench").exists()


@pytest.mark.parametrize("seed", RANDOM_SEEDS)
def test_random_bytes_as_pretrained_weights_are_a_clear_error(tmp_path, seed):
    """Pretrained weights files (ResNet / VGG / DRN / LPIPS) fail as clearly as checkpoints do."""
    from sdn3d.nets.weights import PretrainedWeightsError, read_state_dict

    with pytest.raises(PretrainedWeightsError, match="could not read pretrained weights"):
        read_state_dict(random_bytes(tmp_path / "weights.pth", seed))
