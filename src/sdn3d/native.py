"""sdn3d's C++ kernels: each built from its ``.cpp`` source on first use and loaded with ctypes.

A kernel has a plain C ABI and no torch headers, so ``g++ -O3 -shared`` builds it in about a second on a fresh
machine (``build-essential``); no ninja or torch extension toolchain is needed. Each shared library is cached under
``$SDN3D_NATIVE_CACHE`` (default ``~/.cache/sdn3d/native``: :func:`sdn3d.io.cache_dir`), keyed by a hash of the
source, the compiler command and the processor, and written atomically, so parallel processes may build it at once.
Without a compiler, or if the build fails, :func:`load_kernel` returns ``None`` with a warning, and the kernel's
caller runs its pure-PyTorch path. The kernels: the soft silhouette's (:mod:`sdn3d.render._native`) and the photo
appearance's nearest examples (:mod:`sdn3d.editing.photo.nearest`).
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

from sdn3d.io import cache_dir

__all__ = ["build_kernel", "compiler", "load_kernel"]

#: GCC's default ``-ffp-contract=fast`` fuses ``a - t * b`` into one multiply-add where ``-march=native`` has FMA, as
#: PyTorch's vectorised ``addcmul`` does: near an edge the soft silhouette's ``r = w - t e`` cancels, and unfused
#: rounding there moved silhouettes by up to 2e-6 at ``sigma = 0.02`` (fused: within 1 float32 ulp of the PyTorch
#: path).
FLAGS = ("-O3", "-march=native", "-shared", "-fPIC", "-std=c++17", "-pthread")


def _cpu() -> str:
    """The processor's model and instruction-set flags (``-march=native`` builds for them; a cache directory shared
    between machines gets one library per kind of processor)."""
    try:
        info = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return platform.machine()
    return platform.machine() + "".join(sorted({line for line in info if line.startswith(("flags", "model name"))}))


def compiler() -> str | None:
    """The C++ compiler the kernels are built with: ``$CXX``, else ``g++``, else ``c++`` on the path; None: none."""
    return os.environ.get("CXX") or shutil.which("g++") or shutil.which("c++")


def build_kernel(compiler_path: str, source: Path, defines: tuple[str, ...] = ()) -> Path:
    """The shared library built from ``source`` (cached: ``<source stem>_<hash>.so``); ``defines``: extra ``-D``
    flags (the tests' variants)."""
    flags = (*FLAGS, *defines)
    text = source.read_bytes()
    key = hashlib.sha256(text + " ".join((compiler_path, *flags, _cpu())).encode()).hexdigest()[:16]
    target = cache_dir("native") / f"{source.stem}_{key}.so"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
        built = Path(tmp) / target.name
        subprocess.run([compiler_path, *flags, "-o", str(built), str(source)], check=True, capture_output=True,
                       text=True)
        os.replace(built, target)  # atomic: a concurrent build of the same key writes the same bytes
    return target


def load_kernel(source: Path, abi_function: str, abi_version: int, bind: Callable[[ctypes.CDLL], ctypes.CDLL],
                what: str) -> ctypes.CDLL | None:
    """The kernel of ``source`` built (:func:`build_kernel`), loaded, checked (its ``abi_function()`` must return
    ``abi_version``: a stale library is refused) and bound (``bind`` sets each function's argument types); None,
    with a warning naming ``what`` uses its PyTorch path, when there is no compiler or the build or load fails."""
    found = compiler()
    if found is None:
        warnings.warn(f"no C++ compiler: {what} uses its (slower) PyTorch path", stacklevel=3)
        return None
    try:
        lib = ctypes.CDLL(str(build_kernel(found, source)))
        getattr(lib, abi_function).restype = ctypes.c_int
        if getattr(lib, abi_function)() != abi_version:
            raise RuntimeError(f"stale {source.stem} library")
        return bind(lib)
    except (OSError, RuntimeError, AttributeError, subprocess.CalledProcessError) as err:
        detail = getattr(err, "stderr", "") or err
        warnings.warn(f"{source.stem} not built ({detail}); {what} uses its PyTorch path", stacklevel=3)
        return None
