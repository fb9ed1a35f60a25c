"""Shared test settings: deterministic seeds and a small thread count (CI has 2 cores)."""

from __future__ import annotations

import os
import random
from pathlib import Path

import numpy as np
import pytest
import torch

REPO_ROOT = Path(__file__).resolve().parents[1]
SHARED_REFERENCE = REPO_ROOT.parent / "shared" / "reference"

# One intra-op thread by default: OpenMP worker threads spin-wait, and on a 2-core machine any
# other busy process makes multi-threaded small ops orders of magnitude slower. Benchmarks,
# not tests, measure multi-threaded speed. SDN3D_TEST_THREADS overrides.
torch.set_num_threads(int(os.environ.get("SDN3D_TEST_THREADS", "1")))


@pytest.fixture(autouse=True)
def _seed_everything() -> None:
    random.seed(0)
    np.random.seed(0)
    torch.manual_seed(0)


@pytest.fixture(scope="session")
def reference_dir() -> Path:
    """``../shared/reference`` beside the checkout (CI clones main with shared/ beside it)."""
    if not SHARED_REFERENCE.is_dir():
        pytest.skip(f"reference material not found at {SHARED_REFERENCE}")
    return SHARED_REFERENCE
