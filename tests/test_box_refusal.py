"""Issue 42: a click or box where no vehicle is gets a refusal naming why (sdn3d.box_masks.no_vehicle, click_box)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
from PIL import Image

from sdn3d.box_masks import MIN_FIT_IOU, box_at_point, click_box, no_vehicle
from sdn3d.math3d.camera import VKITTI_INTRINSICS as K

REAL = Path(__file__).resolve().parent / "data" / "0006_30-deg-right_00043.png"
SIZE = (K.width, K.height)


@pytest.fixture(scope="module")
def image():
    return torch.from_numpy(np.array(Image.open(REAL).convert("RGB"))).permute(2, 0, 1).float() / 255


def _why(box, **kw):
    return no_vehicle(box, K.fx, K.fy, K.cy, SIZE, **kw)


def test_clicks_on_the_two_cars_are_accepted_and_on_road_or_sky_refused(image):
    for click in ((565, 280), (810, 250)):  # the two near cars of the real frame
        box, found = click_box(image, click, K.fx, K.fy, K.cy)
        assert found and _why(box, found=found) is None and torch.equal(box, box_at_point(image, click, K.fx, K.fy,
                                                                                                K.cy))
    box, found = click_box(image, (300, 340), K.fx, K.fy, K.cy)  # empty road: it implied an ~888x175 "car"
    assert not found and _why(box, found=found).startswith("GrabCut found no object under the click")
    box, found = click_box(image, (600, 50), K.fx, K.fy, K.cy)  # the sky: a 7x6 px "car"
    assert "above the horizon" in _why(box, found=found)


def test_each_witness_names_its_reason():
    car = (466.0, 203.0, 666.0, 333.0)  # the red car's box
    assert _why(car, fit_iou=0.85) is None
    assert _why(car, fit_iou=0.0) == ("no car shape fits what GrabCut found in it (3D fit's silhouette IoU 0.00 < "
                                      f"{MIN_FIT_IOU})")
    assert _why(car, fit_missing="its mask has 3 pixels").startswith("GrabCut found too little in it (its mask has 3")
    assert "0.7 m tall" in _why((600.0, 196.0, 640.0, 203.0))  # 40x7 px at 75 m: 4 m wide but 0.7 m tall
    # A box cut off by the picture's edge is not refused for being small there (the rest of the car is outside).
    assert _why((0.0, 250.0, 20.0, 300.0)) is None and "wide" in _why((20.0, 250.0, 40.0, 300.0))
    # A box whose bottom is cut off: its distance is unknown, its size not checked; above the horizon it is refused.
    assert _why((100.0, 200.0, 1200.0, 375.0)) is None and "horizon" in _why((100.0, 20.0, 300.0, 150.0))


def test_sdn3d_edit_refuses_a_box_where_no_vehicle_is_unless_forced(tmp_path, capsys):
    """CLI ``objects:``: a box in the sky fails (exit 2) with the reason and how to add it anyway; force: true adds
    it."""
    from helpers.tiny_models import write_checkpoints

    from sdn3d.cli.edit import main

    ckpts = write_checkpoints(tmp_path / "ckpt")
    args = [f"input.image={REAL}", "proposals=boxes", f"checkpoints.geometric={ckpts['geometric']}",
            f"checkpoints.textural={ckpts['textural']}", "geometric.crop_size=32", "image_size=[312,96]", "threads=1"]
    spec = tmp_path / "sky.yaml"
    spec.write_text("objects:\n  - {box: [466, 203, 666, 333], class: Car}\n  - {box: [590, 40, 640, 60]}\n")
    assert main([*args, f"edits={spec}", f"output_dir={tmp_path / 'a'}"]) == 2
    err = capsys.readouterr().err
    assert ("objects[1] (box [590.0, 40.0, 640.0, 60.0], Car): no vehicle there: its bottom edge (row 60) is above "
            "the horizon (row 187)") in err and "To add it anyway, give it force: true" in err
    assert "objects[0]" not in err and not (tmp_path / "a").exists()
    spec.write_text("objects:\n  - {box: [466, 203, 666, 333], class: Car}\n"
                    "  - {box: [590, 40, 640, 60], force: true}\n")
    assert main([*args, f"edits={spec}", f"output_dir={tmp_path / 'b'}"]) == 0
