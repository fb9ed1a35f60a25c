"""Replay captured kernel calls (kernel_capture.py) through two builds of ``soft_kernel.cpp``: CPU seconds of the
forwards and backwards (one thread, least of 3 rounds, the two builds taking turns) and whether every output bit is
the same.

    PYTHONPATH=src python kernel_bench.py CAPTURE.pt NEW.cpp REF.cpp

The builds use ``sdn3d.render._native``'s flags (``-O3 -march=native``), into /tmp/s22data/fitcost/k_<hash>.so.
"""

from __future__ import annotations

import ctypes
import hashlib
import subprocess
import sys
import time
from pathlib import Path

import torch

from sdn3d.render._common import AREA_EPS
from sdn3d.render._native import _FLAGS


def _build(source: str) -> ctypes.CDLL:
    out = Path("/tmp/s22data/fitcost") / f"k_{hashlib.sha1(Path(source).read_bytes()).hexdigest()[:10]}.so"
    if not out.exists():
        subprocess.run(["g++", *_FLAGS, "-o", str(out), source], check=True)
    lib = ctypes.CDLL(str(out))
    ptr, i32, i64, f64 = ctypes.c_void_p, ctypes.c_int, ctypes.c_int64, ctypes.c_double
    lib.sdn3d_soft_forward_f32.argtypes = [ptr, ptr, i64, i64, i64, i64, f64, f64, ptr, i32]
    lib.sdn3d_soft_backward_f32.argtypes = [ptr, ptr, i64, i64, i64, i64, f64, f64, ptr, ptr, i32]
    return lib


def _replay(lib: ctypes.CDLL, caps: list[dict]) -> tuple[list[torch.Tensor], float, float]:
    outs, forward, backward = [], 0.0, 0.0
    for c in caps:
        screen, box, (h, w) = c["screen"], c["box"], c["size"]
        args = (screen.data_ptr(), box.data_ptr(), screen.shape[0], c["fpm"], h, w, 1.0 / c["sigma"], AREA_EPS)
        start = time.thread_time()
        if c["direction"] == "forward":
            out = torch.zeros(screen.shape[0] // c["fpm"] * h * w)
            lib.sdn3d_soft_forward_f32(*args, out.data_ptr(), 1)
            forward += time.thread_time() - start
        else:
            out = torch.empty_like(screen)
            lib.sdn3d_soft_backward_f32(*args, c["pixel_grad"].data_ptr(), out.data_ptr(), 1)
            backward += time.thread_time() - start
        outs.append(out)
    return outs, forward, backward


def main() -> None:
    caps = torch.load(sys.argv[1], weights_only=False)
    libs = {"new": _build(sys.argv[2]), "ref": _build(sys.argv[3])}
    best: dict[str, list] = {}
    for _ in range(3):
        for name, lib in libs.items():
            outs, forward, backward = _replay(lib, caps)
            old = best.get(name, [9e9, 9e9, outs])
            best[name] = [min(old[0], forward), min(old[1], backward), outs]
    same = all(torch.equal(a.view(torch.int32), b.view(torch.int32)) for a, b in zip(best["new"][2], best["ref"][2],
                                                                                      strict=True))
    print(f"{len(caps)} calls; ref: forward {best['ref'][0]:.3f} s, backward {best['ref'][1]:.3f} s | new: forward "
          f"{best['new'][0]:.3f} s, backward {best['new'][1]:.3f} s | every output bit the same: {same}")


if __name__ == "__main__":
    main()
