"""SemanticModule on a tiny Virtual KITTI fixture: training, metrics, TensorBoard grids, checkpoint -> predictor."""

from __future__ import annotations

import math
from pathlib import Path

import lightning as L
import pytest
import torch
from hydra import compose, initialize_config_dir
from hydra.utils import instantiate
from lightning.pytorch.loggers import TensorBoardLogger
from omegaconf import OmegaConf

from datamodules import SemanticDataModule
from lightning_modules.semantic import SemanticModule
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.semantic import SemanticPredictor, segment

CONF = Path(__file__).resolve().parents[1] / "conf"
SIZE = (96, 32)


@pytest.fixture(scope="module")
def data_cfg(tmp_path_factory: pytest.TempPathFactory):
    root = tmp_path_factory.mktemp("vkitti")
    write_vkitti1_fixture(root, frames=range(7), size=(310, 94))
    cfg = OmegaConf.load(CONF / "data" / "vkitti.yaml")
    cfg.root = str(root)
    cfg.image_size = list(SIZE)
    # A fixture-sized split (the released ranges need Virtual KITTI's frame numbers): 0-3 train, 4 val, 5-6 test.
    cfg.split = {"rule": "paper", "val_fraction": 0.25, "val_gap": 0}
    return cfg


def _small_module(**kw) -> SemanticModule:
    # a narrow DRN (tests/helpers/tiny_models.py's widths; the published ones took ~5x the time and 130 MB checkpoints)
    args = dict(classes="vkitti", head_channels=32, crop_size=[64, 32], log_images=2, min_area=1,
                channels=[4, 4, 8, 8, 16, 16, 16, 16])
    args.update(kw)
    return SemanticModule(**args)


def test_fit_validate_test_logs_metrics_grids_and_poly_schedule(data_cfg, tmp_path):
    dm = SemanticDataModule(data_cfg, batch_size=2)
    model = _small_module()
    logger = TensorBoardLogger(tmp_path, name="tb")
    trainer = L.Trainer(accelerator="cpu", max_steps=2, limit_val_batches=1, limit_test_batches=1, logger=logger,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False,
                        num_sanity_val_steps=0, val_check_interval=2)
    trainer.fit(model, datamodule=dm)
    metrics = trainer.callback_metrics
    for key in ("train/loss", "train/ce", "train/center", "train/offset", "val/loss", "val/miou", "val/pixel_acc",
                "val/iou_Road", "val/pq", "val/sq", "val/rq"):
        assert key in metrics and torch.isfinite(metrics[key]), key
    assert 0.0 <= float(metrics["val/miou"]) <= 1.0
    # Poly schedule per step: lr * (1 - step / total) ** 0.9 reaches 0 after the last of 2 steps.
    assert trainer.optimizers[0].param_groups[0]["lr"] == pytest.approx(0.0)
    sched = trainer.lr_scheduler_configs[0].scheduler
    assert sched.lr_lambdas[0](1) == pytest.approx(0.5**0.9)
    results = trainer.test(model, datamodule=dm, verbose=False)[0]
    assert {"test/miou", "test/pq"} <= set(results)
    assert all(k.startswith("test/") for k in results)

    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    events = EventAccumulator(str(Path(logger.log_dir)), size_guidance={"images": 0})
    events.Reload()
    tags = set(events.Tags()["images"])
    assert {"val/segmentation", "val/instances", "test/segmentation"} <= tags
    img = events.Images("val/segmentation")[0]
    assert img.width > 3 * SIZE[0] and SIZE[1] < img.height < 2 * SIZE[1]  # 3 columns, 1 val frame


def test_checkpoint_loads_weights_only_into_the_predictor(data_cfg, tmp_path):
    dm = SemanticDataModule(data_cfg, batch_size=2)
    model = _small_module(crop_size=OmegaConf.create([64, 32]))  # a ListConfig, as Hydra passes it
    trainer = L.Trainer(accelerator="cpu", max_steps=1, limit_val_batches=0, logger=False,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False)
    trainer.fit(model, datamodule=dm)
    path = tmp_path / "semantic.ckpt"
    trainer.save_checkpoint(path)
    ckpt = torch.load(path, map_location="cpu", weights_only=True)
    assert ckpt["hyper_parameters"]["crop_size"] == [64, 32] and ckpt["hyper_parameters"]["classes"] == "vkitti"

    predictor = SemanticPredictor.from_checkpoint(path)
    assert predictor.thing_classes == [12, 13] and predictor.grouping["min_area"] == 1
    batch = next(iter(dm.val_dataloader()))
    model.eval()
    with torch.no_grad():
        label, instance = model.predict_maps(model(batch["image"]))
    result = predictor(batch["image"])
    assert result.label.shape == (batch["image"].shape[0], SIZE[1], SIZE[0]) and result.label.dtype == torch.int64
    torch.testing.assert_close(result.instance, instance)
    inst_px = instance > 0
    torch.testing.assert_close(result.label[~inst_px], label[~inst_px])
    assert (result.label[inst_px] == instance[inst_px] // 1000).all()  # instance pixels carry their class
    torch.testing.assert_close(result.probability.sum(1), torch.ones_like(result.probability[:, 0]))
    # segment(): single image, path; a predictor with a working size resizes and maps back.
    lab1, inst1 = segment(batch["image"][0], path)
    torch.testing.assert_close(lab1, result.label[:1])
    big = torch.nn.functional.interpolate(batch["image"][:1], scale_factor=2, mode="bilinear")
    resized = SemanticPredictor.from_checkpoint(path, image_size=SIZE)(big)
    assert resized.label.shape == (1, 2 * SIZE[1], 2 * SIZE[0]) and resized.instance.shape == resized.label.shape


def _train_cfg(*overrides: str):
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        return compose("train", overrides=list(overrides))


def test_hydra_branch_config_and_experiments(data_cfg):
    base = ["branch=semantic", "data=synth", f"data.root={data_cfg.root}"]
    cfg = _train_cfg(*base, "data.image_size=[96,32]")
    assert cfg.branch_name == "semantic" and cfg.monitor == "val/miou" and cfg.monitor_mode == "max"
    assert OmegaConf.load(CONF / "branch" / "semantic.yaml").trainer.max_epochs == 25  # the paper's 25 epochs
    paper = _train_cfg(*base, "data.image_size=[96,32]", "experiment=paper_vkitti")  # data=synth wins
    assert (paper.model.lr, paper.model.momentum, paper.model.weight_decay, paper.model.poly_power) == \
           (0.01, 0.9, 1e-4, 0.9)
    assert paper.datamodule.batch_size == 8 and paper.trainer.max_epochs == 25
    demo = _train_cfg(*base, "data.image_size=[96,32]", "experiment=demo")
    assert demo.trainer.max_epochs * demo.trainer.limit_train_batches <= 60
    assert list(demo.data.image_size) == [96, 32] and demo.trainer.limit_train_batches == 12  # CLI beats experiment
    assert list(_train_cfg(*base, "experiment=demo").data.image_size) == [312, 96]
    model = instantiate(paper.model, head_channels=32)
    dm = instantiate(paper.datamodule)
    assert isinstance(model, SemanticModule) and model.hparams.classes == "vkitti" and model.num_classes == 14
    assert model.hparams.crop_size == 224 and dm.batch_size == 8 and dm.image_size == SIZE


def test_rejects_bad_hyperparameters():
    with pytest.raises(ValueError, match="lr"):
        SemanticModule(lr=0.0, head_channels=32)
    with pytest.raises(ValueError, match="classes"):
        SemanticModule(classes="ade20k")
    assert math.isclose(SemanticModule(instance_head=False).hparams.poly_power, 0.9)


def test_class_weights_from_label_histograms():
    from sdn3d.semantic import class_weights, label_histogram

    labels = [torch.tensor([[0, 0, 0, 1], [0, 0, 2, 255]]), torch.tensor([[0, 0, 0, 0]])]
    counts = label_histogram(labels, 4)
    assert counts.tolist() == [9, 1, 1, 0]  # 255 ignored, class 3 absent
    w = class_weights(counts, "median_frequency", max_weight=100.0)
    # frequencies 9/11, 1/11, 1/11; median 1/11 -> weights 1/9, 1, 1; absent class 0
    torch.testing.assert_close(w, torch.tensor([1 / 9, 1.0, 1.0, 0.0]))
    clipped = class_weights(torch.tensor([1000, 10, 1, 0]), "median_frequency", max_weight=5.0)
    assert clipped[2] == 5.0 and clipped[1] == 1.0 and clipped[3] == 0.0 and clipped[0] < 1.0  # 10 clipped to 5
    enet = class_weights(counts, "enet")
    assert enet[1] > enet[0] > 0 and enet[3] == 0
    with pytest.raises(ValueError, match="class weighting"):
        class_weights(counts, "inverse")
    with pytest.raises(ValueError, match="no labelled pixel"):
        class_weights(torch.zeros(3, dtype=torch.int64))


def test_class_weighted_training_computes_weights_once_and_checkpoints_them(data_cfg, tmp_path):
    dm = SemanticDataModule(data_cfg, batch_size=2)
    model = _small_module(class_weighting="median_frequency")
    assert not bool(model.ce_weight_ready)
    trainer = L.Trainer(accelerator="cpu", max_steps=1, limit_val_batches=0, logger=False,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False)
    trainer.fit(model, datamodule=dm)
    assert bool(model.ce_weight_ready)
    weights = model.ce_weight.clone()
    road, pole = (next(c.id for c in model.classes if c.name == n) for n in ("Road", "Pole"))
    assert weights[pole] > weights[road] > 0  # the rare class weighs more
    path = tmp_path / "weighted.ckpt"
    trainer.save_checkpoint(path)
    again = SemanticModule.load_from_checkpoint(path, weights_only=True)
    torch.testing.assert_close(again.ce_weight, weights)
    assert bool(again.ce_weight_ready)
    # A checkpoint from before class weighting existed still loads (plain cross-entropy).
    ckpt = torch.load(path, weights_only=True)
    for key in ("ce_weight", "ce_weight_ready"):
        del ckpt["state_dict"][key]
    ckpt["hyper_parameters"].pop("class_weighting")
    ckpt["hyper_parameters"].pop("max_class_weight")
    torch.save(ckpt, tmp_path / "old.ckpt")
    old = SemanticModule.load_from_checkpoint(tmp_path / "old.ckpt", weights_only=True)
    assert bool(old.ce_weight_ready) and torch.equal(old.ce_weight, torch.ones(old.num_classes))
    with pytest.raises(ValueError, match="class_weighting"):
        _small_module(class_weighting="inverse")


def test_adamw_skip_decoder_and_jitter_train_and_reload_into_the_predictor(data_cfg, tmp_path):
    torch.manual_seed(0)
    dm = SemanticDataModule(data_cfg, batch_size=2)
    slim = [8, 16, 16, 32, 32, 32, 32, 32]
    model = _small_module(decoder="skip", decoder_channels=[16, 8, 8], channels=slim, optimizer="adamw",
                          lr=1e-3, color_jitter=0.3)
    trainer = L.Trainer(accelerator="cpu", max_steps=2, limit_val_batches=0, logger=False,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False)
    before = model.net.decoder.fuse[-1][0].weight.detach().clone()
    trainer.fit(model, datamodule=dm)
    assert isinstance(trainer.optimizers[0], torch.optim.AdamW)
    assert not torch.equal(before, model.net.decoder.fuse[-1][0].weight)
    path = tmp_path / "skip.ckpt"
    trainer.save_checkpoint(path)
    predictor = SemanticPredictor.from_checkpoint(path)
    assert predictor.net.decoder is not None
    image = next(iter(dm.val_dataloader()))["image"]
    model.eval()
    with torch.no_grad():
        expected = model(image)["logits"].softmax(1)
    torch.testing.assert_close(predictor(image).probability, expected, atol=1e-5, rtol=1e-4)


def test_rejects_bad_optimizer_decoder_and_jitter():
    with pytest.raises(ValueError, match="optimizer"):
        SemanticModule(optimizer="lbfgs", head_channels=32)
    with pytest.raises(ValueError, match="decoder"):
        SemanticModule(decoder="fpn", head_channels=32)
    with pytest.raises(ValueError, match="color_jitter"):
        SemanticModule(color_jitter=1.5, head_channels=32)


def test_semantic_cpu_experiment_composes_the_documented_cpu_recipe(data_cfg):
    cfg = _train_cfg("branch=semantic", "experiment=semantic_cpu", f"data.root={data_cfg.root}")
    assert cfg.data.kind == "vkitti1"
    assert list(cfg.data.image_size) == [312, 96] and cfg.trainer.max_epochs == 20
    assert cfg.trainer.check_val_every_n_epoch == 2
    model = instantiate(cfg.model, head_channels=32)
    assert model.hparams.decoder == "skip" and model.hparams.optimizer == "adamw"
    assert model.hparams.class_weighting == "enet" and model.net.decoder is not None
    assert model.net.backbone.channels == (16, 32, 64, 128, 128, 256, 256, 256)
    # experiment=semantic_cpu_fullres: full-size frames, crops, flip.
    full = _train_cfg("branch=semantic", "experiment=semantic_cpu_fullres", f"data.root={data_cfg.root}")
    assert list(full.data.image_size) == [624, 192] and full.trainer.max_epochs == 22
    fm = instantiate(full.model, head_channels=32)
    assert fm.hparams.crop_size == [312, 96] and fm.hparams.test_flip and fm.hparams.offset_weight == 0.05
    assert fm.net.backbone.channels == model.net.backbone.channels and fm.net.decoder is not None
    # The paper recipe keeps the paper's head and optimiser.
    paper = instantiate(_train_cfg("branch=semantic", "experiment=paper_vkitti").model, head_channels=32)
    assert paper.hparams.decoder == "bilinear" and paper.hparams.optimizer == "sgd" and paper.net.decoder is None


def test_semantic_gpu_experiment_composes_the_gpu_recipe(data_cfg):
    cfg = _train_cfg("branch=semantic", "experiment=semantic_gpu", f"data.root={data_cfg.root}", "trainer.max_epochs=7")
    assert cfg.data.kind == "vkitti1" and cfg.trainer.accelerator == "gpu"
    assert cfg.trainer.precision == "bf16-mixed" and cfg.trainer.check_val_every_n_epoch == 22
    assert cfg.trainer.max_epochs == 7  # what the user typed beats the experiment
    assert list(cfg.data.image_size) == [624, 192] and cfg.datamodule.num_workers == 6
    model = instantiate(cfg.model, head_channels=32)
    assert model.hparams.crop_size is None and model.hparams.test_flip and model.hparams.offset_weight == 0.05
    # The full DRN-D-22 (published widths) with the wider skip decoder.
    published = instantiate(OmegaConf.merge(cfg, {"model": {"decoder": "bilinear"}}).model, head_channels=32)
    assert model.net.backbone.channels == published.net.backbone.channels
    assert model.net.backbone.channels[-1] == 512 and model.net.decoder is not None
    assert list(model.hparams.decoder_channels) == [128, 64, 32]


def _bench_module():
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "semantic.py"
    spec = importlib.util.spec_from_file_location("semantic_bench", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_benchmark_ceiling_and_evaluate_on_the_fixture(data_cfg, tmp_path):
    import argparse

    from sdn3d.data.datasets import SemanticDataset
    from sdn3d.data.sources import SourceConfig

    bench = _bench_module()
    ceiling = bench.ceiling(argparse.Namespace(root=data_cfg.root, size=list(SIZE), part="test"))
    assert ceiling["stride_1"]["miou"] == 1.0  # full-resolution scores reproduce the labels exactly
    assert ceiling["stride_8"]["miou"] < 1.0
    assert sum(ceiling["pixel_share_percent"].values()) == pytest.approx(100.0, abs=0.01)

    dm = SemanticDataModule(data_cfg, batch_size=2)
    model = _small_module()
    trainer = L.Trainer(accelerator="cpu", max_steps=1, limit_val_batches=0, logger=False,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False)
    trainer.fit(model, datamodule=dm)
    path = tmp_path / "m.ckpt"
    trainer.save_checkpoint(path)
    result = bench.evaluate(argparse.Namespace(ckpt=str(path), root=data_cfg.root, size=list(SIZE), part="test",
                                               work_size=None, device="cpu", batch=2, flip=False))
    # The same mIoU by hand from the module's own predictions on that split.
    synth = OmegaConf.load(CONF / "data" / "synth.yaml")
    synth.root, synth.image_size = str(data_cfg.root), list(SIZE)
    ds = SemanticDataset.from_source(SourceConfig.from_mapping(OmegaConf.to_container(synth)), "test")
    model.eval()
    images = torch.stack([ds[i]["image"] for i in range(len(ds))])
    labels = torch.stack([ds[i]["label"] for i in range(len(ds))])
    with torch.no_grad():
        pred = model(images)["logits"].argmax(1)
    valid = labels != 255
    cm = torch.bincount(labels[valid] * 14 + pred[valid], minlength=196).reshape(14, 14).double()
    tp = cm.diagonal()
    union = cm.sum(0) + cm.sum(1) - tp
    assert result["images"] == len(ds)
    assert result["miou"] == pytest.approx(float((tp / union.clamp_min(1))[union > 0].mean()), abs=1e-4)


def test_test_flip_validates_with_flip_averaging_and_travels_to_the_predictor(data_cfg, tmp_path):
    from sdn3d.semantic import flip_averaged_outputs

    torch.manual_seed(0)
    dm = SemanticDataModule(data_cfg, batch_size=2)
    model = _small_module(channels=[8, 16, 16, 32, 32, 32, 32, 32], decoder="skip", decoder_channels=[16, 8, 8],
                          test_flip=True)
    trainer = L.Trainer(accelerator="cpu", max_epochs=1, limit_train_batches=1, limit_val_batches=1, logger=False,
                        num_sanity_val_steps=0, enable_checkpointing=False, enable_progress_bar=False,
                        enable_model_summary=False)
    trainer.fit(model, datamodule=dm)
    assert math.isfinite(float(trainer.callback_metrics["val/miou"]))
    path = tmp_path / "flip.ckpt"
    trainer.save_checkpoint(path)
    predictor = SemanticPredictor.from_checkpoint(path)
    assert predictor.flip and not SemanticPredictor.from_checkpoint(path, flip=False).flip
    image = next(iter(dm.val_dataloader()))["image"]
    model.eval()
    with torch.no_grad():
        expected = flip_averaged_outputs(model.net, image)["logits"].softmax(1)
        plain = model(image)["logits"].softmax(1)
    got = predictor(image).probability
    torch.testing.assert_close(got, expected, atol=1e-5, rtol=1e-4)
    assert not torch.allclose(got, plain, atol=1e-4)


def test_proposal_recall_metric_counts_objects_over_the_papers_size_scaled_to_the_maps():
    """ProposalRecall: the demo's measure inside the module; objects under 256 px at 624x192 (scaled by the area to
    the maps' size: 64 px at 312x96) are not counted, a proposal finds an object at IoU >= 0.5, precision is the
    share of proposals covering an object, and parts without objects or proposals give NaN (not logged)."""
    from lightning_modules.semantic import ProposalRecall

    gt = torch.zeros(1, 96, 312, dtype=torch.long)
    gt[0, 10:20, 10:20] = 13001    # 100 px: counted
    gt[0, 40:50, 40:50] = 13002    # 100 px: counted, not found
    gt[0, 80:87, 200:207] = 13003  # 49 px: under 64, not counted
    pred = torch.zeros_like(gt)
    pred[0, 10:20, 10:18] = 13001  # IoU 0.8 with the first
    pred[0, 60:70, 100:110] = 14001  # a proposal on nothing
    metric = ProposalRecall([13, 14])
    metric.update(pred, gt)
    result = metric.compute()
    assert float(result["recall"]) == pytest.approx(0.5) and float(result["precision"]) == pytest.approx(0.5)
    metric.reset()
    metric.update(torch.zeros_like(gt), torch.zeros_like(gt))
    assert torch.isnan(metric.compute()["recall"]) and torch.isnan(metric.compute()["precision"])
