"""Semantic branch benchmark: DRN speed (forward / training step) and a timed training run; prints JSON.

    python benchmarks/semantic.py speed [--size W H] [--batch B] [--threads T] [--repeats N] [--arch drn_d_22]
        [--decoder bilinear|skip] [--channels C1 ... C8] [--device cpu|cuda]
    python benchmarks/semantic.py ceiling --root /work/data/synth [--size W H] [--part test]
    python benchmarks/semantic.py evaluate --ckpt CKPT --root /work/data/synth [--size W H] [--work-size W H]
    python benchmarks/semantic.py train --root /work/data/synth [--size W H] [--epochs E] [--batch B]
        [--lr LR] [--crop C] [--threads T] [--out DIR] [--set key=value ...] [--device cpu|cuda]
        [--precision 32-true|16-mixed|bf16-mixed] [--preset cpu]

``speed``: images/s of ``DRNSeg`` (with the instance head) for inference (eval, no grad) and
for a training step (forward, loss, backward, SGD step) on random images; medians over
``--repeats`` after one warm-up call (the minimum too, the CPU may be shared).

``ceiling``: the best mIoU a head predicting at output stride ``s`` (1, 2, 4, 8) could reach on a split
when its class scores are upsampled bilinearly: ideal scores = the one-hot ground truth average-pooled
over ``s`` x ``s`` cells, upsampled to the working size, argmax. Shows what the stride-8 DRN head
loses on thin classes (poles, signs, lights) and what the skip decoder can win back.

``evaluate``: mIoU / per-class IoU of a ``SemanticModule`` checkpoint on a split at ``--size``
(the labels' resolution), through :class:`sdn3d.semantic.SemanticPredictor`: with ``--work-size``
the network runs at that size and its class probabilities are upsampled bilinearly to ``--size``
(how a model trained at half the working size is scored at the full one).

``train``: ``SemanticModule`` + ``SemanticDataModule`` on a ``conf/data/synth.yaml`` dataset
(frames decoded once and kept in memory, so the timing is the network's), ``lightning.Trainer``
on the CPU, then a test on the test split. Reports the test metrics (mIoU, per-class IoU,
thing-class PQ), the fit wall time (validation included) and the training images/s (time
inside training batches only). ``--max-minutes`` stops fitting early (Trainer ``max_time``; the poly
schedule still assumes ``--epochs``). ``--device cuda`` runs the same on one GPU (``--precision``
defaults to 32-true, the CPU run's arithmetic; CUDA timings synchronize before the clock stops).
``--preset NAME`` takes the module arguments, batch size, working size, epochs and validation interval
from ``conf/recipe/semantic_NAME.yaml`` (``--size`` / ``--epochs`` / ``--batch`` / ``--lr``
given explicitly on the command line still win). ``--set`` passes other ``SemanticModule`` arguments
(e.g. ``--set center_sigma=3``). Checkpoints and TensorBoard logs go under ``--out``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import torch
import yaml

REPO = Path(__file__).resolve().parents[1]


def speed(args: argparse.Namespace) -> dict:
    from sdn3d.nets.drn import DRNSeg

    torch.manual_seed(0)
    w, h = args.size
    device = torch.device(args.device)
    extra = {"channels": args.channels} if args.channels else {}
    net = DRNSeg(14, arch=args.arch, decoder=args.decoder, **extra).to(device, memory_format=torch.channels_last)
    image = torch.rand(args.batch, 3, h, w).to(device).contiguous(memory_format=torch.channels_last)
    label = torch.randint(0, 14, (args.batch, h, w)).to(device)
    opt = torch.optim.SGD(net.parameters(), lr=1e-3, momentum=0.9)

    def train_step() -> None:
        out = net(image)
        loss = torch.nn.functional.cross_entropy(out["logits"], label) + out["center"].square().mean() \
            + out["offset"].abs().mean()
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()

    def infer() -> None:
        with torch.no_grad():
            net(image)

    result = {"arch": args.arch, "decoder": args.decoder, "channels": args.channels,
              "size": [w, h], "batch": args.batch, "threads": torch.get_num_threads(),
              "device": str(device), "gpu": torch.cuda.get_device_name(device) if device.type == "cuda" else None,
              "params_M": round(sum(p.numel() for p in net.parameters()) / 1e6, 3)}
    for name, fn, mode in (("train", train_step, True), ("inference", infer, False)):
        net.train(mode)
        fn()  # warm-up
        times = []
        for _ in range(args.repeats):
            t = time.perf_counter()
            fn()
            if device.type == "cuda":
                torch.cuda.synchronize()
            times.append(time.perf_counter() - t)
        result[f"{name}_s_per_batch_median"] = round(statistics.median(times), 4)
        result[f"{name}_images_per_s_median"] = round(args.batch / statistics.median(times), 3)
        result[f"{name}_images_per_s_best"] = round(args.batch / min(times), 3)
    return result


def ceiling(args: argparse.Namespace) -> dict:
    import torch.nn.functional as F

    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.datasets import SemanticDataset

    dataset = SemanticDataset.from_source(synth_data_source(args.root, args.size), args.part)
    labels = torch.stack([dataset[i]["label"] for i in range(len(dataset))])  # (N, H, W)
    n = len(dataset.classes)
    valid = labels != 255
    share = torch.bincount(labels[valid], minlength=n).double()
    result = {"size": list(args.size), "part": args.part, "images": len(dataset),
              "pixel_share_percent": {c.name: round(100 * float(v), 3)
                                      for c, v in zip(dataset.classes, share / share.sum(), strict=True)},
              "method": "one-hot ground truth avg-pooled over s x s, bilinear upsampling, argmax; mIoU over "
                        "classes present"}
    one_hot = F.one_hot(labels.masked_fill(~valid, 0), n).permute(0, 3, 1, 2).float()
    for stride in (1, 2, 4, 8):
        scores = F.interpolate(F.avg_pool2d(one_hot, stride, ceil_mode=True), size=labels.shape[-2:],
                               mode="bilinear", align_corners=False)
        pred = scores.argmax(1)
        confmat = torch.bincount(labels[valid] * n + pred[valid], minlength=n * n).reshape(n, n).double()
        tp = confmat.diagonal()
        union = confmat.sum(0) + confmat.sum(1) - tp
        iou = tp / union.clamp_min(1)
        result[f"stride_{stride}"] = {"miou": round(float(iou[union > 0].mean()), 4),
                                      "iou": {c.name: round(float(v), 3) for c, v in zip(dataset.classes, iou,
                                                                                         strict=True)}}
    return result


def evaluate(args: argparse.Namespace) -> dict:
    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.datasets import SemanticDataset
    from sdn3d.semantic import SemanticPredictor

    dataset = SemanticDataset.from_source(synth_data_source(args.root, args.size), args.part)
    predictor = SemanticPredictor.from_checkpoint(args.ckpt, map_location=args.device,
                                                  image_size=tuple(args.work_size) if args.work_size else None,
                                                  flip=args.flip)
    n = len(predictor.classes)
    confmat = torch.zeros(n, n, dtype=torch.float64)
    t0 = time.perf_counter()
    for start in range(0, len(dataset), args.batch):
        items = [dataset[i] for i in range(start, min(start + args.batch, len(dataset)))]
        image = torch.stack([it["image"] for it in items])
        label = torch.stack([it["label"] for it in items])
        pred = predictor(image).probability.argmax(1).cpu()
        valid = label != 255
        confmat += torch.bincount(label[valid] * n + pred[valid], minlength=n * n).reshape(n, n).double()
    tp = confmat.diagonal()
    union = confmat.sum(0) + confmat.sum(1) - tp
    iou = tp / union.clamp_min(1)
    return {"checkpoint": str(args.ckpt), "size": list(args.size), "work_size": args.work_size, "part": args.part,
            "flip": args.flip,
            "images": len(dataset), "seconds": round(time.perf_counter() - t0, 1),
            "miou": round(float(iou[union > 0].mean()), 4), "pixel_acc": round(float(tp.sum() / confmat.sum()), 4),
            "iou": {c.name: round(float(v), 4) for c, v, u in zip(predictor.classes, iou, union, strict=True) if u > 0}}


class _InMemory(torch.utils.data.Dataset):
    """A dataset's items decoded once (the synthetic split is a few tens of MB at the working size)."""

    def __init__(self, dataset: torch.utils.data.Dataset) -> None:
        self.items = [dataset[i] for i in range(len(dataset))]

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, i: int) -> dict:
        return self.items[i]


def train(args: argparse.Namespace) -> dict:
    import lightning as L
    from lightning.pytorch.callbacks import Callback, ModelCheckpoint
    from lightning.pytorch.loggers import TensorBoardLogger
    from omegaconf import OmegaConf

    from datamodules import SemanticDataModule
    from lightning_modules.semantic import SemanticModule

    class TrainTimer(Callback):
        def __init__(self) -> None:
            self.seconds, self.images, self._t = 0.0, 0, 0.0

        def on_train_batch_start(self, trainer, pl_module, batch, batch_idx) -> None:
            self._t = time.perf_counter()

        def on_train_batch_end(self, trainer, pl_module, outputs, batch, batch_idx) -> None:
            if pl_module.device.type == "cuda":
                torch.cuda.synchronize()
            self.seconds += time.perf_counter() - self._t
            self.images += int(batch["image"].shape[0])

    class ValCurve(Callback):
        """``(epoch, val/miou)`` after every validation: how fast the run learns."""

        def __init__(self) -> None:
            self.points: list[tuple[int, float]] = []

        # on_validation_end, not on_validation_epoch_end: callbacks' epoch-end hooks run before the module's,
        # which is where val/miou is computed, so they would read the previous validation's value.
        def on_validation_end(self, trainer, pl_module) -> None:
            if not trainer.sanity_checking and "val/miou" in trainer.callback_metrics:
                self.points.append((trainer.current_epoch + 1, round(float(trainer.callback_metrics["val/miou"]), 4)))

    preset_model: dict = {}
    if args.preset:
        presets = {p.stem.removeprefix("semantic_"): OmegaConf.load(p)
                   for p in (REPO / "conf" / "recipe").glob("semantic_*.yaml")}
        presets = {name: recipe for name, recipe in presets.items() if "defaults" not in recipe}  # plain recipes
        if args.preset not in presets:
            raise SystemExit(f"--preset {args.preset!r} is not a conf/recipe/semantic_NAME.yaml "
                             f"({sorted(presets)})")
        preset = OmegaConf.to_container(presets[args.preset], resolve=True)
        preset_model = dict(preset.get("model", {}))
        given = set(args.given)
        if "size" not in given and "image_size" in preset.get("data", {}):
            args.size = list(preset["data"]["image_size"])
        if "epochs" not in given and "max_epochs" in preset.get("trainer", {}):
            args.epochs = int(preset["trainer"]["max_epochs"])
        if "batch" not in given and "batch_size" in preset.get("datamodule", {}):
            args.batch = int(preset["datamodule"]["batch_size"])
        if "val_every" not in given and "check_val_every_n_epoch" in preset.get("trainer", {}):
            args.val_every = int(preset["trainer"]["check_val_every_n_epoch"])
        if "lr" in given:
            preset_model["lr"] = args.lr
        args.lr = float(preset_model.pop("lr", args.lr))
        crop = preset_model.pop("crop_size", args.crop)
        args.crop = args.crop if "crop" in given else crop
    if isinstance(args.crop, list):
        if len(args.crop) not in (1, 2):
            raise SystemExit(f"--crop takes a square side or W H, got {args.crop}")
        args.crop = args.crop[0] if len(args.crop) == 1 else list(args.crop)
    L.seed_everything(args.seed, workers=True)
    data = OmegaConf.load(REPO / "conf" / "data" / "synth.yaml")
    data.root = str(args.root)
    dm = SemanticDataModule(data, image_size=tuple(args.size), batch_size=args.batch, seed=args.seed)
    t0 = time.perf_counter()
    dm.setup("fit")
    dm.setup("test")
    dm.datasets = {part: _InMemory(ds) for part, ds in dm.datasets.items()}
    load_s = time.perf_counter() - t0
    extra = {**preset_model, **{k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}}
    model = SemanticModule(classes="vkitti", lr=args.lr, crop_size=args.crop, **extra)
    out = Path(args.out)
    timer, curve = TrainTimer(), ValCurve()
    ckpt = ModelCheckpoint(dirpath=out / "checkpoints", monitor="val/miou", mode="max", save_last=True)
    cuda = args.device == "cuda"
    trainer = L.Trainer(accelerator="gpu" if cuda else "cpu", devices=1, precision=args.precision,
                        max_epochs=args.epochs, logger=TensorBoardLogger(out, "tb"),
                        callbacks=[timer, curve, ckpt], enable_progress_bar=False, log_every_n_steps=10,
                        check_val_every_n_epoch=args.val_every, num_sanity_val_steps=0,
                        max_time={"minutes": args.max_minutes} if args.max_minutes else None)
    t0 = time.perf_counter()
    trainer.fit(model, datamodule=dm)
    fit_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    test = trainer.test(model, datamodule=dm, ckpt_path="last", verbose=False)[0]
    test_s = time.perf_counter() - t0
    return {
        "preset": args.preset, "size": list(args.size), "epochs": args.epochs, "batch": args.batch, "lr": args.lr,
        "crop": args.crop,
        "threads": torch.get_num_threads(), "device": args.device, "precision": args.precision,
        "gpu": torch.cuda.get_device_name() if cuda else None, "extra": extra,
        "train_images": len(dm.datasets["train"]),
        "test_images": len(dm.datasets["test"]), "data_load_s": round(load_s, 1), "fit_wall_s": round(fit_s, 1),
        "train_batches_s": round(timer.seconds, 1), "train_images_seen": timer.images,
        "train_images_per_s": round(timer.images / max(timer.seconds, 1e-9), 3), "test_wall_s": round(test_s, 1),
        "global_step": trainer.global_step, "epochs_done": trainer.current_epoch,
        "checkpoint": str(ckpt.last_model_path), "val_miou_by_epoch": curve.points,
        "test": {k: round(float(v), 4) for k, v in sorted(test.items())},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="mode", required=True)
    for name in ("speed", "train", "ceiling", "evaluate"):
        p = sub.add_parser(name)
        p.add_argument("--size", type=int, nargs=2, default=[312, 96], metavar=("W", "H"))
        p.add_argument("--batch", type=int, default=8)
        p.add_argument("--threads", type=int, default=2)
        p.add_argument("--seed", type=int, default=0)
        p.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    sp = sub.choices["speed"]
    sp.add_argument("--repeats", type=int, default=5)
    sp.add_argument("--arch", default="drn_d_22")
    sp.add_argument("--decoder", default="bilinear", choices=["bilinear", "skip"])
    sp.add_argument("--channels", type=int, nargs=8, default=None)
    cp = sub.choices["ceiling"]
    cp.add_argument("--root", default="/work/data/synth")
    cp.add_argument("--part", default="test", choices=["train", "val", "test"])
    ep = sub.choices["evaluate"]
    ep.add_argument("--ckpt", required=True)
    ep.add_argument("--root", default="/work/data/synth")
    ep.add_argument("--part", default="test", choices=["train", "val", "test"])
    ep.add_argument("--work-size", type=int, nargs=2, default=None, metavar=("W", "H"))
    ep.add_argument("--flip", action="store_true", help="flip test-time augmentation (image + mirror, averaged)")
    tp = sub.choices["train"]
    tp.add_argument("--root", default="/work/data/synth")
    tp.add_argument("--epochs", type=int, default=10)
    tp.add_argument("--lr", type=float, default=0.01)
    tp.add_argument("--crop", type=int, nargs="+", default=None, metavar="SIDE | W H",
                    help="training crop: a square side or W H (clamped to the image)")
    tp.add_argument("--val-every", type=int, default=5)
    tp.add_argument("--precision", default="32-true", help="Lightning precision (cuda: 16-mixed / bf16-mixed)")
    tp.add_argument("--max-minutes", type=float, default=None, help="stop fitting after this long (then test)")
    tp.add_argument("--out", default=str(REPO / "outputs" / "bench" / "semantic"))
    tp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    tp.add_argument("--preset", default=None, help="conf/recipe/semantic_NAME.yaml (e.g. cpu)")
    argv = sys.argv[1:]
    args = parser.parse_args(argv)
    # Which options were typed (a preset must not override them).
    args.given = [a[2:].split("=", 1)[0].replace("-", "_") for a in argv if a.startswith("--")]
    torch.set_num_threads(args.threads)
    result = {"speed": speed, "train": train, "ceiling": ceiling, "evaluate": evaluate}[args.mode](args)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
