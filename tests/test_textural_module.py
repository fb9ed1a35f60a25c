"""TexturalModule: manual GAN optimisation, step counting, resume, metrics, checkpoint -> renderer, config."""

from __future__ import annotations

from pathlib import Path

import lightning as L
import pytest
import torch
from helpers.tiny_models import write_checkpoints
from hydra.utils import instantiate
from omegaconf import OmegaConf

from datamodules import TexturalDataModule
from lightning_modules._base import NonFiniteLossError
from lightning_modules.textural import LinearDecay, TexturalModule
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.nets.vgg import VGG19Features
from sdn3d.textural.code_bank import code_bank_path, load_code_bank
from sdn3d.textural.renderer import TexturalRenderer

CONF = Path(__file__).resolve().parents[1] / "conf"
SMALL = dict(ngf=8, n_downsampling=2, n_blocks=1, nef=4, n_downsampling_encoder=2, ndf=8)


@pytest.fixture(scope="module")
def data_root(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("vk1")
    write_vkitti1_fixture(root, frames=range(7), size=(128, 48))  # 4 train, 1 validation, 2 test frames
    return root


def _datamodule(root: Path, batch_size: int = 2) -> TexturalDataModule:
    cfg = OmegaConf.load(CONF / "data" / "vkitti.yaml")
    cfg.root = str(root)
    cfg.split = {"rule": "paper", "fraction": 0.8, "val_fraction": 0.2, "val_gap": 0}  # a fixture, not VKITTI's worlds
    return TexturalDataModule(cfg, image_size=(64, 32), batch_size=batch_size)


def _trainer(**kwargs) -> L.Trainer:
    base = dict(accelerator="cpu", logger=False, enable_checkpointing=False, enable_progress_bar=False,
                enable_model_summary=False, num_sanity_val_steps=0)
    return L.Trainer(**{**base, **kwargs})


def test_linear_decay_schedule():
    f = LinearDecay(2, 4)
    assert [f(e) for e in range(7)] == [1.0, 1.0, 1.0, 0.75, 0.5, 0.25, 0.0]
    assert LinearDecay(3, 0)(10) == 1.0
    with pytest.raises(ValueError, match="lr_constant_epochs"):
        LinearDecay(-1, 2)


def test_fit_counts_steps_decays_lr_logs_metrics_and_resumes(data_root, tmp_path):
    torch.manual_seed(0)
    model = TexturalModule(**SMALL, lr=2e-4, lr_constant_epochs=0, lr_decay_epochs=4)
    grids = []
    model.log_image_grid = lambda tag, rows, step=None: grids.append((tag, rows, step)) or False
    dm = _datamodule(data_root)
    before = {k: v.clone() for k, v in model.state_dict().items()}
    trainer = _trainer(max_epochs=2)
    trainer.fit(model, datamodule=dm)
    # 2 batches per epoch: 4 G updates; Lightning's global_step counts both optimizers' steps
    assert int(model.g_updates) == 4 and trainer.global_step == 8
    trained = [k for k in before if k.startswith(("generator.model.1.", "encoder.model.1.", "discriminator.scales.0."))]
    assert len(trained) > 6 and all(not torch.equal(before[k], model.state_dict()[k]) for k in trained)
    opt_g, opt_d = model.optimizers()
    assert opt_g.param_groups[0]["lr"] == pytest.approx(1e-4) == opt_d.param_groups[0]["lr"]  # factor 1 - 2/4
    metrics = trainer.callback_metrics
    for key in ("val/l1", "val/psnr", "val/ssim", "val/obj_l1", "val/obj_psnr", "val/obj_ssim",
                "train/loss_g", "train/loss_d", "train/g_fm", "train/g_l1"):
        assert key in metrics and torch.isfinite(metrics[key]), key
    assert "train/g_perceptual" not in metrics and "val/lpips" not in metrics  # perceptual=none: off
    assert "train/g_swap" not in metrics  # lambda_swap=0 (the paper's losses)
    assert 0 < float(metrics["val/ssim"]) < 1 and float(metrics["val/psnr"]) > 0
    tag, rows, step = grids[-1]
    assert tag == "val/label_reconstruction_real" and step == 4 and len(rows) == 3
    assert all(r.shape == (1, 3, 32, 64) for r in rows) and rows[0].max() <= 1

    ckpt = tmp_path / "textural.ckpt"
    trainer.save_checkpoint(ckpt)
    renderer = TexturalRenderer.from_checkpoint(ckpt)
    batch = next(iter(dm.val_dataloader()))
    model.eval()
    with torch.no_grad():
        expected = model(batch)
    got = renderer.reconstruct(batch["image"], batch["label"], batch["instance_label_map"], batch["boundary"],
                               batch["pose"], batch["normal"])
    assert torch.allclose(got, expected, atol=1e-5)

    # resume: counters, optimizer and scheduler state continue
    resumed = TexturalModule(**SMALL, lr=2e-4, lr_constant_epochs=0, lr_decay_epochs=4)
    trainer = _trainer(max_epochs=3, limit_val_batches=0)
    trainer.fit(resumed, datamodule=_datamodule(data_root), ckpt_path=ckpt)
    assert int(resumed.g_updates) == 6 and trainer.global_step == 12
    assert resumed.optimizers()[0].param_groups[0]["lr"] == pytest.approx(0.5e-4)


def test_max_steps_counts_both_optimizers(data_root):
    model = TexturalModule(**SMALL)
    trainer = _trainer(max_steps=2, limit_val_batches=0)
    trainer.fit(model, datamodule=_datamodule(data_root))
    assert int(model.g_updates) == 1


@pytest.mark.parametrize("policy", ["stop", "skip"])
def test_nonfinite_loss_policy(data_root, policy):
    model = TexturalModule(**SMALL)
    model.nonfinite = policy
    generate = model._generate
    model._generate = lambda batch: (generate(batch)[0] * float("nan"), *generate(batch)[1:])
    before = {k: v.clone() for k, v in model.generator.state_dict().items()}
    trainer = _trainer(max_epochs=1, limit_val_batches=0)
    if policy == "stop":
        with pytest.raises(NonFiniteLossError, match="loss_g"):
            trainer.fit(model, datamodule=_datamodule(data_root))
        return
    trainer.fit(model, datamodule=_datamodule(data_root))
    assert model.skipped_batches == 2 and int(model.g_updates) == 0 and trainer.global_step == 0
    assert all(torch.equal(before[k], v) for k, v in model.generator.state_dict().items())


@pytest.mark.parametrize("net", ["vgg", "drn"])
def test_perceptual_loss_and_decoupling_switches(data_root, tmp_path, net):
    torch.save(VGG19Features().state_dict(), tmp_path / "vgg19.pth")
    weights = tmp_path / "vgg19.pth" if net == "vgg" else write_checkpoints(tmp_path)["semantic"]
    model = TexturalModule(**SMALL, use_pose=False, use_normal=False, perceptual=net, perceptual_weights=str(weights))
    assert model.generator.model[1].in_channels == 14 + 1 + 5
    assert not any(k.startswith("_frozen") or "vgg" in k or "backbone" in k for k in model.state_dict())  # F stays out
    trainer = _trainer(fast_dev_run=True)
    trainer.fit(model, datamodule=_datamodule(data_root))
    assert torch.isfinite(trainer.callback_metrics["train/g_perceptual"])
    no_codes = TexturalModule(**SMALL, use_codes=False, classes="cityscapes")
    assert no_codes.generator.model[1].in_channels == 19 + 1 + 24 + 3


def test_generator_without_pose_and_normal_maps_trains_and_renders_without_them(data_root, tmp_path):
    """model.use_pose=false model.use_normal=false (the 2D baselines' generator, sdn3d-bench
    checkpoints.textural_2d): G has no such channels in training, the checkpoint says so, and the renderer built
    from it draws the same picture whatever pose and normal maps it is given."""
    torch.manual_seed(0)
    model = TexturalModule(**SMALL, use_pose=False, use_normal=False)
    trainer = _trainer(max_steps=2, limit_val_batches=0)
    dm = _datamodule(data_root)
    trainer.fit(model, datamodule=dm)
    assert int(model.g_updates) == 1 and model.generator.model[1].in_channels == 14 + 1 + 5
    ckpt = tmp_path / "textural_2d.ckpt"
    trainer.save_checkpoint(ckpt)
    saved = torch.load(ckpt, weights_only=True)["hyper_parameters"]
    assert saved["use_pose"] is False and saved["use_normal"] is False and saved["use_codes"] is True
    renderer = TexturalRenderer.from_checkpoint(ckpt)
    assert not renderer.spec.use_pose and not renderer.spec.use_normal
    assert renderer.generator.model[1].in_channels == 14 + 1 + 5
    batch = next(iter(dm.train_dataloader()))
    assert batch["pose"].abs().sum() > 0 and batch["normal"].abs().sum() > 0  # the data has the maps ...
    model.eval()
    with torch.no_grad():
        trained = model(batch)
    args = (batch["image"], batch["label"], batch["instance_label_map"], batch["boundary"])
    drawn = renderer.reconstruct(*args, batch["pose"], batch["normal"])
    torch.testing.assert_close(drawn, trained, atol=1e-5, rtol=0)
    # ... and neither G reads them
    torch.testing.assert_close(renderer.reconstruct(*args, torch.rand_like(batch["pose"]), None), drawn)


def test_swap_term_makes_the_code_decide_the_colour_it_is_scored_on(data_root):
    """The swap term compares G's drawing with swapped codes against the donors' real colours, and its gradient
    reaches both G and E."""
    torch.manual_seed(0)
    model = TexturalModule(**SMALL, lambda_swap=10.0, swap_min_pixels=1)
    batch = next(iter(_datamodule(data_root).train_dataloader()))
    fake, real, cond, codes = model._generate(batch)
    torch.manual_seed(1)
    term = model.swap_term(batch, real, cond, codes)
    assert term.dim() == 0 and float(term.detach()) > 0
    term.backward()
    assert model.encoder.model[1].weight.grad.abs().sum() > 0 and model.generator.model[1].weight.grad.abs().sum() > 0
    # the same number by hand: swap the codes with the same donors, draw, compare mean colours per object
    from sdn3d.nets.pix2pixhd import instance_mean, region_index
    from sdn3d.textural.codes import code_donors

    L_map = batch["instance_label_map"]
    index, _, ids = region_index(L_map)
    torch.manual_seed(1)
    donors = code_donors(ids)
    with torch.no_grad():
        drawn = model.generator(model.spec.generator_input(cond, codes[donors][index].permute(0, 3, 1, 2),
                                                           batch["pose"], batch["normal"]))
    _, drawn_colors, _, _ = instance_mean(drawn, L_map)
    _, real_colors, _, _ = instance_mean(real, L_map)
    swapped = [i for i in range(ids.numel()) if int(donors[i]) != i]
    assert swapped and all(int(ids[i]) >= 1000 for i in swapped)
    expected = torch.stack([(drawn_colors[i] - real_colors[int(donors[i])]).abs() for i in swapped]).mean()
    torch.testing.assert_close(term.detach(), expected)


def test_fit_writes_a_code_bank_next_to_each_kept_checkpoint(data_root, tmp_path, monkeypatch):
    import lightning_modules.textural as textural_module

    torch.manual_seed(0)
    model = TexturalModule(**SMALL, lambda_swap=10.0)
    checkpoint = L.pytorch.callbacks.ModelCheckpoint(dirpath=tmp_path / "checkpoints", monitor="val/psnr",
                                                     mode="max", save_last=True, filename="best")
    trainer = _trainer(max_epochs=1, enable_checkpointing=True, callbacks=[checkpoint])
    dm = _datamodule(data_root)
    encoded = []
    build = textural_module.build_code_bank
    monkeypatch.setattr(textural_module, "build_code_bank", lambda *a: encoded.append(1) or build(*a))
    trainer.fit(model, datamodule=dm)
    assert "train/g_swap" in trainer.callback_metrics
    assert len(encoded) == 1  # one epoch: the best checkpoint is the last, its bank encoded once for both files
    for name in ("best.ckpt", "last.ckpt"):
        bank = load_code_bank(code_bank_path(tmp_path / "checkpoints" / name))
        renderer = TexturalRenderer.from_checkpoint(tmp_path / "checkpoints" / name)
        frames = list(dm.code_bank_loader())
        image = torch.cat([b["image"] for b in frames])
        L_map = torch.cat([b["instance_label_map"] for b in frames])
        codes = renderer.encode(image, L_map)
        cars = codes.ids >= 1000
        assert len(bank) == len(codes) and sorted(bank.classes) == sorted(set(codes.classes.tolist()))
        car_class = int(codes.classes[cars][0])
        torch.testing.assert_close(bank.codes[car_class], codes.codes[codes.classes == car_class], atol=1e-5, rtol=0)
        assert bank.colors[car_class].shape == (int((codes.classes == car_class).sum()), 3)


def test_branch_config_and_recipes(data_root):
    branch = OmegaConf.load(CONF / "branch" / "textural.yaml")
    data = OmegaConf.load(CONF / "data" / "vkitti.yaml")
    data.root = str(data_root)
    data.split = {"rule": "paper", "fraction": 0.8, "val_fraction": 0.2, "val_gap": 0}
    cfg = OmegaConf.merge({"data": data, "seed": 0}, branch)
    assert cfg.branch_name == "textural" and cfg.monitor == "val/psnr" and cfg.monitor_mode == "max"
    paper = OmegaConf.merge(cfg, OmegaConf.load(CONF / "recipe" / "textural_paper.yaml"))  # experiment=paper_*
    assert (paper.model.ngf, paper.model.n_downsampling, paper.model.n_blocks) == (64, 4, 9)
    assert (paper.model.lambda_fm, paper.model.lambda_recon, paper.model.code_dim) == (5.0, 10.0, 5)
    assert paper.model.lambda_swap == 0 and cfg.model.lambda_swap > 0  # the swap term: on, except the paper's recipe
    assert cfg.model.perceptual == "none" and cfg.model.write_code_bank
    demo = OmegaConf.merge(cfg, OmegaConf.load(CONF / "recipe" / "textural_demo.yaml"))  # experiment=demo
    model = instantiate(demo.model)
    assert isinstance(model, TexturalModule) and model.hparams.ngf == 16 and model.hparams.classes == "vkitti"
    dm = instantiate(demo.datamodule)
    assert dm.image_size == (312, 96) and dm.batch_size == 2
    assert demo.trainer.max_epochs * demo.trainer.limit_train_batches <= 400  # a few CPU minutes


def test_only_lightnings_manual_optimisation_checkpoint_warning_is_silenced():
    import warnings

    from lightning_modules.textural import silence_step_checkpoint_warning

    with warnings.catch_warnings(record=True) as caught:
        silence_step_checkpoint_warning()  # what TexturalModule.on_fit_start does
        warnings.filterwarnings("always", message="an unrelated warning")
        warnings.warn("Using ModelCheckpoint with manual optimization and every_n_train_steps, but no "
                      "pre-optimization state was saved.", UserWarning, stacklevel=1)
        warnings.warn("an unrelated warning", UserWarning, stacklevel=1)
    assert [str(w.message) for w in caught] == ["an unrelated warning"]


def test_same_weights_tells_equal_state_dicts_from_different_ones():
    from lightning_modules.textural import _same_weights

    a = {"w": torch.tensor([1.0, 2.0]), "b": torch.tensor([0.5])}
    assert _same_weights(a, {k: v.clone() for k, v in a.items()})
    assert not _same_weights(a, {"w": torch.tensor([1.0, 2.0 + 1e-6]), "b": torch.tensor([0.5])})
    assert not _same_weights(a, {"w": a["w"]})
    assert not _same_weights(a, {"w": a["w"].double(), "b": a["b"]})
