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


def grouped_cases(seed: int):
    """(query, examples, k) whose examples' last three features take few distinct rows (the part lookups' normals):
    groups of one example and of hundreds, every example twice (exact ties), queries 1e-7 from an example, queries
    sharing their last three features with examples and with one another, and k up to every example."""
    g = torch.Generator().manual_seed(seed)
    for q, e, k, n_groups in ((3000, 1500, 4, 40), (2000, 1500, 16, 12), (1500, 300, 4, 3), (1200, 64, 64, 5),
                              (1100, 200, 16, 50), (4000, 451, 4, 21)):
        tails = torch.nn.functional.normalize(torch.randn(n_groups, 3, generator=g, dtype=torch.float64), dim=1) * 3
        examples = torch.cat([torch.rand(e, 3, generator=g, dtype=torch.float64) * torch.tensor([0.25, 1.0, 0.5]),
                              tails[torch.randint(n_groups, (e,), generator=g)]], 1)
        examples[0, 3:] = tails[-1]  # a group of (at least) one
        examples[e // 2:] = examples[:e - e // 2].clone()
        normals = torch.nn.functional.normalize(torch.randn(q, 3, generator=g, dtype=torch.float64), dim=1)
        query = torch.cat([torch.rand(q, 3, generator=g, dtype=torch.float64), normals * 3], 1)
        query[::5, 3:] = tails[torch.randint(n_groups, (len(query[::5]),), generator=g)]  # an example's normal
        query[1::5, 3:] = query[0, 3:]  # many rows with one normal
        query[::7] = examples[torch.arange(0, q, 7) % e] + 1e-7
        yield query, examples, k


@needs_compiler
def test_the_grouped_scan_gives_the_flat_scans_answer_bit_for_bit(monkeypatch) -> None:
    """``shared_from`` changes how the kernel finds the nearest examples, never which: the same indices in the same
    order as the flat scan in every row, exact ties (lower index first) and near ties included; and the grouped scan
    does run on these cases."""
    ran = []
    groups = nearest._groups
    monkeypatch.setattr(nearest, "_groups", lambda *args: ran.append(groups(*args)) or ran[-1])
    for query, examples, k in grouped_cases(11):
        flat = nearest.nearest_examples(query, examples, k)
        assert torch.equal(nearest.nearest_examples(query, examples, k, shared_from=3), flat)
        assert ran[-1] is not None
    assert len(ran) == 6


@needs_compiler
def test_the_grouped_scan_on_the_part_lookups_features() -> None:
    """Examples as :func:`~sdn3d.editing.photo.transfer._part_features` makes them (a car's frame, its faces' normals
    weighted 3: 43 of them) against a turned car's queries: the flat scan's answer, with 1, 2 and 3 threads."""
    from sdn3d.editing.photo.transfer import FEATURE_NORMAL, PART_LENGTH_WEIGHT, PART_NORMAL_WEIGHT

    g = torch.Generator().manual_seed(4)
    faces = torch.nn.functional.normalize(torch.randn(43, 3, generator=g), dim=1)
    where = torch.rand(1500, 3, generator=g) * torch.tensor([PART_LENGTH_WEIGHT, 1.0, 0.5])
    examples = torch.cat([where, PART_NORMAL_WEIGHT * faces[torch.randint(43, (1500,), generator=g)]], 1)
    turned = torch.nn.functional.normalize(torch.randn(300, 3, generator=g), dim=1)
    query = torch.cat([torch.rand(20000, 3, generator=g) * torch.tensor([PART_LENGTH_WEIGHT, 1.0, 0.5]),
                       PART_NORMAL_WEIGHT * turned[torch.randint(300, (20000,), generator=g)]], 1)
    threads = torch.get_num_threads()
    try:
        for count in (1, 2, 3):
            torch.set_num_threads(count)
            for k in (4, 16):
                assert torch.equal(nearest.nearest_examples(query, examples, k, shared_from=FEATURE_NORMAL),
                                   nearest.nearest_examples(query, examples, k))
    finally:
        torch.set_num_threads(threads)


def test_groups_of_equal_trailing_features() -> None:
    """Each group's members share their trailing features (its ``tails`` row) and lie in its box; every example is
    in one group; too many distinct rows (more than ``GROUPED_MAX_SHARE`` of the examples), or an empty side of the
    split: no groups (the flat scan)."""
    g = torch.Generator().manual_seed(2)
    examples = torch.cat([torch.rand(200, 3, generator=g), torch.randint(2, (200, 3), generator=g).float()], 1)
    examples_t, index, tails, boxes, offsets = nearest._groups(examples, 3)
    assert sorted(index.tolist()) == list(range(200)) and int(offsets[-1]) == 200
    assert torch.equal(examples_t.t(), examples[index])
    for group in range(len(tails)):
        members = examples[index[offsets[group]:offsets[group + 1]]]
        assert len(members) and bool((members[:, 3:] == tails[group]).all())
        assert bool((members[:, :3] >= boxes[group, 0]).all() and (members[:, :3] <= boxes[group, 1]).all())
    assert nearest._groups(torch.rand(200, 6, generator=g), 3) is None
    assert nearest._groups(examples, 0) is None and nearest._groups(examples, 6) is None
    rows = examples[:, 3:]
    hashed = nearest._row_hash(rows)
    same = (rows[:, None] == rows[None]).all(2)
    assert bool((hashed[:, None] == hashed[None])[same].all())


@needs_compiler
def test_the_grouped_scan_breaks_ties_across_groups_by_index() -> None:
    """Examples at exactly the same distance in two groups (their normals mirror one another about the query's): the
    lower index first, and the lower index kept where only one fits, whichever group the scan reaches first (both
    arrangements of the two normals)."""
    g = torch.Generator().manual_seed(9)
    where = torch.rand(40, 3, generator=g)
    a, b = torch.tensor([0.0, 3.0, 0.0]), torch.tensor([0.0, 0.0, 3.0])
    for first, second in ((a, b), (b, a)):
        # example 2i and 2i + 1: the same place, normals a and b, at the same distance from a query facing (3, 0, 0)
        examples = torch.cat([where.repeat_interleave(2, 0), torch.stack([first, second]).repeat(40, 1)], 1)
        query = torch.cat([torch.rand(1200, 3, generator=g), torch.tensor([3.0, 0.0, 0.0]).expand(1200, 3)], 1)
        for k in (1, 3, 4):
            got = nearest.nearest_examples(query, examples, k, shared_from=3)
            assert torch.equal(got, nearest.nearest_examples(query, examples, k))
            pairs = got[:, :k - k % 2].reshape(len(query), -1, 2)
            assert bool((pairs[..., 0] % 2 == 0).all() and (pairs[..., 1] == pairs[..., 0] + 1).all())
            if k % 2:
                assert bool((got[:, -1] % 2 == 0).all())


@needs_compiler
def test_the_benchmark_runs_and_finds_the_same_answers(capsys) -> None:
    """``benchmarks/nearest_examples.py`` times both scans on its two workloads and reports that they agree."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "nearest_examples.py"
    spec = importlib.util.spec_from_file_location("nearest_examples_benchmark", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    threads = torch.get_num_threads()
    try:
        assert module.main(["--repeats", "1"]) == 0
    finally:
        torch.set_num_threads(threads)  # the benchmark sets its own
    lines = [line for line in capsys.readouterr().out.splitlines() if "rows x" in line]
    assert len(lines) == 2 and all(line.endswith("same answer: True") for line in lines)
