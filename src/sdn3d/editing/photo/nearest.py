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

A part lookup's examples share their normal's three features with the others of their template face (36-43 distinct
normals among 1,500 examples on the real frame's turns). Told so (``shared_from=3``), the kernel scans the examples a
group of equal trailing features at a time, nearest group first, each row starting from the examples the row before
it kept, and skips a group whose trailing distance (plus the distance to its members' box) is beyond the ``k``-th
best so far: the same answer bit for bit in about a third of the flat scan's time on the real frame's turns
(``nearest_kernel.cpp``, docs/results/2026-12-02_cpu/session35/lead/nearest/; where the groups are more than
:data:`GROUPED_MAX_SHARE` of the examples or the rows fewer than :data:`GROUPED_MIN_ROWS`, the flat scan).

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

__all__ = ["GROUPED_MAX_SHARE", "GROUPED_MIN_ROWS", "NEAREST_ROWS", "nearest_examples", "nearest_kernel"]

SOURCE = Path(__file__).with_name("nearest_kernel.cpp")
ABI_VERSION = 3
#: The PyTorch path's block of query rows (its ``(rows, E)`` float32 distances: 3 MB at 1500 examples), so that each
#: block's distances stay in the processor's cache between ``cdist`` and ``topk``: blocks of 8192 rows (49 MB of
#: distances at 1500 examples) took about 1.5 times as long on the real frame's turns
#: (docs/results/2026-11-30_cpu/session23/turncost/).
NEAREST_ROWS = 512
#: :func:`nearest_examples` with ``shared_from``: the grouped scan runs where the examples' distinct trailing feature
#: rows are at most this share of them (each group's trailing distance is summed and sorted for every query row: with
#: a group an example, that is the flat scan's work and more).
GROUPED_MAX_SHARE = 0.25
#: ... and where there are at least this many query rows (fewer: the groups' setup costs more than it saves).
GROUPED_MIN_ROWS = 1024


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    ptr, i64 = ctypes.c_void_p, ctypes.c_int64
    lib.sdn3d_nearest_f32.argtypes = [ptr, ptr, i64, i64, i64, i64, ptr, ctypes.c_int]
    lib.sdn3d_nearest_f32.restype = None
    lib.sdn3d_nearest_grouped_f32.argtypes = [ptr, ptr, ptr, ptr, ptr, ptr, ptr, i64, i64, i64, i64, i64, i64, ptr,
                                              ctypes.c_int]
    lib.sdn3d_nearest_grouped_f32.restype = None
    return lib


@functools.lru_cache(maxsize=1)
def nearest_kernel() -> ctypes.CDLL | None:
    """The loaded kernel library, or ``None`` when it cannot be built (then the PyTorch path runs)."""
    return load_kernel(SOURCE, "sdn3d_nearest_abi_version", ABI_VERSION, _bind, "the photo's nearest examples")


def nearest_examples(query: Tensor, examples: Tensor, k: int, shared_from: int | None = None) -> Tensor:
    """``(Q, min(k, E))`` int64: the indices of the ``k`` examples ``examples (E, F)`` nearest (Euclidean, in
    float32) each row of ``query (Q, F)``, nearest first (module doc: the kernel, else the PyTorch path).
    ``shared_from``: the examples' features from this column on take few distinct values (the part lookups' normals),
    which the kernel's grouped scan uses; the answer is the same with or without it."""
    k = min(k, len(examples))
    query, examples = query.float().contiguous(), examples.float()
    kernel = nearest_kernel() if len(query) and k > 0 else None
    if kernel is None:
        return _nearest_in_blocks(query, examples, k)
    out = torch.empty(len(query), k, dtype=torch.int64)
    grouped = shared_from is not None and len(query) >= GROUPED_MIN_ROWS
    groups = _groups(examples, shared_from) if grouped else None
    if groups is not None:
        examples_t, example_index, tails, boxes, offsets = groups
        # rows with the same trailing features one after another: the kernel sorts the groups once for them (it
        # reads and writes the rows in this order in place: no sorted copy of the query, no answer to scatter back)
        rows = _row_hash(query[:, shared_from:]).argsort(stable=True)
        kernel.sdn3d_nearest_grouped_f32(query.data_ptr(), rows.data_ptr(), examples_t.data_ptr(),
                                         example_index.data_ptr(), tails.data_ptr(), boxes.data_ptr(),
                                         offsets.data_ptr(), len(tails), len(query), len(examples), query.shape[1],
                                         shared_from, k, out.data_ptr(), torch.get_num_threads())
        return out
    examples_t = examples.t().contiguous()  # (F, E): the kernel's loop over examples is one vector loop a feature
    kernel.sdn3d_nearest_f32(query.data_ptr(), examples_t.data_ptr(), len(query), len(examples), query.shape[1], k,
                             out.data_ptr(), torch.get_num_threads())
    return out


def _row_hash(rows: Tensor) -> Tensor:
    """``(Q,)`` int64: a hash of each float32 row of ``rows (Q, T)`` by its bits; equal rows hash equal (only the
    grouped kernel's speed rests on unequal ones hashing apart; its answer rests on nothing here). ``torch.unique``
    over rows took 2.5 times the kernel's own time on the real frame's turns."""
    key = torch.zeros(len(rows), dtype=torch.int64)
    for column in rows.contiguous().view(torch.int32).long().unbind(1):
        key = key * 1_000_003 + column  # wraps round in int64: a hash
    return key


def _boxes(lead: Tensor, offsets: Tensor) -> Tensor:
    """``(G, 2, S)``: the least and greatest of ``lead (E, S)``'s rows in each run ``offsets[g]:offsets[g + 1]``."""
    run = torch.arange(len(offsets) - 1).repeat_interleave(offsets.diff())[:, None].expand_as(lead)
    low = torch.full((len(offsets) - 1, lead.shape[1]), torch.inf).scatter_reduce(0, run, lead, "amin")
    high = torch.full((len(offsets) - 1, lead.shape[1]), -torch.inf).scatter_reduce(0, run, lead, "amax")
    return torch.stack([low, high], 1)


def _groups(examples: Tensor, shared_from: int) -> tuple[Tensor, Tensor, Tensor, Tensor, Tensor] | None:
    """The grouped kernel's view of float32 ``examples (E, F)`` whose columns from ``shared_from`` on take few
    distinct values: ``(examples_t (F, E), example_index (E,), tails (G, F - shared_from), boxes (G, 2, shared_from),
    offsets (G + 1,))``: the examples in groups of equal trailing features, transposed; each one's index in
    ``examples``; each group's trailing features, the least and greatest of its members' leading ones, and where its
    members start. None where the groups are more than :data:`GROUPED_MAX_SHARE` of the examples, or the split leaves
    either side empty."""
    if not 0 < shared_from < examples.shape[1]:
        return None
    order = _row_hash(examples[:, shared_from:]).argsort(stable=True)  # equal rows one after another
    ordered = examples[order]
    tail = ordered[:, shared_from:]
    # a group starts where a row differs from the one before it (two rows hashing alike may split a group in two:
    # each part is still a group of equal rows)
    starts = torch.cat([torch.ones(1, dtype=torch.bool), (tail[1:] != tail[:-1]).any(1)]).nonzero().flatten()
    if len(starts) > GROUPED_MAX_SHARE * len(examples):
        return None
    offsets = torch.cat([starts, torch.tensor([len(examples)])])
    boxes = _boxes(ordered[:, :shared_from], offsets).contiguous()
    return ordered.t().contiguous(), order, tail[starts].contiguous(), boxes, offsets


def _nearest_in_blocks(query: Tensor, examples: Tensor, k: int) -> Tensor:
    """The PyTorch path of :func:`nearest_examples` (float32 ``query`` and ``examples``): ``cdist`` then ``topk``,
    :data:`NEAREST_ROWS` query rows at a time. Each distance is the same whatever the block: ``cdist`` picks its
    formula (a matrix product above 25 rows on either side) from the sizes it is given, so the pick is made here once
    from the whole query's, as one call on all of it would make it."""
    mode = "use_mm_for_euclid_dist" if len(query) > 25 or len(examples) > 25 else "donot_use_mm_for_euclid_dist"
    return torch.cat([torch.cdist(chunk, examples, compute_mode=mode).topk(k, largest=False).indices
                      for chunk in query.split(NEAREST_ROWS)])
