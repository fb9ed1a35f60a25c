"""Textural branch benchmark: training / inference throughput, and a short training run with test metrics.

    python benchmarks/textural.py speed [--threads 2] [--repeats 3] [--size 624 192] [--device cpu|cuda]
    python benchmarks/textural.py train [--data-root /work/data/synth] [--preset demo] [--epochs N]
                                        [--train-batches N] [--threads 2] [--out outputs/bench/textural]

``speed``: images/s of one training iteration (encoder + generator forward, 3 discriminator passes,
G/E and D backward + Adam steps) and of inference (:meth:`sdn3d.textural.renderer.TexturalRenderer.reconstruct`:
encode + render), batch 1, at ``--size`` (default the VKITTI working size 624x192), for the demo
and paper network sizes of ``conf/branch/textural.yaml``. Inputs are one real synthetic frame
(data loading excluded). Median over ``--repeats`` after one warm-up; min given too, and the process
CPU seconds per image (summed over threads: on a shared, oversubscribed CPU wall time is not the
net's own cost; ``cpu_seconds / threads`` is the wall time on idle cores with perfect scaling).

``train``: the branch config with ``--preset`` merged (``demo`` by default, ``--epochs`` /
``--train-batches`` override its budget; ``--epochs`` also resets the lr schedule to half
constant, half linear decay), trained with Lightning on ``--data-root`` (a VKITTI-format
folder, e.g. the synthetic one), then evaluated on the whole test split (PSNR / SSIM / L1 on whole
images and on object pixels). Writes ``<out>/textural.json``, ``<out>/last.ckpt`` and the grid
``docs/images/textural_grid.png``: label | reconstruction | real | reconstruction with every car's
code resampled from the training code bank (:class:`sdn3d.textural.renderer.CodeBank`).
"""

from __future__ import annotations

import argparse
import json
import logging
import statistics
import sys
import time
from pathlib import Path

import torch
from omegaconf import OmegaConf

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))  # lightning_modules / datamodules when run as a script

from datamodules import TexturalDataModule  # noqa: E402
from lightning_modules._base import image_grid  # noqa: E402
from lightning_modules.textural import TexturalModule  # noqa: E402
from sdn3d.evaluation.image_metrics import image_metrics  # noqa: E402
from sdn3d.labels import INSTANCE_DIVISOR  # noqa: E402
from sdn3d.textural.codes import CodeBank, sample_code  # noqa: E402
from sdn3d.textural.renderer import TexturalRenderer  # noqa: E402

GRID_PATH = REPO / "docs" / "images" / "textural_grid.png"


def branch_config(preset: str | None, data_root: str) -> OmegaConf:
    data = OmegaConf.load(REPO / "conf" / "data" / "synth.yaml")
    data.root = data_root
    cfg = OmegaConf.merge({"data": data, "seed": 0}, OmegaConf.load(REPO / "conf" / "branch" / "textural.yaml"))
    return OmegaConf.merge(cfg, OmegaConf.load(REPO / "conf" / "recipe" / f"textural_{preset}.yaml")) if preset else cfg


def _model_kwargs(cfg) -> dict:
    kw = OmegaConf.to_container(cfg.model, resolve=True)
    kw.pop("_target_")
    return kw


def _timed(fn, repeats: int, cuda: bool = False) -> tuple[float, float, float]:
    """Median and min wall seconds per call, and median process CPU seconds per call (all threads);
    ``cuda``: synchronize after each call, so its kernels count."""
    fn()  # warm-up
    times, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        if cuda:
            torch.cuda.synchronize()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return statistics.median(times), min(times), statistics.median(cpu)


def speed(args) -> dict:
    w, h = args.size
    dm = TexturalDataModule(branch_config(None, args.data_root).data, image_size=(w, h), batch_size=1)
    device = torch.device(args.device)
    cuda = device.type == "cuda"
    batch = {k: v.to(device) if torch.is_tensor(v) else v for k, v in next(iter(dm.val_dataloader())).items()}
    results = {}
    for preset in ("demo", "paper"):
        model = TexturalModule(**_model_kwargs(branch_config(preset, args.data_root))).to(device)
        opt_g, opt_d = model.configure_optimizers()[0]

        def train_iter(model=model, opt_g=opt_g, opt_d=opt_d) -> None:
            from sdn3d.nets.pix2pixhd import feature_matching_loss, lsgan_loss

            fake, real, cond = model._generate(batch)
            d = model.discriminator
            d.requires_grad_(False)
            pf = d(torch.cat([cond, fake], 1))
            d.requires_grad_(True)
            pr, pd = d(torch.cat([cond, real], 1)), d(torch.cat([cond, fake.detach()], 1))
            loss_g = lsgan_loss(pf, True) + 5 * feature_matching_loss(pf, pr) + 10 * (fake - real).abs().mean()
            loss_d = 0.5 * (lsgan_loss(pr, True) + lsgan_loss(pd, False))
            opt_g.zero_grad()
            loss_g.backward()
            opt_g.step()
            opt_d.zero_grad()
            loss_d.backward()
            opt_d.step()

        renderer = TexturalRenderer.from_state_dict(model.state_dict(), dict(model.hparams)).to(device)

        def infer(renderer=renderer) -> None:
            renderer.reconstruct(batch["image"], batch["label"], batch["instance_label_map"], batch["boundary"],
                                 batch["pose"], batch["normal"])

        tm, tmin, tcpu = _timed(train_iter, args.repeats, cuda)
        im, imin, icpu = _timed(infer, args.repeats, cuda)
        results[preset] = {
            "generator_params_M": round(sum(p.numel() for p in model.generator.parameters()) / 1e6, 3),
            "train_images_per_s": round(1 / tm, 3), "train_images_per_s_best": round(1 / tmin, 3),
            "train_cpu_seconds_per_image": round(tcpu, 3),
            "infer_images_per_s": round(1 / im, 3), "infer_images_per_s_best": round(1 / imin, 3),
            "infer_cpu_seconds_per_image": round(icpu, 3),
        }
        print(preset, results[preset], flush=True)
    return {"mode": "speed", "size": [w, h], "batch_size": 1, "threads": torch.get_num_threads(),
            "device": str(device), "gpu": torch.cuda.get_device_name(device) if cuda else None,
            "repeats": args.repeats, "results": results}


@torch.no_grad()
def evaluate(renderer: TexturalRenderer, loader) -> tuple[dict, dict]:
    sums: dict[str, list[torch.Tensor]] = {}
    first = None
    for batch in loader:
        fake = renderer.reconstruct(batch["image"], batch["label"], batch["instance_label_map"], batch["boundary"],
                                    batch["pose"], batch["normal"]).clamp(0, 1)
        objects = batch["instance_label_map"] >= INSTANCE_DIVISOR
        for prefix, mask in (("", None), ("obj_", objects)):
            for k, v in image_metrics(fake, batch["image"], mask).items():
                sums.setdefault(prefix + k, []).append(v)
        if first is None:
            first = {**batch, "fake": fake}
    return {k: round(float(torch.nanmean(torch.cat(v))), 4) for k, v in sums.items()}, first


def train(args) -> dict:
    import lightning as L

    cfg = branch_config(args.preset, args.data_root)
    if args.epochs is not None:  # keep the preset's shape of schedule: half constant, half linear decay
        cfg.trainer.max_epochs = args.epochs
        cfg.model.lr_constant_epochs = args.epochs // 2
        cfg.model.lr_decay_epochs = args.epochs - args.epochs // 2
    if args.train_batches is not None:
        cfg.trainer.limit_train_batches = args.train_batches
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    L.seed_everything(0)
    model = TexturalModule(**_model_kwargs(cfg))
    dm_kw = OmegaConf.to_container(cfg.datamodule, resolve=True)
    dm_kw.pop("_target_")
    dm = TexturalDataModule(**dm_kw)
    trainer_kw = OmegaConf.to_container(cfg.trainer, resolve=True)
    class Progress(L.Callback):
        def on_train_epoch_end(self, trainer, module) -> None:
            psnr = float(trainer.callback_metrics.get("val/psnr", 0))
            print(f"epoch {trainer.current_epoch}: {int(module.g_updates)} G updates, "
                  f"{time.perf_counter() - t0:.0f} s, val/psnr {psnr:.2f}", flush=True)

    trainer = L.Trainer(accelerator="cpu", logger=False, enable_checkpointing=False, enable_progress_bar=False,
                        enable_model_summary=False, num_sanity_val_steps=0, callbacks=[Progress()], **trainer_kw)
    t0 = time.perf_counter()
    trainer.fit(model, datamodule=dm)
    train_s = time.perf_counter() - t0
    trainer.save_checkpoint(out / "last.ckpt")
    renderer = TexturalRenderer.from_checkpoint(out / "last.ckpt")

    dm.batch_size = 4
    dm.setup("test")
    t0 = time.perf_counter()
    test_metrics, first = evaluate(renderer, dm.test_dataloader())
    test_s = time.perf_counter() - t0

    # Code bank from the training split, then new paint for every car of the grid's images.
    bank = CodeBank.from_codes(renderer.encode(b["image"], b["instance_label_map"])
                               for b in dm._loader("train", shuffle=False))
    n = min(4, first["image"].shape[0])
    codes = renderer.encode(first["image"][:n], first["instance_label_map"][:n])
    gen = torch.Generator().manual_seed(0)
    for b, rid in zip(codes.batch.tolist(), codes.ids.tolist(), strict=True):
        if rid >= INSTANCE_DIVISOR:
            codes = sample_code(codes, bank, b, rid, generator=gen)
    recoloured = renderer.render(first["label"][:n], first["instance_label_map"][:n], first["boundary"][:n],
                                 codes=codes, pose=first["pose"][:n], normal=first["normal"][:n])
    grid = image_grid([model.colorize(first["label"][:n]), first["fake"][:n], first["image"][:n], recoloured])
    GRID_PATH.parent.mkdir(parents=True, exist_ok=True)
    from PIL import Image

    Image.fromarray((grid.permute(1, 2, 0).numpy() * 255).round().astype("uint8")).save(GRID_PATH)
    return {
        "mode": "train", "preset": args.preset, "threads": torch.get_num_threads(),
        "image_size": list(dm.image_size), "train_frames": len(dm.datasets["train"]),
        "test_frames": len(dm.datasets["test"]), "model": _model_kwargs(cfg),
        "trainer": trainer_kw, "g_updates": int(model.g_updates), "global_step": trainer.global_step,
        "train_seconds": round(train_s, 1), "test_seconds": round(test_s, 1), "test": test_metrics,
        "code_bank": {"classes": bank.classes, "codes": len(bank)}, "grid": str(GRID_PATH.relative_to(REPO)),
        "grid_columns": "label | reconstruction | real | cars with codes sampled from the training bank",
    }


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mode", choices=["speed", "train"])
    p.add_argument("--data-root", default="/work/data/synth")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--size", type=int, nargs=2, default=(624, 192), metavar=("W", "H"))
    p.add_argument("--preset", default="demo")
    p.add_argument("--device", default="cpu", help="speed mode: cpu | cuda")
    p.add_argument("--epochs", type=int, default=None)
    p.add_argument("--train-batches", type=int, default=None)
    p.add_argument("--out", default=str(REPO / "outputs" / "bench" / "textural"))
    args = p.parse_args(argv)
    torch.set_num_threads(args.threads)
    logging.basicConfig(level=logging.WARNING)
    result = speed(args) if args.mode == "speed" else train(args)
    text = json.dumps(result, indent=2)
    print(text)
    if args.mode == "train":
        (Path(args.out) / "textural.json").write_text(text + "\n")


if __name__ == "__main__":
    main()
