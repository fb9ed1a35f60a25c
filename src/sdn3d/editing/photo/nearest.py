"""The nearest examples of the photo appearance's part lookups: for each query row, the ``k`` examples nearest it.

The part lookup of a turned car's never-seen pixels (:func:`sdn3d.editing.photo.transfer._part_colors`) asks this for
every such pixel, and part smoothing for each face around its corners (about 280,000 rows against up to 1,500
examples for the real frame's two cars turned -90 degrees): it was the costliest step of those turns. Where a C++
compiler is at hand the fused kernel ``nearest_kernel.cpp`` answers (built on first use by
:func:`sdn3d.native.load_kernel`; its distances in one pass per row, the ``k`` best kept as they come, rows over
torch's thread count); else the PyTorch path, ``cdist`` then ``topk`` on blocks of :data:`NEAREST_ROWS` rows. Both
compute squared distances in float32 (float64 only reorders near ties among the nearest:
docs/results/2026-11-29_cpu/session9/rot05/) and give the same nearest sets, nearest first, except among near ties (the
two sum a distance's terms in other orders: ``cdist`` as ``|q|^2 + |e|^2 - 2 q.e``), and of exactly equal distances
the kernel puts the lower index first, where ``topk`` leaves their order unspecified.

>>> import torch
>>> examples = torch.tensor([[0.0, 0.0], [1.0, 0.0], [5.0, 5.0]])
>>> nearest_examples(torch.tensor([[0.9, 0.1]]), examples, 2).tolist()
[[1, 0]]
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

import torch
from torch import Tensor

from sdn3d.native import load_kernel

__all__ = ["NEAREST_ROWS", "nearest_examples", "nearest_kernel"]

SOURCE = Path(__file__).with_name("nearest_kernel.cpp")
ABI_VERSION = 1
#: The PyTorch path's block of query rows (its ``(rows, E)`` float32 distances: 3 MB at 1500 examples), so that each
#: block's distances stay in the processor's cache between ``cdist`` and ``topk``: blocks of 8192 rows (49 MB of
#: distances at 1500 examples) took about 1.5 times as long on the real frame's turns
#: (docs/results/2026-11-30_cpu/session23/turncost/).
NEAREST_ROWS = 512


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    ptr, i64 = ctypes.c_void_p, ctypes.c_int64
    lib.sdn3d_nearest_f32.argtypes = [ptr, ptr, i64, i64, i64, i64, ptr, ctypes.c_int]
    lib.sdn3d_nearest_f32.restype = None
    return lib


@functools.lru_cache(maxsize=1)
def nearest_kernel() -> ctypes.CDLL | None:
    """The loaded kernel library, or ``None`` when it cannot be built (then the PyTorch path runs)."""
    return load_kernel(SOURCE, "sdn3d_nearest_abi_version", ABI_VERSION, _bind, "the photo's nearest examples")


def nearest_examples(query: Tensor, examples: Tensor, k: int) -> Tensor:
    """``(Q, min(k, E))`` int64: the indices of the ``k`` examples ``examples (E, F)`` nearest (Euclidean, in
    float32) each row of ``query (Q, F)``, nearest first (module doc: the kernel, else the PyTorch path)."""
    k = min(k, len(examples))
    query, examples = query.float().contiguous(), examples.float()
    kernel = nearest_kernel() if len(query) and k > 0 else None
    if kernel is None:
        return _nearest_in_blocks(query, examples, k)
    examples_t = examples.t().contiguous()  # (F, E): the kernel's loop over examples is one vector loop a feature
    out = torch.empty(len(query), k, dtype=torch.int64)
    kernel.sdn3d_nearest_f32(query.data_ptr(), examples_t.data_ptr(), len(query), len(examples), query.shape[1], k,
                             out.data_ptr(), torch.get_num_threads())
    return out


def _nearest_in_blocks(query: Tensor, examples: Tensor, k: int) -> Tensor:
    """The PyTorch path of :func:`nearest_examples` (float32 ``query`` and ``examples``): ``cdist`` then ``topk``,
    :data:`NEAREST_ROWS` query rows at a time. Each distance is the same whatever the block: ``cdist`` picks its
    formula (a matrix product above 25 rows on either side) from the sizes it is given, so the pick is made here once
    from the whole query's, as one call on all of it would make it."""
    mode = "use_mm_for_euclid_dist" if len(query) > 25 or len(examples) > 25 else "donot_use_mm_for_euclid_dist"
    return torch.cat([torch.cdist(chunk, examples, compute_mode=mode).topk(k, largest=False).indices
                      for chunk in query.split(NEAREST_ROWS)])
