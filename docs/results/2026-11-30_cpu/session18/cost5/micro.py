"""Each cut's primitive, this branch's formulation against main's, on the photo path's sizes (threads 1): roty on one
and on seven angles (float64); the 8-bit levels' linear RGB of a whole 1242x375 picture and of a 700x200 box
(OpenCV's LUT against np.take); a whole picture's bool mask tested (any, any over rows and columns, count, flat
indices, rows and columns of its set pixels, at 0.1 %, 5 % and 30 % set); the channels' mean of a channel-last
picture. The two formulations alternate call by call; the least of ROUNDS wall times each is kept, and their
outputs are checked equal (bit for bit, the same dtype and shape).

    python micro.py [ROUNDS]
"""

import sys
import time

import numpy as np
import torch

from sdn3d.editing.photo.road import _LINEAR_LEVELS, _linear_of_levels
from sdn3d.image_ops import any_along, any_set, count_set, flat_nonzero, nonzero_yx
from sdn3d.math3d.rotations import _axis_angle_to_rotation_matrix, roty
from sdn3d.math3d.sums import sum3

torch.set_num_threads(1)
ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 30
gen = torch.Generator().manual_seed(0)


def kornia_roty(ry: torch.Tensor) -> torch.Tensor:
    flat = ry.reshape(-1)
    zeros = torch.zeros_like(flat)
    return _axis_angle_to_rotation_matrix(torch.stack([zeros, flat, zeros], -1)).reshape(*ry.shape, 3, 3)


def same(a, b) -> bool:
    if isinstance(a, tuple):
        return all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, torch.Tensor):
        return a.dtype == b.dtype and a.shape == b.shape and bool((a == b).all())
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and bool((a.view(np.uint8) == b.view(np.uint8)).all())
    return a == b


def compare(name: str, new, old) -> None:
    best_new = best_old = float("inf")
    for _ in range(ROUNDS):
        t = time.perf_counter()
        a = new()
        best_new = min(best_new, time.perf_counter() - t)
        t = time.perf_counter()
        b = old()
        best_old = min(best_old, time.perf_counter() - t)
    assert same(a, b), name
    print(f"| {name} | {1e3 * best_new:.3f} | {1e3 * best_old:.3f} | {best_new / best_old:.2f} |")


print("| primitive | this branch ms | main ms | ratio |\n|---|---|---|---|")
for n in (1, 7):
    ry = torch.rand(n, generator=gen, dtype=torch.float64) * 6 - 3
    compare(f"roty of {n} angle(s), float64", lambda ry=ry: roty(ry), lambda ry=ry: kornia_roty(ry))
levels = torch.randint(256, (3, 375, 1242), generator=gen, dtype=torch.uint8).numpy()
box = levels[:, 100:300, 200:900].reshape(3, -1)
for name, values in (("whole picture", levels.reshape(3, -1)), ("700x200 box", box)):
    compare(f"linear RGB of 8-bit levels, {name}", lambda v=values: _linear_of_levels(v),
            lambda v=values: np.take(_LINEAR_LEVELS, v))
for share in (0.001, 0.05, 0.3):
    mask = torch.rand(375, 1242, generator=gen) < share
    compare(f"any, {share:.1%} set", lambda m=mask: any_set(m), lambda m=mask: bool(m.any()))
    compare(f"any over rows (dim 1), {share:.1%} set", lambda m=mask: any_along(m, 1), lambda m=mask: m.any(1))
    compare(f"count, {share:.1%} set", lambda m=mask: count_set(m), lambda m=mask: int(m.sum()))
    compare(f"flat indices, {share:.1%} set", lambda m=mask: flat_nonzero(m),
            lambda m=mask: m.reshape(-1).nonzero().flatten())
    compare(f"rows and columns, {share:.1%} set", lambda m=mask: nonzero_yx(m), lambda m=mask: m.nonzero(as_tuple=True))
picture = torch.randn(375, 1242, 3, generator=gen).permute(2, 0, 1)
compare("channels' mean, channel-last 1242x375", lambda: sum3(picture, 0) / 3, lambda: picture.mean(0))
