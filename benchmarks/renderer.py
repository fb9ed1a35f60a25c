"""Renderer benchmark: soft silhouette (sparse vs dense) and the hard rasterizer; prints JSON.

    python benchmarks/renderer.py [--device cpu|cuda] [--repeats N] [--sigma S] [--sweep S ...]

Soft silhouette: 32 car-like objects (icosphere, 1280 faces each, random size / yaw / place),
each rendered into its own 64x64 crop: the crop intrinsics map the object's projected 2D box
(10 % margin) onto the crop, anisotropically, like the geometric branch's ROI crops. Timed:
forward + backward (``(silhouette * w).sum()``) w.r.t. the vertices. The dense reference
would need gigabytes for the full batch, so it is timed on a slice of meshes and scaled
linearly (said in the JSON). Peak memory: ``torch.cuda.max_memory_allocated`` on CUDA; on
CPU the growth of the peak RSS of a fresh subprocess over one call (Linux ``VmHWM`` after
resetting it, else ``ru_maxrss``). ``--sweep`` also times other sigmas (the work grows with
the culling radius). The targets are checked at ``--sigma`` (default: the settings' default).

Hard rasterizer: a 624x192 Virtual KITTI frame with 12 vehicles (1280 faces) standing on the
ground plane y = 1.65 m at z = 6..40 m, plus the ground plane (2 triangles).
Times are medians over ``--repeats`` after two warm-up calls; the minimum is given too since
the CPU may be shared.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import time

import torch
import trimesh

from sdn3d.math3d import VKITTI_INTRINSICS, object_to_camera, project_points
from sdn3d.render import (
    RasterSettings,
    SoftSilhouetteSettings,
    rasterize_meshes,
    soft_silhouette,
    soft_silhouette_dense,
)

FRAME = VKITTI_INTRINSICS.resized(624, 192)
CAMERA_HEIGHT = 1.65
TARGETS = {"soft_speedup_min": 100.0, "soft_seconds_max": 0.1, "hard_seconds_max": 0.2}


def car_meshes(
    count: int, generator: torch.Generator, device: torch.device, z: torch.Tensor | None = None
) -> tuple[torch.Tensor, torch.Tensor]:
    """``count`` car-sized icospheres (1280 faces) on the ground at depths ``z`` (default random 6..40 m)."""
    sphere = trimesh.creation.icosphere(subdivisions=3)
    canonical = torch.tensor(sphere.vertices, dtype=torch.float32) * 0.5  # inscribed in the unit box
    faces = torch.tensor(sphere.faces, dtype=torch.long)
    scale = 0.8 + 0.4 * torch.rand(count, 1, generator=generator)
    dims = torch.tensor([4.0, 1.5, 1.8]) * scale  # (l, h, w)
    if z is None:
        z = 6.0 + 34.0 * torch.rand(count, generator=generator)
    x = (torch.rand(count, generator=generator) - 0.5) * 0.6 * z
    ry = (torch.rand(count, generator=generator) * 2.0 - 1.0) * math.pi
    center = torch.stack([x, CAMERA_HEIGHT - dims[:, 1] / 2, z], 1)
    verts = object_to_camera(canonical.expand(count, -1, -1), dims, ry, center)
    return verts.to(device), faces.to(device)


def crop_intrinsics(verts: torch.Tensor, size: int, margin: float = 0.1) -> torch.Tensor:
    """``(N, 3, 3)`` intrinsics mapping each object's projected 2D box (plus margin) onto a crop."""
    K = FRAME.matrix(device=verts.device)
    uv = project_points(verts, K)
    lo, hi = uv.amin(1), uv.amax(1)
    pad = (hi - lo) * margin
    lo, hi = lo - pad, hi + pad
    scale = size / (hi - lo)  # pixels of the crop per pixel of the frame, per axis
    out = torch.zeros(verts.shape[0], 3, 3, device=verts.device)
    out[:, 0, 0] = K[0, 0] * scale[:, 0]
    out[:, 1, 1] = K[1, 1] * scale[:, 1]
    # Crop edge ``lo - 0.5`` maps to ``-0.5`` (pixel-centre convention).
    out[:, 0, 2] = (K[0, 2] - lo[:, 0] + 0.5) * scale[:, 0] - 0.5
    out[:, 1, 2] = (K[1, 2] - lo[:, 1] + 0.5) * scale[:, 1] - 0.5
    out[:, 2, 2] = 1.0
    return out


def hard_scene(device: torch.device) -> tuple[torch.Tensor, ...]:
    generator = torch.Generator().manual_seed(1)
    count = 12
    verts, faces = car_meshes(count, generator, device, z=torch.linspace(6.0, 40.0, count))
    ground = torch.tensor(
        [
            [-60.0, CAMERA_HEIGHT, 1.0],
            [60.0, CAMERA_HEIGHT, 1.0],
            [60.0, CAMERA_HEIGHT, 300.0],
            [-60.0, CAMERA_HEIGHT, 300.0],
        ],
        device=device,
    )
    all_verts = torch.zeros(count + 1, verts.shape[1], 3, device=device)
    all_verts[:count], all_verts[count, :4] = verts, ground
    all_faces = torch.zeros(count + 1, faces.shape[0], 3, dtype=torch.long, device=device)
    all_faces[:count], all_faces[count, :2] = faces, torch.tensor([[0, 1, 2], [0, 2, 3]], device=device)
    return (
        all_verts,
        all_faces,
        FRAME.matrix(device=device),
        torch.zeros(count + 1, dtype=torch.long, device=device),
    )


def soft_inputs(device: torch.device, count: int = 32, size: int = 64) -> tuple[torch.Tensor, ...]:
    verts, faces = car_meshes(count, torch.Generator().manual_seed(0), device)
    weight = torch.rand(count, size, size, generator=torch.Generator().manual_seed(2)).to(device)
    return verts, faces, crop_intrinsics(verts, size), weight


def sync(device: torch.device) -> None:
    if device.type == "cuda":
        torch.cuda.synchronize(device)


def time_call(fn, repeats: int, device: torch.device, warmup: int = 2) -> list[float]:
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        sync(device)
        start = time.perf_counter()
        fn()
        sync(device)
        times.append(time.perf_counter() - start)
    return times


def soft_step(render, verts, faces, K, weight, settings) -> None:
    v = verts.detach().requires_grad_(True)
    (render(v, faces, K, settings) * weight).sum().backward()


def peak_memory_bytes(device: torch.device, settings: SoftSilhouetteSettings, dense_slice: int | None) -> int:
    """Peak memory of one forward + backward (dense on a slice when ``dense_slice`` is given)."""
    verts, faces, K, weight = soft_inputs(device)
    render = soft_silhouette if dense_slice is None else soft_silhouette_dense
    if dense_slice is not None:
        verts, K, weight = verts[:dense_slice], K[:dense_slice], weight[:dense_slice]
    if device.type == "cuda":
        soft_step(render, verts, faces, K, weight, settings)
        torch.cuda.reset_peak_memory_stats(device)
        base = torch.cuda.memory_allocated(device)
        soft_step(render, verts, faces, K, weight, settings)
        return torch.cuda.max_memory_allocated(device) - base
    # Peak RSS during the call minus the RSS just before it, in a fresh process (imports and
    # inputs excluded). Linux: VmHWM, reset to the current RSS first via clear_refs; elsewhere
    # ru_maxrss (which a child inherits from its parent across exec).
    base = _reset_peak_rss()
    soft_step(render, verts, faces, K, weight, settings)
    return max(_peak_rss() - base, 0)


def _proc_status_kib(field: str) -> int | None:
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def _ru_maxrss_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * (1 if sys.platform == "darwin" else 1024)


def _reset_peak_rss() -> int:
    """Reset the peak-RSS mark where possible; return the current RSS in bytes."""
    try:
        with open("/proc/self/clear_refs", "w") as clear:
            clear.write("5")
    except OSError:
        pass
    current = _proc_status_kib("VmRSS")
    return current * 1024 if current is not None else _ru_maxrss_bytes()


def _peak_rss() -> int:
    peak = _proc_status_kib("VmHWM")
    return peak * 1024 if peak is not None else _ru_maxrss_bytes()


def probe_memory(args: argparse.Namespace, dense_slice: int | None) -> int | None:
    if args.device == "cuda":
        return peak_memory_bytes(
            torch.device("cuda"), SoftSilhouetteSettings((64, 64), sigma=args.sigma), dense_slice
        )
    cmd = [
        sys.executable,
        __file__,
        "--device",
        "cpu",
        "--sigma",
        str(args.sigma),
        "--_memory-probe",
        "dense" if dense_slice else "sparse",
        "--dense-slice",
        str(args.dense_slice),
    ]
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    return int(done.stdout.strip()) if done.returncode == 0 else None


def stats(times: list[float], scale: float = 1.0) -> dict[str, float]:
    return {"median_s": statistics.median(times) * scale, "min_s": min(times) * scale}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--sigma", type=float, default=SoftSilhouetteSettings((64, 64)).sigma)
    parser.add_argument("--dense-slice", type=int, default=2, help="meshes the dense reference is timed on")
    parser.add_argument(
        "--sweep", type=float, nargs="*", default=[0.1, 0.5, 1.0], help="extra sigmas to time"
    )
    parser.add_argument(
        "--_memory-probe", dest="memory_probe", choices=["sparse", "dense"], help=argparse.SUPPRESS
    )
    args = parser.parse_args()
    device = torch.device(args.device)
    settings = SoftSilhouetteSettings(image_size=(64, 64), sigma=args.sigma)
    if args.memory_probe:
        dense = args.dense_slice if args.memory_probe == "dense" else None
        print(peak_memory_bytes(device, settings, dense))
        return

    verts, faces, K, weight = soft_inputs(device)
    count = verts.shape[0]
    sparse_times = time_call(
        lambda: soft_step(soft_silhouette, verts, faces, K, weight, settings), args.repeats, device
    )
    k = min(args.dense_slice, count)
    dense_times = time_call(
        lambda: soft_step(soft_silhouette_dense, verts[:k], faces, K[:k], weight[:k], settings),
        max(1, min(args.repeats, 3)),
        device,
        warmup=1,
    )
    with torch.no_grad():
        error = (
            (
                soft_silhouette(verts[:k], faces, K[:k], settings)
                - soft_silhouette_dense(verts[:k], faces, K[:k], settings)
            )
            .abs()
            .max()
            .item()
        )
    sweep = {}
    for sigma in args.sweep:
        swept = SoftSilhouetteSettings(image_size=(64, 64), sigma=sigma)
        times = time_call(
            lambda s=swept: soft_step(soft_silhouette, verts, faces, K, weight, s), args.repeats, device
        )
        sweep[str(sigma)] = stats(times)
    soft = stats(sparse_times)
    dense = stats(dense_times, scale=count / k)
    speedup = dense["median_s"] / soft["median_s"]

    h_verts, h_faces, h_K, image = hard_scene(device)
    raster = RasterSettings(image_size=(FRAME.height, FRAME.width))
    hard_times = time_call(
        lambda: rasterize_meshes(h_verts, h_faces, h_K, raster, image, 1), args.repeats, device
    )
    frags = rasterize_meshes(h_verts, h_faces, h_K, raster, image, 1)
    hard = stats(hard_times)

    report = {
        "device": str(device) if device.type == "cpu" else torch.cuda.get_device_name(device),
        "threads": torch.get_num_threads(),
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "torch": torch.__version__,
        "repeats": args.repeats,
        "soft_silhouette": {
            "meshes": count,
            "faces_per_mesh": int(faces.shape[0]),
            "image_size": [64, 64],
            "sigma_px2": settings.sigma,
            "cull_eps": settings.cull_eps,
            "cull_radius_px": settings.cull_radius,
            "forward_backward": soft,
            "peak_memory_bytes": probe_memory(args, None),
            "dense_reference": {
                **dense,
                "timed_on_meshes": k,
                "scaled_linearly_to": count,
                "peak_memory_bytes_on_slice": probe_memory(args, k),
            },
            "speedup_vs_dense": speedup,
            "max_abs_diff_vs_dense_on_slice": error,
            "forward_backward_by_sigma_px2": sweep,
        },
        "hard_rasterizer": {
            "image_size": [FRAME.height, FRAME.width],
            "vehicles": 12,
            "faces_per_vehicle": int(faces.shape[0]),
            "ground_triangles": 2,
            "covered_fraction": frags.mask.float().mean().item(),
            "per_frame": hard,
        },
        "targets": {
            **TARGETS,
            "soft_speedup_pass": speedup >= TARGETS["soft_speedup_min"],
            "soft_seconds_pass": soft["median_s"] < TARGETS["soft_seconds_max"],
            "hard_seconds_pass": hard["median_s"] < TARGETS["hard_seconds_max"],
        },
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
