"""The photo appearance's cost cuts that are not bit-identical (docs/results/2026-11-29_cpu/session9/rot05/): each
gives what the computation it replaced gave wherever that is well defined (no near ties), with the replaced
computation written out here as the reference."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.editing.photo import nearest
from sdn3d.editing.photo.road import GRAIN_WEIGHTS, _nearest_zero
from sdn3d.image_ops import dilate_square


def _scan(values: list[float | None]) -> int | None:
    """_matched_weight's choice as it was: every weight looked at, in order, the first nearest 0 kept."""
    best, gap = None, math.inf
    for i, e in enumerate(values):
        if e is not None and abs(e) < gap:
            best, gap = i, abs(e)
    return best


def _counted(values: list[float | None]):
    seen: list[int] = []

    def excess(i: int) -> float | None:
        seen.append(i)
        return values[i]
    return excess, seen


def test_nearest_zero_is_the_scans_choice_with_few_looks_when_the_excess_grows():
    assert list(GRAIN_WEIGHTS) == sorted(set(GRAIN_WEIGHTS))  # the bisection reads them as increasing
    g = torch.Generator().manual_seed(0)
    n = len(GRAIN_WEIGHTS)
    for _ in range(300):
        shift = float(torch.randn(1, generator=g)) * 0.01
        grows = (torch.rand(n, generator=g) * 0.003).cumsum(0) + shift  # increasing, crossing 0 or not
        values = grows.tolist()
        excess, seen = _counted(values)
        assert _nearest_zero(excess, n) == _scan(values)
        assert len(set(seen)) <= 2 + math.ceil(math.log2(n - 1)), seen  # the ends, then one more or a bisection


def test_nearest_zero_falls_back_to_the_scan_on_gaps_ties_and_bends():
    n = len(GRAIN_WEIGHTS)
    cases = [
        [0.0] * n,  # no grain: the first weight
        [-0.01] * n,  # the same, below the target
        [-0.02, -0.01] + [-0.005] * (n - 2),  # a plateau at the end: its first index
        [None] + [0.001 * i - 0.004 for i in range(1, n)],  # too few road-like pixels at one weight
        [None] * n,  # nowhere enough: None (the caller's default)
        [-0.004, 0.003, -0.001, 0.002, 0.004, 0.005, 0.006, 0.007, 0.008, 0.009],  # not monotone
        [0.009, 0.008, 0.007, 0.006, 0.005, 0.004, 0.003, 0.002, 0.001, -0.003],  # falling
        [-0.009, -0.007, -0.005, -0.003, -0.001, 0.001, 0.003, 0.005, 0.007, 0.009],  # an exact tie: the first
    ]
    for values in cases:
        excess, _ = _counted(values)
        assert _nearest_zero(excess, n) == _scan(values), values


@pytest.mark.parametrize("kernel", [True, False], ids=["kernel", "pytorch"])
def test_nearest_examples_in_float32_are_float64s_without_near_ties(monkeypatch, kernel):
    if not kernel:
        monkeypatch.setattr(nearest, "nearest_kernel", lambda: None)
    g = torch.Generator().manual_seed(1)
    for q, e, k in ((500, 1500, 4), (9000, 40, 4), (30, 3, 4)):  # several chunks; fewer examples than k
        examples = torch.rand(e, 6, generator=g, dtype=torch.float64)
        query = torch.rand(q, 6, generator=g, dtype=torch.float64)
        want = torch.cdist(query, examples).topk(min(k, e), largest=False)
        got = nearest.nearest_examples(query, examples, k)
        assert got.shape == (q, min(k, e))
        dist = torch.cdist(query, examples).sort(1).values
        clear = (dist[:, min(k, e)] - dist[:, min(k, e) - 1] > 1e-5) if e > k else torch.ones(q, dtype=torch.bool)
        assert float(clear.float().mean()) > 0.9
        assert torch.equal(got[clear].sort(1).values, want.indices[clear].sort(1).values)


def test_road_around_is_road_colours_and_road_like_from_one_conversion():
    from sdn3d.editing.photo.road import _road_around, road_colours, road_like
    from tests.test_photo_cost import _road_picture

    image = _road_picture(90, 200, 3)
    hole = torch.zeros(90, 200, dtype=torch.bool)
    hole[30:60, 50:120] = True
    for ring in (dilate_square(hole, 25) & ~dilate_square(hole, 5), torch.ones(90, 200, dtype=torch.bool)[:, ::3]):
        img = image if ring.shape[1] == 200 else image[:, :, ::3]
        road, like = _road_around(img, ring)
        want = road_colours(img, ring)
        assert road is not None and torch.equal(road, want)
        expected = ring & road_like(img, want, within=ring)
        assert 0 < int(like.sum()) < int(ring.sum())  # a real test: some ring pixels are road, some not
        assert int((like != expected).sum()) <= max(1, int(ring.sum()) // 1000)  # last-bit flips at the threshold
    empty = torch.zeros(90, 200, dtype=torch.bool)
    road, like = _road_around(image, empty)
    assert road is None and not bool(like.any())


def test_road_lab_is_srgb_to_lab_within_its_tolerance():
    from sdn3d.editing.photo.recolor import srgb_to_lab
    from sdn3d.editing.photo.road import road_lab

    g = torch.Generator().manual_seed(7)
    rgb = torch.cat([torch.rand(50000, 3, generator=g), torch.eye(3), torch.zeros(1, 3), torch.ones(1, 3),
                     torch.tensor([[0.04045, 0.0404, 0.0405], [-0.1, 1.2, 0.5]])])  # the branches' edges, clamping
    got, want = road_lab(rgb), srgb_to_lab(rgb)
    assert got.shape == want.shape and got.dtype == torch.float32 and got.stride() == want.stride()
    assert float((got - want).abs().max()) < 2e-3  # whole Lab units are the road tests' scale
    assert float((got - want).abs().mean()) < 1e-4
    assert torch.equal(road_lab(rgb.double()), got)  # computed in float32 whatever comes in
