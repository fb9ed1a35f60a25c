"""Geometric-branch training throughput, with and without L_reproj, side by side; prints JSON.

    python benchmarks/geometric.py [--root /work/data/synth] [--batch-size 32] [--crop-size 64]
                                   [--num-samples 4] [--steps 10] [--threads 2] [--device cpu|cuda]

Both variants run ``GeometricModule.training_step`` + backward + Adam step on the same preloaded
batches (data loading is not timed): ``pred`` is stage 1 (L_pred only), ``joint`` is stage 2
(L_pred + 0.1 L_reproj + REINFORCE with ``--num-samples`` rendered templates per object + FFD
term). Steps alternate between the two variants (A B A B ...) so that load from other processes
on a shared machine affects both alike. Reported per variant: objects per second of wall time
(median step; the minimum step time is given too, as the CPU may be shared) and per second of
process CPU time (summed over threads); and the time of the joint step's soft silhouettes alone
(forward + backward of one batch's renders, timed once) and its share of the median joint step.
Without ``--root`` (or when it has no data) random crops with plausible boxes and targets are used.
The (untrained) nets' attribute heads are set to predict the mean targets (``_plausible_heads``),
so the renderer sees car-sized silhouettes as after stage 1; the template distribution is uniform
(the most distinct (object, template) pairs to render: the slowest case).
"""

from __future__ import annotations

import argparse
import json
import logging
import statistics
import time
import warnings
from pathlib import Path

import torch

from lightning_modules.geometric import GeometricModule


def _batches(root: str | None, batch_size: int, crop_size: int, count: int) -> list[dict]:
    if root and (Path(root) / "vkitti_1.3.1_motgt").is_dir():
        from datamodules import GeometricDataModule

        dm = GeometricDataModule({"kind": "vkitti1", "root": root, "image_size": [624, 192]},
                                 batch_size=batch_size, crop_size=crop_size)
        loader = dm.train_dataloader()
        out = []
        for batch in loader:
            if batch["crop"].shape[0] == batch_size:
                out.append(batch)
            if len(out) == count:
                return out
    from sdn3d.math3d.camera import VKITTI_INTRINSICS
    from sdn3d.math3d.encodings import AttributeEncoding
    from sdn3d.math3d.transforms import project_box

    intr = VKITTI_INTRINSICS.resized(624, 192)
    K = intr.matrix()
    out = []
    g = torch.Generator().manual_seed(0)
    for _ in range(count):
        n = batch_size
        dims = torch.tensor([4.2, 1.6, 1.8]) * (0.8 + 0.4 * torch.rand(n, 3, generator=g))
        ry = (torch.rand(n, generator=g) * 2 - 1) * torch.pi
        center = torch.stack([torch.rand(n, generator=g) * 8 - 4, torch.full((n,), 0.8),
                              8 + 20 * torch.rand(n, generator=g)], 1)
        box = project_box(dims, ry, center, K)
        side = (box[:, 2:] - box[:, :2]).amax(1) * 1.2
        left, top = (box[:, 0] + box[:, 2] - side) / 2, (box[:, 1] + box[:, 3] - side) / 2
        s = crop_size / side
        vec = torch.tensor([intr.fx, intr.fy, intr.cx, intr.cy]).expand(n, 4)
        crop_intr = torch.stack([vec[:, 0] * s, vec[:, 1] * s, (vec[:, 2] - left + 0.5) * s - 0.5,
                                 (vec[:, 3] - top + 0.5) * s - 0.5], 1)
        mask = torch.zeros(n, 1, crop_size, crop_size)
        q = crop_size // 5
        mask[..., q:-q, q // 2:-q // 2] = 1.0
        out.append({
            "crop": torch.rand(n, 3, crop_size, crop_size) * mask, "mask": mask, "ignore": torch.zeros_like(mask),
            "box": box, "intrinsics": vec.clone(), "crop_intrinsics": crop_intr,
            "crop_box": torch.stack([left, top, left + side, top + side], 1),
            "targets": AttributeEncoding().encode(dims, ry, center, box, K), "template_id": torch.zeros(n).long(),
        })
    return out


@torch.no_grad()
def _plausible_heads(module: GeometricModule, batches: list[dict]) -> None:
    """Make an untrained net predict car-like poses: the mean targets, yaw varying with the features.

    A random head puts objects at arbitrary distances (huge or tiny silhouettes), which would time
    the renderer on inputs training never sees after stage 1.
    """
    heads = module.net.heads
    for key, target in (("log_scale", "log_scale"), ("offset", "offset"), ("log_distance", "log_distance")):
        mean = torch.cat([b["targets"][target] for b in batches]).mean(0)
        heads[key].weight.zero_()
        heads[key].bias.copy_(mean)


def _to(batch: dict, device: torch.device) -> dict:
    return {k: (_to(v, device) if isinstance(v, dict) else v.to(device) if torch.is_tensor(v) else v)
            for k, v in batch.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default="/work/data/synth")
    parser.add_argument("--batch-size", type=int, default=32)
    parser.add_argument("--crop-size", type=int, default=64)
    parser.add_argument("--num-samples", type=int, default=4)
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--device", default="cpu")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    logging.getLogger("sdn3d.nets.weights").setLevel(logging.ERROR)
    warnings.filterwarnings("ignore", message=".*self.log.*")  # no Trainer: logging is skipped
    device = torch.device(args.device)
    batches = [_to(b, device) for b in _batches(args.root, args.batch_size, args.crop_size, 4)]
    common = dict(num_samples=args.num_samples, image_size=(624, 192))
    variants = {
        "pred": GeometricModule(pred_epochs=10**6, **common).to(device),  # epoch 0 is stage 1
        "joint": GeometricModule(pred_epochs=0, **common).to(device),  # epoch 0 is stage 2
    }
    for module in variants.values():
        _plausible_heads(module, batches)
    optimizers = {k: torch.optim.Adam(m.parameters(), lr=1e-4) for k, m in variants.items()}
    wall: dict[str, list[float]] = {k: [] for k in variants}
    cpu: dict[str, list[float]] = {k: [] for k in variants}

    def step(name: str, i: int) -> None:
        module, opt = variants[name], optimizers[name]
        opt.zero_grad(set_to_none=True)
        loss = module.training_step(batches[i % len(batches)], i)
        loss.backward()
        opt.step()

    for name in variants:  # warm-up
        for i in range(2):
            step(name, i)
    for i in range(args.steps):
        for name in variants:
            if device.type == "cuda":
                torch.cuda.synchronize()
            t0, c0 = time.perf_counter(), time.process_time()
            step(name, i)
            if device.type == "cuda":
                torch.cuda.synchronize()
            wall[name].append(time.perf_counter() - t0)
            cpu[name].append(time.process_time() - c0)

    # Renderer share of a joint step: one forward + backward of the silhouettes alone.
    joint = variants["joint"]
    batch = batches[0]
    with torch.no_grad():
        raw = joint.net(batch["crop"], batch["box"], batch["intrinsics"])
    from sdn3d.geometric.decode import decode_outputs

    pred = decode_outputs(raw, batch["box"], batch["intrinsics"])
    pred = {k: v.detach().requires_grad_(v.is_floating_point()) for k, v in pred.items()}
    objects = torch.arange(args.batch_size, device=device).repeat_interleave(args.num_samples)
    ids = torch.randint(0, 8, objects.shape, device=device)
    t0 = time.perf_counter()
    sil = joint._render(pred, objects, ids, batch["crop_intrinsics"], args.crop_size)
    sil.sum().backward()
    render_s = time.perf_counter() - t0

    n = args.batch_size
    result = {
        "device": str(device), "threads": args.threads, "batch_size": n, "crop_size": args.crop_size,
        "num_samples": args.num_samples, "steps": args.steps,
        "data": "synth" if args.root and (Path(args.root) / "vkitti_1.3.1_motgt").is_dir() else "random",
    }
    for name in variants:
        med_wall, med_cpu = statistics.median(wall[name]), statistics.median(cpu[name])
        result[name] = {"objects_per_s_wall": round(n / med_wall, 2), "objects_per_cpu_s": round(n / med_cpu, 2),
                        "step_s_median": round(med_wall, 4), "step_s_min": round(min(wall[name]), 4)}
    result["joint_over_pred_wall"] = round(result["joint"]["step_s_median"] / result["pred"]["step_s_median"], 2)
    result["render_s_per_joint_step"] = round(render_s, 4)
    result["render_share_of_joint_step"] = round(render_s / result["joint"]["step_s_median"], 2)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
