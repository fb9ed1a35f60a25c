"""Semantic branch benchmark: DRN speed (forward / training step) and a timed training run; prints JSON.

    python benchmarks/semantic.py speed [--size W H] [--batch B] [--threads T] [--repeats N] [--arch drn_d_22]
        [--device cpu|cuda]
    python benchmarks/semantic.py train --root /work/data/synth [--size W H] [--epochs E] [--batch B]
        [--lr LR] [--crop C] [--threads T] [--out DIR] [--set key=value ...] [--device cpu|cuda]
        [--precision 32-true|16-mixed|bf16-mixed]

``speed``: images/s of ``DRNSeg`` (with the instance head) for inference (eval, no grad) and
for a training step (forward, loss, backward, SGD step) on random images; medians over
``--repeats`` after one warm-up call (the minimum too, the CPU may be shared).

``train``: ``SemanticModule`` + ``SemanticDataModule`` on a ``conf/data/synth.yaml`` dataset
(frames decoded once and kept in memory, so the timing is the network's), ``lightning.Trainer``
on the CPU, then a test on the test split. Reports the test metrics (mIoU, per-class IoU,
thing-class PQ), the fit wall time (validation included) and the training images/s (time
inside training batches only). ``--max-minutes`` stops fitting early (Trainer ``max_time``; the poly
schedule still assumes ``--epochs``). ``--device cuda`` runs the same on one GPU (``--precision``
defaults to 32-true, the CPU run's arithmetic; CUDA timings synchronize before the clock stops).
``--set`` passes other ``SemanticModule`` arguments
(e.g. ``--set center_sigma=3``). Checkpoints and TensorBoard logs go under ``--out``.
"""

from __future__ import annotations

import argparse
import json
import statistics
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
    net = DRNSeg(14, arch=args.arch).to(device, memory_format=torch.channels_last)
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

    result = {"arch": args.arch, "size": [w, h], "batch": args.batch, "threads": torch.get_num_threads(),
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

        def on_validation_epoch_end(self, trainer, pl_module) -> None:
            if not trainer.sanity_checking and "val/miou" in trainer.callback_metrics:
                self.points.append((trainer.current_epoch + 1, round(float(trainer.callback_metrics["val/miou"]), 4)))

    L.seed_everything(args.seed, workers=True)
    data = OmegaConf.load(REPO / "conf" / "data" / "synth.yaml")
    data.root = str(args.root)
    dm = SemanticDataModule(data, image_size=tuple(args.size), batch_size=args.batch, seed=args.seed)
    t0 = time.perf_counter()
    dm.setup("fit")
    dm.setup("test")
    dm.datasets = {part: _InMemory(ds) for part, ds in dm.datasets.items()}
    load_s = time.perf_counter() - t0
    extra = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
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
        "size": list(args.size), "epochs": args.epochs, "batch": args.batch, "lr": args.lr, "crop": args.crop,
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
    for name in ("speed", "train"):
        p = sub.add_parser(name)
        p.add_argument("--size", type=int, nargs=2, default=[312, 96], metavar=("W", "H"))
        p.add_argument("--batch", type=int, default=8)
        p.add_argument("--threads", type=int, default=2)
        p.add_argument("--seed", type=int, default=0)
        p.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    sp = sub.choices["speed"]
    sp.add_argument("--repeats", type=int, default=5)
    sp.add_argument("--arch", default="drn_d_22")
    tp = sub.choices["train"]
    tp.add_argument("--root", default="/work/data/synth")
    tp.add_argument("--epochs", type=int, default=10)
    tp.add_argument("--lr", type=float, default=0.01)
    tp.add_argument("--crop", type=int, default=None)
    tp.add_argument("--val-every", type=int, default=5)
    tp.add_argument("--precision", default="32-true", help="Lightning precision (cuda: 16-mixed / bf16-mixed)")
    tp.add_argument("--max-minutes", type=float, default=None, help="stop fitting after this long (then test)")
    tp.add_argument("--out", default=str(REPO / "outputs" / "bench" / "semantic"))
    tp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    result = speed(args) if args.mode == "speed" else train(args)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
