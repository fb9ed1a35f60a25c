"""The soft silhouette's fused C++ kernel (``soft_kernel.cpp``): built on first use, loaded with ctypes.

The kernel has a plain C ABI and no torch headers, so ``g++ -O3 -shared`` builds it in about a second on a fresh
machine (``build-essential``); no ninja or torch extension toolchain is needed. The shared library is cached under
``$SDN3D_NATIVE_CACHE`` (default ``~/.cache/sdn3d/native``: :func:`sdn3d.io.cache_dir`), keyed by a hash of the
source, the compiler command and the processor, and written atomically, so parallel processes may build it at once.
Without a compiler, or if the build fails, :func:`soft_kernel` returns ``None`` (once, with a warning) and
:mod:`sdn3d.render.soft` uses its pure-PyTorch path, which computes the same silhouettes and gradients up to float
rounding.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
import warnings
from pathlib import Path

from sdn3d.io import cache_dir

__all__ = ["soft_kernel"]

_SOURCE = Path(__file__).with_name("soft_kernel.cpp")
#: GCC's default ``-ffp-contract=fast`` fuses ``a - t * b`` into one multiply-add where ``-march=native`` has FMA, as
#: PyTorch's vectorised ``addcmul`` does: near an edge ``r = w - t e`` cancels, and unfused rounding there moved
#: silhouettes by up to 2e-6 at ``sigma = 0.02`` (fused: within 1 float32 ulp of the PyTorch path).
_FLAGS = ("-O3", "-march=native", "-shared", "-fPIC", "-std=c++17", "-pthread")
_ABI_VERSION = 4


def _cpu() -> str:
    """The processor's model and instruction-set flags (``-march=native`` builds for them; a cache directory shared
    between machines gets one library per kind of processor)."""
    try:
        info = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return platform.machine()
    return platform.machine() + "".join(sorted({line for line in info if line.startswith(("flags", "model name"))}))


def _build(compiler: str, source: bytes, defines: tuple[str, ...] = ()) -> Path:
    """The library built from ``source`` (cached); ``defines``: extra ``-D`` flags (the tests' variants)."""
    flags = (*_FLAGS, *defines)
    key = hashlib.sha256(source + " ".join((compiler, *flags, _cpu())).encode()).hexdigest()[:16]
    target = cache_dir("native") / f"soft_kernel_{key}.so"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
        built = Path(tmp) / target.name
        subprocess.run(
            [compiler, *flags, "-o", str(built), str(_SOURCE)], check=True, capture_output=True, text=True
        )
        os.replace(built, target)  # atomic: a concurrent build of the same key writes the same bytes
    return target


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
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
    compiler = os.environ.get("CXX") or shutil.which("g++") or shutil.which("c++")
    if compiler is None:
        warnings.warn("no C++ compiler: the soft silhouette uses its (slower) PyTorch path", stacklevel=2)
        return None
    try:
        lib = ctypes.CDLL(str(_build(compiler, _SOURCE.read_bytes())))
        if lib.sdn3d_soft_abi_version() != _ABI_VERSION:
            raise RuntimeError("stale soft_kernel library")
        return _bind(lib)
    except (OSError, RuntimeError, subprocess.CalledProcessError) as err:
        detail = getattr(err, "stderr", "") or err
        warnings.warn(f"soft silhouette kernel not built ({detail}); using the PyTorch path", stacklevel=2)
        return None
