"""Issue 40, session 23 (inward): a car the image's left or right border cuts has its near end at that border, so
the fit drops the hypotheses whose near end points inwards (the silhouette's depth reflection,
``alpha -> -alpha``; ``FitSettings.cut_inward``)."""

from __future__ import annotations

import math

import pytest
import torch

import sdn3d.geometric.fit as fitmod
from sdn3d.geometric.fit import FitSettings, fit_to_masks, inward_at_border
from sdn3d.math3d.camera import Intrinsics

SMALL = FitSettings(coarse_steps=2, fine_steps=2, coarse_size=16, fine_size=16, coarse_faces=0, fine_faces=0)
INTR = Intrinsics(60.0, 60.0, 48.0, 12.0, 96, 48)
X, Z = 2.5, 8.0  # every fine fit is placed here: the ray through it is atan2(X, Z), 17 degrees right
RAY = math.atan2(X, Z)
INWARD, OUTWARD = RAY - math.radians(60), RAY - math.radians(120)  # back views: the back to the left / right


def _wrapd(a: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a), math.cos(a))))


def _rigged(monkeypatch, yaws: list[float], losses: list[float]) -> None:
    """The fine stage's fits of the one car end at ``yaws`` with ``losses`` (the first ones; the rest keep the
    last), all at ``(X, Z)``: the choice among them is what is tested."""
    real = fitmod._stage

    def stage(*args, **kwargs):
        values, loss = real(*args, **kwargs)
        if not kwargs.get("with_ffd"):
            return values, loss
        h = loss.shape[0]
        pad = lambda v: torch.tensor((v + [v[-1]] * h)[:h], dtype=torch.float32)  # noqa: E731
        values = {**values, "ry": pad(yaws), "x": torch.full((h,), X), "z": torch.full((h,), Z)}
        return values, pad(losses)

    monkeypatch.setattr(fitmod, "_stage", stage)


def _fit(box: list[float], settings: FitSettings = SMALL, believed: float | None = None) -> float:
    """The fitted yaw; the appearance believes every yaw alike, or only ``believed`` (cosine)."""
    masks = torch.zeros(1, INTR.height, INTR.width, dtype=torch.bool)
    x0, y0, x1, y1 = (int(v) for v in box)
    masks[0, y0:y1, x0:x1] = True
    result = fit_to_masks(masks, torch.tensor([box]), INTR, settings=settings,
                          yaw_belief=lambda ry: torch.zeros_like(ry) if believed is None else torch.cos(ry - believed))
    return float(result.ry[0])


def test_a_car_cut_by_the_right_border_is_not_fitted_with_its_near_end_inwards(monkeypatch):
    """The inward fit has a quarter of the outward one's loss, but the border cuts the car on the right: the
    outward fit wins. ``cut_inward=1`` (drops none) and a car the border does not cut keep the lower loss."""
    _rigged(monkeypatch, [INWARD, OUTWARD], [0.01, 0.04])
    assert _wrapd(_fit([60.0, 20.0, 96.0, 40.0]) - OUTWARD) < 1e-3
    assert _wrapd(_fit([60.0, 20.0, 96.0, 40.0], FitSettings(**{**SMALL.to_dict(), "cut_inward": 1.0}))
                  - INWARD) < 1e-3
    assert _wrapd(_fit([40.0, 20.0, 80.0, 40.0]) - INWARD) < 1e-3


def test_the_left_border_drops_the_other_reflection(monkeypatch):
    """At the left border the near end must lie left: the fit the right border keeps is the inward one there."""
    _rigged(monkeypatch, [OUTWARD, INWARD], [0.01, 0.04])
    assert _wrapd(_fit([0.0, 20.0, 36.0, 40.0]) - INWARD) < 1e-3


def test_a_cut_car_whose_every_fit_points_inwards_keeps_the_best(monkeypatch):
    """Dropping every fit would leave nothing: then none is dropped and the lowest loss wins as before."""
    _rigged(monkeypatch, [INWARD, INWARD + 0.1], [0.04, 0.01])
    assert _wrapd(_fit([60.0, 20.0, 96.0, 40.0]) - INWARD - 0.1) < 1e-3


def test_the_border_does_not_hand_a_cut_car_the_end_its_appearance_believes_less(monkeypatch):
    """The fit left after the drop faces the end the appearance disbelieves (the inward fit's reverse): the border
    tells the near end's side, not the end, so the inward fit stays. Believed alike, the outward fit wins."""
    reverse = OUTWARD + math.pi  # the outward axis facing the other end: the inward fit's depth reflection reversed
    _rigged(monkeypatch, [INWARD, reverse], [0.01, 0.04])
    assert _wrapd(_fit([60.0, 20.0, 96.0, 40.0], believed=INWARD) - INWARD) < 1e-3
    assert _wrapd(_fit([60.0, 20.0, 96.0, 40.0]) - reverse) < 1e-3


def test_inward_reads_the_near_end_of_end_and_side_views_as_moot():
    """``sin(2 alpha)``: a car seen end on or side on has no near end to one side, so it is not dropped at the
    smallest ``cut_inward`` above rounding; a back view turned 30 degrees with its back inwards is."""
    side = torch.ones(1)
    ry = torch.tensor([[RAY - math.pi / 2, RAY, RAY - math.radians(60), RAY - math.radians(120)]])
    assert inward_at_border(side, ry, torch.full((1, 4), RAY), 0.01).tolist() == [[False, False, True, False]]
    assert inward_at_border(torch.zeros(1), ry, torch.full((1, 4), RAY), 0.0).tolist() == [[False] * 4]


@pytest.mark.parametrize("value", [-0.1, 1.5, True, "0.2", math.nan])
def test_cut_inward_refuses_values_outside_zero_to_one_by_name(value):
    with pytest.raises(ValueError, match="cut_inward"):
        FitSettings(cut_inward=value)
