"""The template the test-time fit draws a vehicle with (issue 40): bounded by the object's class, and among fits of
one pose chosen by the fit rather than by noise in the appearance's belief (tests/test_fit_facing.py)."""

from __future__ import annotations

import pytest
import torch
from test_box_objects import HEIGHT, WORK, _render

from sdn3d.geometric.fit import FitRequest, FitSettings, allowed_templates, fit_many, fit_to_masks
from sdn3d.image_ops import mask_boxes
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import CLASS_TEMPLATES, TEMPLATE_CATEGORY, TEMPLATE_NAMES

SMALL = FitSettings(coarse_steps=3, fine_steps=2, coarse_size=16, fine_size=24, coarse_survivors=0, parts=1)
BOX_SHAPED = {TEMPLATE_NAMES.index(n) for n in CLASS_TEMPLATES["van"]}


def test_the_classes_templates_follow_the_templates_categories():
    assert set(CLASS_TEMPLATES["car"]) == {n for n in TEMPLATE_NAMES if TEMPLATE_CATEGORY[n] == "Car"}
    assert CLASS_TEMPLATES["van"] == ("van", "minibus", "bus")
    everything = allowed_templates(["truck", None], MeshBank.templates(), 2)  # no rule: every template
    assert bool(everything.all())
    assert bool(allowed_templates(["Van"], MeshBank.vehicle_shapes(), 1).all())  # not the templates: no rule
    with pytest.raises(ValueError, match="classes must name 2 objects"):
        allowed_templates(["Car"], MeshBank.templates(), 2)


def test_a_van_is_drawn_box_shaped_and_a_car_never_as_a_minibus_or_bus():
    """A sedan's silhouette named a van is fitted with the van, the minibus or the bus; a minibus's silhouette named
    a car with none of the Van category's templates; unnamed, each may be drawn with any."""
    _, masks = _render([0, 6], [(4.6, 1.45, 1.8), (6.0, 2.55, 2.0)], [-1.2, 0.5], [(-3.0, HEIGHT, 12.0),
                                                                                  (3.5, HEIGHT, 16.0)])
    boxes = mask_boxes(masks).float()
    named = fit_to_masks(masks, boxes, WORK, settings=SMALL, classes=["Van", "Car"])
    assert int(named.template[0]) in BOX_SHAPED
    assert TEMPLATE_CATEGORY[TEMPLATE_NAMES[int(named.template[1])]] == "Car"
    # a prediction of a template the class does not allow does not start the fit with it
    start = fit_to_masks(masks, boxes, WORK, settings=SMALL, classes=["Van", "Car"],
                         start_template=torch.tensor([0, 6]), start_ry=torch.tensor([-1.2, 0.5]),
                         start_location=torch.tensor([[-3.0, HEIGHT, 12.0], [3.5, HEIGHT, 16.0]]),
                         start_dims=torch.tensor([[4.6, 1.45, 1.8], [6.0, 2.55, 2.0]]))
    assert int(start.template[0]) in BOX_SHAPED and int(start.template[1]) not in (6, 7)
    # fit_many carries each request's classes (a request without them: any template)
    both = fit_many([FitRequest(masks[:1], boxes[:1], classes=["van"]), FitRequest(masks[1:], boxes[1:])], WORK,
                    settings=SMALL)
    assert int(both[0].template[0]) in BOX_SHAPED
