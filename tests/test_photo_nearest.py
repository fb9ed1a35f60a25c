"""The photo appearance's nearest examples (editing/photo/nearest.py): the C++ kernel against the PyTorch path, its
threads, its fallback and its cache."""

from __future__ import annotations

import torch
from helpers.native import needs_compiler, require_compiler_on_ci

from sdn3d.editing.photo import nearest

require_compiler_on_ci("nearest-examples")


def pytorch_path(query: torch.Tensor, examples: torch.Tensor, k: int) -> torch.Tensor:
    k = min(k, len(examples))
    return nearest._nearest_in_blocks(query.float().contiguous(), examples.float(), k)


def cases(seed: int):
    """(query, examples, k): many rows and few, more examples than a vector and fewer than k, exact ties (every
    example twice) and near ties (queries 1e-7 from an example)."""
    g = torch.Generator().manual_seed(seed)
    for q, e, k in ((3000, 1500, 4), (1030, 700, 16), (530, 20, 4), (20, 20, 4), (63, 12, 16), (9000, 40, 4),
                    (30, 3, 4), (200, 1, 4)):
        examples = torch.rand(e, 6, generator=g, dtype=torch.float64)
        if e > 1:
            examples[e // 2:] = examples[:e - e // 2].clone()
        query = torch.rand(q, 6, generator=g, dtype=torch.float64)
        query[::7] = examples[torch.arange(0, q, 7) % e] + 1e-7
        yield query, examples, k


@needs_compiler
def test_the_kernel_builds_here_and_answers(monkeypatch) -> None:
    assert nearest.nearest_kernel() is not None

    def refuse(*args):
        raise AssertionError("the PyTorch path ran although the kernel is here")

    monkeypatch.setattr(nearest, "_nearest_in_blocks", refuse)
    got = nearest.nearest_examples(torch.rand(100, 6), torch.rand(50, 6), 4)
    assert got.shape == (100, 4) and got.dtype == torch.int64


@needs_compiler
def test_the_kernel_finds_the_pytorch_paths_nearest_sets_nearest_first() -> None:
    """The same k nearest examples as ``cdist`` + ``topk`` in every row, in the same order wherever the distances
    are told apart (more than 1e-5 between neighbours in the row's order: the two sum a distance's terms in other
    orders); of exactly equal distances (every example twice) the lower index first."""
    for query, examples, k in cases(3):
        got, want = nearest.nearest_examples(query, examples, k), pytorch_path(query, examples, k)
        k = min(k, len(examples))
        assert got.shape == want.shape == (len(query), k)
        dist = torch.cdist(query, examples)  # float64: the truth the two float32 paths approximate
        sorted_dist = dist.sort(1).values
        # rows whose k-th and (k+1)-th distances are told apart: both paths must find the same set
        clear = (sorted_dist[:, k] - sorted_dist[:, k - 1] > 1e-5) if len(examples) > k else torch.ones(
            len(query), dtype=torch.bool)
        assert float(clear.float().mean()) > 0.3
        assert torch.equal(got[clear].sort(1).values, want[clear].sort(1).values)
        # nearest first: the kernel's distances do not fall along a row (up to float32 rounding)
        mine = dist.gather(1, got)
        assert bool((mine[:, 1:] >= mine[:, :-1] - 1e-6).all())
        # exactly repeated examples: of equal distances the lower index first
        e = len(examples)
        if e > 1 and e % 2 == 0:  # example j and j + e / 2 are one example twice
            twins = got.remainder(e // 2)
            same = (twins[:, 1:] == twins[:, :-1]) & (mine[:, 1:] == mine[:, :-1])
            assert bool((got[:, 1:][same] > got[:, :-1][same]).all())


@needs_compiler
def test_any_thread_count_gives_the_same_bits() -> None:
    g = torch.Generator().manual_seed(5)
    query, examples = torch.rand(5000, 6, generator=g), torch.rand(1500, 6, generator=g)
    threads, results = torch.get_num_threads(), []
    try:
        for count in (1, 3, 2, 8):
            torch.set_num_threads(count)
            results.append(nearest.nearest_examples(query, examples, 16))
    finally:
        torch.set_num_threads(threads)
    assert all(torch.equal(r, results[0]) for r in results[1:])


def test_without_the_kernel_the_pytorch_path_answers(monkeypatch) -> None:
    query, examples, k = next(cases(7))
    monkeypatch.setattr(nearest, "nearest_kernel", lambda: None)
    assert torch.equal(nearest.nearest_examples(query, examples, k), pytorch_path(query, examples, k))
    assert nearest.nearest_examples(query[:0], examples, k).shape == (0, k)
