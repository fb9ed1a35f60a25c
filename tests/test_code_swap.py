"""Code-swap test (sdn3d.evaluation.code_swap): the colour move, pair choice, silhouette and leak, one frame."""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import textural_spec

from sdn3d.data import vkitti1
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.evaluation.code_swap import (
    CodeSwapSettings,
    code_swap_frame,
    color_move,
    pair_metrics,
    region_colors,
    summarize,
    swap_pairs,
)
from sdn3d.scene.maps import scene_maps
from sdn3d.textural.codes import rgb_to_lab


def test_color_move_projects_the_change_on_the_way_from_a_to_b():
    a, b = torch.tensor([[0.0, 0.0, 0.0]] * 3), torch.tensor([[1.0, 0.0, 0.0]] * 3)
    rec = torch.tensor([[0.1, 0.0, 0.0]] * 3)
    swap = torch.tensor([[0.6, 0.0, 0.0], [0.1, 0.3, 0.0], [1.1, 0.0, 0.0]])
    move, off = color_move(rec, swap, a, b)
    assert move.tolist() == pytest.approx([0.5, 0.0, 1.0]) and off.tolist() == pytest.approx([0.0, 0.3, 0.0])


def test_swap_pairs_are_same_class_different_colour_usable_objects():
    classes = torch.tensor([12, 12, 13, 12, 12])
    colors = torch.tensor([[0.7, 0.1, 0.1], [0.72, 0.1, 0.1], [0.1, 0.1, 0.7], [0.1, 0.1, 0.7], [0.9, 0.9, 0.9]])
    usable = torch.tensor([True, True, True, True, False])
    pairs = swap_pairs(classes, colors, usable, CodeSwapSettings())
    assert sorted(map(tuple, pairs.tolist())) == [(0, 3), (1, 3), (3, 0), (3, 1)]  # 0 and 1 are both red
    lab = rgb_to_lab(colors)
    assert all(float((lab[a] - lab[b]).norm()) >= 20 for a, b in pairs.tolist())
    few = swap_pairs(classes, colors, usable, CodeSwapSettings(max_pairs_per_frame=2), torch.Generator().manual_seed(0))
    assert few.shape == (2, 2) and set(map(tuple, few.tolist())) <= set(map(tuple, pairs.tolist()))


def _square_scene() -> tuple[torch.Tensor, torch.Tensor]:
    """A grey 24x32 image with a red 8x8 square: ``(image (3, H, W), region (H, W))``."""
    image = torch.full((3, 24, 32), 0.5)
    region = torch.zeros(24, 32, dtype=torch.bool)
    region[8:16, 12:20] = True
    image[:, region] = torch.tensor([0.8, 0.1, 0.1])[:, None]
    return image, region


def test_pair_metrics_of_a_clean_recolour_and_of_one_that_spills():
    rec, region = _square_scene()
    blue = torch.tensor([0.1, 0.1, 0.8])
    clean = rec.clone()
    clean[:, region] = blue[:, None]
    spill = clean.clone()
    spill[:, 4:20, 8:24] = blue[:, None, None]  # paints 4 px around the square too
    red = torch.tensor([[0.8, 0.1, 0.1]] * 2)
    blues = blue.expand(2, 3)
    regions = region.expand(2, -1, -1)
    out = pair_metrics(rec, torch.stack([clean, spill]), regions, red, blues, blues, CodeSwapSettings())
    assert out["color_move"].tolist() == pytest.approx([1.0, 1.0])
    assert out["off_axis"].tolist() == pytest.approx([0, 0])
    assert out["color_move_rendered"].tolist() == pytest.approx([1.0, 1.0])
    assert out["silhouette_change"][0] == 0 and out["leak"][0] == 0
    assert out["iou_rec_vs_region"].tolist() == pytest.approx([1.0, 1.0])
    assert out["silhouette_change"][1] > 0.3 and out["leak"][1] > 0.05  # the outline grew, the change leaked
    assert out["iou_swap_vs_region"][0] == 1 and out["iou_swap_vs_region"][1] < 0.7


class PaintCodes:
    """A generator double that paints every pixel with the first 3 values of its code (a perfectly disentangled
    renderer): the code-swap test must read a colour move of exactly 1 from it."""

    spec = textural_spec()
    device = torch.device("cpu")

    def render(self, label, L, boundary=None, codes=None, code_map=None, pose=None, normal=None):
        assert code_map.shape[0] == label.shape[0] == pose.shape[0]
        return code_map[:, :3].clamp(0, 1)


def test_code_swap_frame_with_a_disentangled_renderer(tiny_synth):
    size = (160, 64)
    record = max(vkitti1.read_frames(tiny_synth), key=lambda r: len(r.objects))
    image = load_frame(record, size).image
    scene = scene_from_frame(record, size, code_dim=5)
    regions = scene_maps(scene).instance_label_map == scene.objects.instance_id[:, None, None]
    colors = region_colors(image, regions)
    codes = torch.cat([colors, torch.zeros(len(colors), 2)], 1)
    scene = scene.replace(objects=scene.objects.replace(code=codes),
                          background_codes=torch.full_like(scene.background_codes, 0.5))
    settings = CodeSwapSettings(min_pixels=10, min_delta_e=5.0, erode=0)
    out = code_swap_frame(scene, image, PaintCodes(), settings)
    assert out["a"].numel() > 0 and out["a"].shape == out["color_move"].shape
    torch.testing.assert_close(out["color_move"], torch.ones_like(out["color_move"]), atol=1e-5, rtol=0)
    torch.testing.assert_close(out["off_axis"], torch.zeros_like(out["off_axis"]), atol=1e-5, rtol=0)
    assert float(out["leak"].abs().max()) == 0  # only A's pixels changed
    assert bool((out["a"] // 1000 == out["b"] // 1000).all()) and bool((out["a"] != out["b"]).all())
    summary = summarize([out, code_swap_frame(scene, image, PaintCodes(), CodeSwapSettings(min_pixels=10**6))],
                        settings)
    assert summary["pairs"] == out["a"].numel() and summary["frames_with_pairs"] == 1
    assert summary["color_move"] == pytest.approx(1.0, abs=1e-5) and summary["color_move_median"] == pytest.approx(1.0)
    assert summary["settings"]["min_delta_e"] == 5.0
    assert math.isnan(summarize([], settings)["color_move"])
