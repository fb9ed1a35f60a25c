"""The soft silhouette's fused C++ kernel (``soft_kernel.cpp``), built on first use and loaded with ctypes by
:func:`sdn3d.native.load_kernel` (its cache, its compiler and its fallback). Without it, :func:`soft_kernel` returns
``None`` (once, with a warning) and :mod:`sdn3d.render.soft` uses its pure-PyTorch path, which computes the same
silhouettes and gradients up to float rounding.
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

from sdn3d.native import load_kernel

__all__ = ["soft_kernel"]

SOURCE = Path(__file__).with_name("soft_kernel.cpp")
ABI_VERSION = 4


def bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    """``lib`` with its functions' argument and result types set."""
    ptr, i32, i64, f64 = ctypes.c_void_p, ctypes.c_int, ctypes.c_int64, ctypes.c_double
    for dtype in ("f32", "f64"):
        getattr(lib, f"sdn3d_soft_forward_{dtype}").argtypes = [ptr, ptr, i64, i64, i64, i64, f64, f64, ptr, i32]
        getattr(lib, f"sdn3d_soft_backward_{dtype}").argtypes = [
            ptr, ptr, i64, i64, i64, i64, f64, f64, ptr, ptr, i32
        ]
        getattr(lib, f"sdn3d_soft_boxes_{dtype}").argtypes = [ptr, ptr, i64, i64, i64, f64, ptr]
        getattr(lib, f"sdn3d_soft_boxes_{dtype}").restype = None
        getattr(lib, f"sdn3d_soft_forward_{dtype}").restype = None
        getattr(lib, f"sdn3d_soft_backward_{dtype}").restype = None
    return lib


@functools.lru_cache(maxsize=1)
def soft_kernel() -> ctypes.CDLL | None:
    """The loaded kernel library, or ``None`` when it cannot be built (then the PyTorch path runs)."""
    return load_kernel(SOURCE, "sdn3d_soft_abi_version", ABI_VERSION, bind, "the soft silhouette")
