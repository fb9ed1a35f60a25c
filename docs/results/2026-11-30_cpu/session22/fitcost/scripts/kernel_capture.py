"""Capture the soft silhouette kernel's inputs during one ``sdn3d-edit`` call (every forward and backward call of the
fit), for kernel_bench.py to replay.

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=src python docs/results/2026-11-30_cpu/session22/fitcost/scripts/\
kernel_capture.py OUT.pt -- <sdn3d-edit overrides, threads=1>
"""

from __future__ import annotations

import sys

import torch


def main() -> None:
    split = sys.argv.index("--")
    out, overrides = sys.argv[1], sys.argv[split + 1:]
    import sdn3d.cli.edit as edit
    import sdn3d.render.soft as soft

    caps, real = [], soft._call

    def call(kernel, direction, screen, box, faces_per_mesh, settings, *tensors):
        caps.append({"direction": direction, "screen": screen.clone(), "box": box.clone(), "fpm": faces_per_mesh,
                     "size": settings.image_size, "sigma": settings.sigma,
                     "pixel_grad": tensors[0].clone() if direction == "backward" else None})
        real(kernel, direction, screen, box, faces_per_mesh, settings, *tensors)

    soft._call = call
    edit.main(overrides)
    torch.save(caps, out)
    print(len(caps), "kernel calls captured into", out)


if __name__ == "__main__":
    main()
