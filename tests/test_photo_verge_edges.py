"""ray_fill's ``verge='edges'`` (photo.ray_verge): a verge whose edges run into the hole runs on inside them.

A traffic island (a wedge of grass between a kerb that runs along the rays and an edge that runs across them, its tip
hidden by the removed car) seen right of a hole only: with ``verge='road'`` the hole is road from where it begins (the
island ends in a straight edge there, issue 41); with ``verge='edges'`` the hole pixels inside the wedge's two edges
continued are grass and those outside them road.
"""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.photo.road import ray_fill, road_lab, verge_like
from sdn3d.editing.photo.settings import PhotoSettings

H, W = 80, 160
VP = (-400.0, 10.0)
ROAD, GRASS = (0.45, 0.45, 0.45), (0.55, 0.66, 0.22)


def _island() -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(image (3, H, W), hole (H, W), wedge (H, W) bool, margin (H, W) float)``: road with a grass wedge whose lower
    edge runs along a ray from ``VP`` and whose upper edge falls to meet it at x = 40, inside the hole (x 30-129, y
    25-69); ``margin``: each pixel's distance (rows) to the nearer of the wedge's edges."""
    y = torch.arange(H, dtype=torch.float32)[:, None].expand(H, W)
    x = torch.arange(W, dtype=torch.float32)[None, :].expand(H, W)
    lower = 10.0 + (x + 400.0) * (50.0 / 550.0)  # through VP and (150, 60): a kerb along the road
    upper = 30.0 + (150.0 - x) * (20.0 / 110.0)  # through (150, 30) and the tip (40, 50)
    wedge = (y >= upper) & (y <= lower) & (x >= 40)
    image = torch.tensor(ROAD)[:, None, None].expand(3, H, W).clone()
    image[:, wedge] = torch.tensor(GRASS)[:, None]
    hole = torch.zeros(H, W, dtype=torch.bool)
    hole[25:70, 30:130] = True
    margin = torch.minimum((y - upper).abs(), (lower - y).abs())
    return image, hole, wedge, margin


def test_edges_continue_the_island_into_the_hole_and_road_ends_it_at_the_hole():
    image, hole, wedge, margin = _island()
    road = road_lab(torch.tensor([ROAD]))[0]
    edges, reached = ray_fill(image, hole, VP, texture=0.0, road=road, verge="edges")
    plain, _ = ray_fill(image, hole, VP, texture=0.0, road=road, verge="road")
    assert bool(reached[hole].all())
    inside = hole & wedge & (margin > 3)
    outside = hole & ~wedge & (margin > 3)
    assert int(inside.sum()) > 300 and int(outside.sum()) > 1000
    grass_edges = verge_like(edges[:, inside], road).float().mean()
    assert float(grass_edges) > 0.95  # the island runs on to its tip
    assert float(verge_like(edges[:, outside], road).float().mean()) < 0.01  # no grass on the road around it
    assert float(verge_like(plain[:, inside], road).float().mean()) < 0.01  # 'road': the island ends at the hole
    # where the far side is road, both modes draw the same road
    assert torch.allclose(edges[:, outside], plain[:, outside])


def test_ray_verge_edges_is_a_setting_and_ray_fill_checks_its_verge():
    assert PhotoSettings().ray_verge == "edges"
    assert PhotoSettings(ray_verge="road").ray_verge == "road"
    image, hole, _, _ = _island()
    with pytest.raises(ValueError, match="verge"):
        ray_fill(image, hole, VP, verge="grass")
