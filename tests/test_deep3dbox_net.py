"""The independent Deep3DBox baseline: MultiBin (sdn3d.geometric.multibin), Deep3DBoxNet and its decoding
(sdn3d.geometric.deep3dbox_net), Deep3DBoxModule (training, decode_batch contract, configs).

(tests/test_deep3dbox.py covers the 2D-box translation solver it uses.)"""

from __future__ import annotations

import math
from pathlib import Path

import lightning as L
import pytest
import torch
from hydra import compose, initialize_config_dir
from hydra.utils import instantiate

from datamodules import GeometricDataModule
from lightning_modules.deep3dbox import Deep3DBoxModule, Deep3DBoxSettingError, native_pixel_pad, object_dimensions
from sdn3d.geometric import GeometricNet
from sdn3d.geometric.deep3dbox import solve_translation
from sdn3d.geometric.deep3dbox_net import (
    DEEP3DBOX_OUTPUT_KEYS,
    Deep3DBoxNet,
    decode_deep3dbox,
    global_yaw,
    local_yaw,
    pinhole_center,
    ray_angle,
)
from sdn3d.geometric.multibin import (
    bin_centers,
    bin_half_width,
    decode_multibin,
    encode_multibin,
    multibin_losses,
)
from sdn3d.math3d.rotations import observation_angle, roty, wrap_angle
from sdn3d.math3d.transforms import project_box
from sdn3d.meshes.templates import TEMPLATE_NAMES

CONF = str(Path(__file__).resolve().parents[1] / "conf")
SIZE = (312, 96)
# The synthetic data's camera at 624x192 (Virtual KITTI resized), as (fx, fy, cx, cy).
INTR = (364.25, 371.2, 311.5, 95.5)


def _angle_gap(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    return wrap_angle(a - b).abs()


# --------------------------------------------------------------------------- MultiBin
def test_two_bins_cover_every_angle_once_or_twice_with_overlap_at_the_sides():
    angle = torch.linspace(-3 * math.pi, 3 * math.pi, 2001, dtype=torch.float64)
    cover, residual = encode_multibin(angle, 2, 0.1)
    assert cover.shape == residual.shape == (2001, 2)
    counts = cover.sum(1)
    assert bool((counts >= 1).all()) and bool((counts <= 2).all())
    # both bins exactly where |wrap(angle)| is within 0.1 * pi / 2 of pi / 2
    edge = (wrap_angle(angle).abs() - math.pi / 2).abs() - 0.1 * math.pi / 2
    away = edge.abs() > 1e-9  # not on a bin's edge, where rounding decides
    assert torch.equal((counts == 2)[away], (edge <= 0)[away]) and int((counts == 2).sum()) > 100
    # residuals are the angle relative to each centre (0 and -pi), wrapped
    torch.testing.assert_close(residual, wrap_angle(angle[:, None] - bin_centers(2, dtype=torch.float64)))
    assert bin_half_width(2, 0.1) == pytest.approx(math.pi / 2 * 1.1)


@pytest.mark.parametrize("num_bins", [1, 2, 4])
def test_encode_decode_round_trip_through_any_covering_bin_and_the_wrap(num_bins):
    angle = torch.cat([torch.linspace(-math.pi, math.pi, 181, dtype=torch.float64)[:-1],
                       torch.tensor([math.pi - 1e-9, -math.pi, math.pi / 2, -math.pi / 2, 7.0, -7.0],
                                    dtype=torch.float64)])
    cover, residual = encode_multibin(angle, num_bins, 0.1)
    unit = torch.stack([residual.cos(), residual.sin()], -1)
    for pick in ("first", "last"):  # the most confident bin may be either covering bin
        order = torch.arange(num_bins, dtype=torch.float64).expand_as(residual)
        score = torch.where(cover, order if pick == "last" else -order, torch.full_like(order, -1e9))
        decoded = decode_multibin(score, unit * 3.0)  # the residual's scale does not matter
        assert bool((decoded >= -math.pi).all()) and bool((decoded < math.pi).all())
        assert float(_angle_gap(decoded, angle).max()) < 1e-9


def test_losses_vanish_at_the_target_and_punish_the_wrong_residual():
    angle = torch.tensor([0.3, -2.9, math.pi / 2, 3.1], dtype=torch.float64)
    cover, residual = encode_multibin(angle, 2, 0.1)
    unit = torch.stack([residual.cos(), residual.sin()], -1)
    logits = torch.where(cover, 30.0, -30.0).to(torch.float64)
    terms = multibin_losses(logits, unit, angle, 0.1)
    assert terms["loc"].abs().max() < 1e-12
    # a confident right answer: cross-entropy against the covering bins (log 2 where two bins share the target)
    expected_conf = (cover.sum(1) == 2).to(torch.float64) * math.log(2.0)
    torch.testing.assert_close(terms["conf"], expected_conf, atol=1e-9, rtol=0)
    # a residual off by 90 degrees costs 1 - cos(90 deg) = 1 in every covering bin
    turned = torch.stack([-unit[..., 1], unit[..., 0]], -1)
    torch.testing.assert_close(multibin_losses(logits, turned, angle, 0.1)["loc"], torch.ones(4, dtype=torch.float64))
    # confidence on the wrong bin alone costs about 60
    single = cover.sum(1) == 1
    assert bool((multibin_losses(-logits, unit, angle, 0.1)["conf"][single] > 25).all()) and int(single.sum()) == 3


def test_multibin_losses_gradcheck_and_a_gradient_step_lowers_them():
    torch.manual_seed(0)
    angle = torch.rand(5, dtype=torch.float64) * 2 * math.pi - math.pi
    logits = torch.randn(5, 2, dtype=torch.float64, requires_grad=True)
    raw = torch.randn(5, 2, 2, dtype=torch.float64, requires_grad=True)

    def total(lg: torch.Tensor, rs: torch.Tensor) -> torch.Tensor:
        terms = multibin_losses(lg, rs, angle, 0.1)
        return terms["conf"] + 0.7 * terms["loc"]

    assert torch.autograd.gradcheck(total, (logits, raw))
    loss = total(logits, raw).sum()
    loss.backward()
    with torch.no_grad():
        stepped = total(logits - 0.05 * logits.grad, raw - 0.05 * raw.grad).sum()
    assert float(stepped) < float(loss.detach())


def test_multibin_refuses_bad_settings_and_shapes():
    with pytest.raises(ValueError, match="num_bins"):
        encode_multibin(torch.zeros(3), 0, 0.1)
    with pytest.raises(ValueError, match="overlap"):
        encode_multibin(torch.zeros(3), 2, 1.5)
    with pytest.raises(ValueError, match=r"\(N, B, 2\)"):
        multibin_losses(torch.zeros(3, 2), torch.zeros(3, 3, 2), torch.zeros(3), 0.1)


# --------------------------------------------------------------------------- geometry and the net
def _scene(n: int, seed: int = 0):
    """Car-sized boxes in front of the synthetic camera, their tight 2D boxes and intrinsics ``(N, 4)``."""
    g = torch.Generator().manual_seed(seed)
    uni = lambda lo, hi: torch.rand(n, generator=g, dtype=torch.float64) * (hi - lo) + lo  # noqa: E731
    dims = torch.stack([uni(3.5, 5.0), uni(1.4, 1.9), uni(1.6, 2.0)], -1)
    ry = uni(-math.pi, math.pi)
    z = uni(8.0, 40.0)
    center = torch.stack([uni(-0.5, 0.5) * z, uni(0.5, 1.5), z], -1)
    intr = torch.tensor(INTR, dtype=torch.float64).expand(n, 4)
    K = torch.tensor([[INTR[0], 0, INTR[2]], [0, INTR[1], INTR[3]], [0, 0, 1]], dtype=torch.float64)
    return dims, ry, center, project_box(dims, ry, center, K), intr


def test_local_and_global_yaw_invert_each_other_and_follow_the_box_ray():
    dims, ry, center, box, intr = _scene(64)
    alpha = local_yaw(ry, box, intr)
    assert float(_angle_gap(global_yaw(alpha, box, intr), ry).max()) < 1e-12
    # a box centred on the principal point looks straight ahead: alpha = ry
    ahead = torch.tensor([[INTR[2] - 20, 40.0, INTR[2] + 20, 60.0]], dtype=torch.float64)
    assert float(ray_angle(ahead, intr[:1])) == pytest.approx(0.0, abs=1e-12)
    # close to KITTI's observation angle (the ray through the 3D centre instead of the 2D box centre)
    kitti = observation_angle(ry, center[:, 0], center[:, 2])
    assert float(_angle_gap(alpha, kitti).max()) < 0.05


def test_net_outputs_unit_residuals_and_starts_at_the_class_mean():
    net = Deep3DBoxNet(num_bins=2, hidden=32, mean_dims=(4.2, 1.5, 1.8)).eval()
    out = net(torch.rand(3, 3, 32, 32))
    assert set(out) == set(DEEP3DBOX_OUTPUT_KEYS)
    assert out["conf_logits"].shape == (3, 2) and out["residual"].shape == (3, 2, 2)
    torch.testing.assert_close(out["residual"].norm(dim=-1), torch.ones(3, 2))
    assert float(out["dims_residual"].abs().max()) == 0.0  # the zero-initialised head: dims = mean
    assert not net.use_ffd and net.num_templates == 1 and int(net.templates) == TEMPLATE_NAMES.index("sedan")
    net.set_mean_dims(torch.tensor([[4.0, 1.4, 1.7], [5.0, 1.6, 1.9]]))
    torch.testing.assert_close(net.mean_dims, torch.tensor([4.5, 1.5, 1.8]))
    assert "mean_dims" in net.state_dict()  # checkpoints carry it
    with pytest.raises(ValueError, match="mean_dims"):
        net.set_mean_dims(torch.tensor([[4.0, -1.0, 1.7]]))


def test_decoding_a_perfect_output_recovers_yaw_dims_and_translation():
    dims, ry, center, box, intr = _scene(40, seed=3)
    mean = torch.tensor([4.2, 1.6, 1.8], dtype=torch.float64)
    cover, residual = encode_multibin(local_yaw(ry, box, intr), 2, 0.1)
    out = {"conf_logits": cover.to(torch.float64), "residual": torch.stack([residual.cos(), residual.sin()], -1),
           "dims_residual": dims - mean}
    pred = decode_deep3dbox(out, mean, box, intr, box_pad=0.0)
    assert float(_angle_gap(pred["ry"], ry).max()) < 1e-9
    torch.testing.assert_close(pred["dims"], dims)
    assert bool(pred["fit_valid"].all()) and float(pred["fit_iou"].min()) > 1 - 1e-6
    torch.testing.assert_close(pred["center"], center, atol=1e-6, rtol=0)
    torch.testing.assert_close(pred["location"][:, 1], center[:, 1] + dims[:, 1] / 2)


def test_pinhole_center_puts_the_box_height_at_its_depth():
    intr = torch.tensor([INTR], dtype=torch.float64)
    box = torch.tensor([[300.0, 80.0, 340.0, 110.0]], dtype=torch.float64)
    dims = torch.tensor([[4.0, 1.5, 1.8]], dtype=torch.float64)
    c = pinhole_center(box, dims, intr)[0]
    z = INTR[1] * 1.5 / 30.0
    torch.testing.assert_close(c, torch.tensor([(320 - INTR[2]) / INTR[0] * z, (95 - INTR[3]) / INTR[1] * z, z],
                                               dtype=torch.float64))


# --------------------------------------------------------------------------- the module
@pytest.fixture(scope="module")
def synth_root(tmp_path_factory) -> Path:
    from sdn3d.data.synth import SynthConfig, generate_dataset

    root = tmp_path_factory.mktemp("d3b_synth") / "vkitti"
    generate_dataset(SynthConfig(output_dir=str(root), image_size=SIZE, frames_per_sequence=5,
                                 cars_per_frame=(4, 6), edit_pairs=0))
    return root


# Of the fixture's 5 frames per sequence, 0-2 train, 3 validates and 4 tests.
FIXTURE_SPLIT = {"rule": "paper", "val_fraction": 0.25, "val_gap": 0}


def _datamodule(root: Path) -> GeometricDataModule:
    data = {"kind": "vkitti1", "root": str(root), "image_size": list(SIZE), "split": dict(FIXTURE_SPLIT)}
    return GeometricDataModule(data, batch_size=4, crop_size=32, min_pixels=32)


def _module(**kwargs) -> Deep3DBoxModule:
    return Deep3DBoxModule(**{"pred_epochs": 1, "joint_epochs": 1, "image_size": SIZE, "hidden": 32, "log_images": 0,
                              **kwargs})


def _trainer(max_epochs: int = 1, **kwargs) -> L.Trainer:
    return L.Trainer(max_epochs=max_epochs, limit_train_batches=2, limit_val_batches=1, limit_test_batches=1,
                     accelerator="cpu", enable_checkpointing=False, enable_progress_bar=False,
                     enable_model_summary=False, num_sanity_val_steps=0, logger=False, **kwargs)


def test_module_trains_validates_and_keeps_its_class_mean_in_the_checkpoint(synth_root, tmp_path):
    model, dm = _module(), _datamodule(synth_root)
    before = [p.detach().clone() for p in model.net.parameters()]
    trainer = _trainer(2)
    trainer.fit(model, datamodule=dm)
    metrics = trainer.callback_metrics
    for name in ("train/loss", "train/loss_conf", "train/loss_loc", "train/loss_dims", "val/loss",
                 "val/orientation_similarity", "val/distance_error", "val/scale_error", "val/mesh_accuracy",
                 "val/box_fit_invalid", "val/box_fit_iou", "val/template_prob/sedan"):
        assert torch.isfinite(metrics[name]), name
    reprojection = [k for k in metrics if k.startswith("val/reprojection_error")]  # the shared evaluation's
    assert reprojection and all(bool(torch.isfinite(metrics[k])) for k in reprojection)
    assert float(metrics["val/template_prob/sedan"]) == 1.0
    assert any(not torch.equal(a, b) for a, b in zip(before, model.net.parameters(), strict=True))
    # the class mean is the training objects' mean size, read from the annotations
    train = dm.datasets["train"]
    expected = torch.stack([train[i]["dims"] for i in range(len(train))]).double().mean(0)
    torch.testing.assert_close(model.net.mean_dims.double(), expected, atol=1e-5, rtol=0)
    torch.testing.assert_close(object_dimensions(train).mean(0), expected, atol=1e-5, rtol=0)
    # half a native pixel at the working width (the synthetic frames are generated at the working size)
    native = train.records[0].intrinsics.width
    assert float(model.box_pad) == pytest.approx(0.5 * SIZE[0] / native) == native_pixel_pad(train)
    ckpt = tmp_path / "d3b.ckpt"
    trainer.save_checkpoint(ckpt)
    state = torch.load(ckpt, map_location="cpu", weights_only=True)
    torch.testing.assert_close(state["state_dict"]["net.mean_dims"], model.net.mean_dims)
    assert state["hyper_parameters"]["num_bins"] == 2 and state["hyper_parameters"]["single_cad"] is True
    # a fresh module tested from the checkpoint uses the checkpoint's mean, not its own prior
    fresh = _module()
    _trainer().test(fresh, datamodule=_datamodule(synth_root), ckpt_path=str(ckpt))
    torch.testing.assert_close(fresh.net.mean_dims, model.net.mean_dims)
    # it scores Table 2 only: de-rendering from it is refused in one clear sentence
    from sdn3d.errors import UserInputError
    from sdn3d.geometric.predict import GeometricPredictor

    with pytest.raises(UserInputError, match="d3b.ckpt.* Deep3DBox baseline checkpoint .*cannot de-render"):
        GeometricPredictor.from_checkpoint(ckpt)


def test_a_few_steps_on_one_batch_lower_the_loss(synth_root):
    torch.manual_seed(0)
    model = _module(lr_pred=1e-3, weight_decay=0.0)
    batch = next(iter(_datamodule(synth_root).train_dataloader()))
    optimizer = torch.optim.Adam(model.net.parameters(), lr=1e-3)
    losses = []
    for _ in range(8):
        terms = model._losses(model.net(batch["crop"]), batch)
        optimizer.zero_grad()
        terms["loss"].backward()
        optimizer.step()
        losses.append(float(terms["loss"]))
    assert losses[-1] < 0.7 * losses[0], losses


def test_decode_batch_contract_and_its_predictions_come_from_the_deep3dbox_net(synth_root):
    model = _module().eval()
    batch = next(iter(_datamodule(synth_root).val_dataloader()))
    n = batch["crop"].shape[0]
    assert isinstance(model.net, Deep3DBoxNet)
    assert not any(isinstance(m, GeometricNet) for m in model.modules())
    pred = model.decode_batch("val", batch)
    shapes = {"template_id": (n,), "template_probs": (n, len(TEMPLATE_NAMES)), "phi": (n, 64, 3), "dims": (n, 3),
              "ry": (n,), "center": (n, 3), "location": (n, 3), "rot": (n, 3, 3)}
    for key, shape in shapes.items():
        assert tuple(pred[key].shape) == shape, key
    sedan = TEMPLATE_NAMES.index("sedan")
    assert pred["template_id"].dtype == torch.long and bool((pred["template_id"] == sedan).all())
    assert bool((pred["template_probs"][:, sedan] == 1).all()) and float(pred["template_probs"].sum()) == n
    assert float(pred["phi"].abs().max()) == 0.0
    torch.testing.assert_close(pred["rot"], roty(pred["ry"]))
    # yaw and dims are the Deep3DBox heads' (shift the dims head: the dims follow), the centre the box fit's
    out = model.net(batch["crop"])
    torch.testing.assert_close(pred["dims"], (model.net.mean_dims + out["dims_residual"]).clamp_min(0.05))
    torch.testing.assert_close(pred["ry"], global_yaw(decode_multibin(out["conf_logits"], out["residual"]),
                                                      batch["box"], batch["intrinsics"]))
    with torch.no_grad():
        model.net.heads["dims_residual"][-1].bias.add_(torch.tensor([0.5, 0.1, -0.2]))
    shifted = model.decode_batch("val", batch)
    torch.testing.assert_close(shifted["dims"] - pred["dims"], torch.tensor([0.5, 0.1, -0.2]).expand(n, 3))
    pad = float(model.box_pad)
    fit = solve_translation(batch["box"] + torch.tensor([-pad, -pad, pad, pad]), shifted["dims"], shifted["ry"],
                            torch.stack([torch.tensor([[f, 0, cx], [0, g, cy], [0, 0, 1.0]])
                                         for f, g, cx, cy in batch["intrinsics"].tolist()]))
    valid = fit.valid
    torch.testing.assert_close(shifted["center"][valid], fit.center[valid])


def test_box_pad_is_half_a_native_pixel_unless_set():
    from types import SimpleNamespace

    vkitti = SimpleNamespace(records=[SimpleNamespace(intrinsics=SimpleNamespace(width=1242))], image_size=(624, 192))
    assert native_pixel_pad(vkitti) == pytest.approx(0.5 * 624 / 1242)
    assert native_pixel_pad(SimpleNamespace()) is None and object_dimensions(SimpleNamespace()) is None
    model = _module(box_pad=0.0)
    trainer = SimpleNamespace(datamodule=SimpleNamespace(datasets={"test": vkitti}))
    model._trainer = trainer  # setup reads only trainer.datamodule
    model.setup("test")
    assert float(model.box_pad) == 0.0
    model = _module()
    model._trainer = trainer
    model.setup("test")
    assert float(model.box_pad) == pytest.approx(0.5 * 624 / 1242)


def test_module_refuses_settings_it_can_not_honour():
    with pytest.raises(Deep3DBoxSettingError, match="ablation.reproj"):
        Deep3DBoxModule(reproj=True)
    with pytest.raises(Deep3DBoxSettingError, match="ablation.rotation"):
        Deep3DBoxModule(rotation="full_quaternion")
    with pytest.raises(TypeError, match="no_such_setting"):
        Deep3DBoxModule(no_such_setting=1)
    with pytest.raises(ValueError, match="overlap"):
        Deep3DBoxModule(overlap=2.0)
    with pytest.raises(ValueError, match="image_size"):
        Deep3DBoxModule(truncation=True)


def test_the_deep3dbox_ablation_builds_the_baseline_from_the_branch_config(synth_root, tmp_path):
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        cfg = compose("train", overrides=["branch=geometric", "ablation=deep3dbox", "experiment=table2",
                                          f"data.root={synth_root}", f"run_dir={tmp_path}", "model.hidden=32",
                                          "model.overlap=0.2"])
    assert cfg.ablation.name == "deep3dbox"
    model = instantiate(cfg.model)
    assert isinstance(model, Deep3DBoxModule) and isinstance(model.net, Deep3DBoxNet)
    hp = model.hparams
    assert hp.overlap == 0.2 and hp.num_bins == 2 and hp.pred_epochs == cfg.model.pred_epochs
    assert hp.single_template == "sedan" and hp.image_size == list(cfg.data.image_size)
