"""The C++ kernels' tests (sdn3d.native): skip where no compiler can build a kernel, and refuse to run without one on
CI, where scripts/test.sh installs build-essential and a missing compiler would leave a kernel untested."""

from __future__ import annotations

import os
import shutil

import pytest

HAS_COMPILER = shutil.which("g++") is not None
needs_compiler = pytest.mark.skipif(not HAS_COMPILER, reason="no C++ compiler: the kernel cannot build")


def require_compiler_on_ci(kernel: str) -> None:
    """Raise (at the importing test module's collection) on CI without ``g++``: ``kernel``'s tests cannot run."""
    if not HAS_COMPILER and os.environ.get("CI", "").lower() == "true":
        raise RuntimeError(f"the {kernel} kernel's tests cannot run on CI: g++ is missing")
