"""Capture every soft-raster kernel call of one ``sdn3d-edit`` call, then time them again alone.

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=CODE/src SDN3D_CONFIG_DIR=CODE/conf \
        python kernel_capture.py capture CAPTURE.pt input.image=IMG edits=SPEC run=RUN threads=2 output_dir=OUT
    ... python kernel_capture.py time CAPTURE.pt

``capture`` wraps :func:`sdn3d.render.soft._call` (the kernel's forward and backward, every call of the fit, both
groups' threads) and saves each call's inputs (a few hundred MB). ``time`` runs each captured call 3 times on one
thread and prints, per direction, crop size and faces per mesh, the summed CPU time (``time.thread_time``), the
(face, pixel) pairs (the faces' grown boxes) and ns per pair.
"""

from __future__ import annotations

import sys
import time

import torch


def capture(path: str, argv: list[str]) -> None:
    import sdn3d.cli.edit as edit
    import sdn3d.render.soft as soft

    calls = []
    original = soft._call

    def recorded(kernel, direction, screen, box, per_mesh, settings, *out):
        calls.append((direction, screen.clone(), box.clone(), per_mesh, (settings.image_size, settings.sigma),
                      [o.clone() for o in out]))
        return original(kernel, direction, screen, box, per_mesh, settings, *out)

    soft._call = recorded
    edit.main(argv)
    torch.save(calls, path)
    print(f"{len(calls)} kernel calls", file=sys.stderr)


def timed(path: str) -> None:
    from sdn3d.render._native import soft_kernel
    from sdn3d.render.soft import AREA_EPS

    kernel = soft_kernel()
    total: dict[tuple, float] = {}
    pairs: dict[tuple, int] = {}
    for direction, screen, box, per_mesh, (size, sigma), out in torch.load(path, weights_only=False):
        fn = getattr(kernel, f"sdn3d_soft_{direction}_f32")
        outs = [o.clone() for o in out]
        start = time.thread_time()
        for _ in range(3):
            fn(screen.data_ptr(), box.data_ptr(), screen.shape[0], per_mesh, size[0], size[1], 1.0 / sigma, AREA_EPS,
               *(o.data_ptr() for o in outs), 1)
        key = (direction, size[0], per_mesh)
        total[key] = total.get(key, 0.0) + (time.thread_time() - start) / 3
        pairs[key] = pairs.get(key, 0) + int((box[:, 2] * box[:, 3]).sum())
    for key in sorted(total):
        print(key, f"CPU s {total[key]:.3f}", f"pairs {pairs[key]}", f"ns/pair {1e9 * total[key] / pairs[key]:.1f}")
    print(f"total CPU s {sum(total.values()):.3f}")


if __name__ == "__main__":
    if sys.argv[1] == "capture":
        capture(sys.argv[2], sys.argv[3:])
    else:
        timed(sys.argv[2])
