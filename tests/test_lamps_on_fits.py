"""A semantic proposal's lamps read again on the part of its mask that its fitted shape covers (issue 40, session 24).

The semantic branch's masks spill past a car onto the road, a lane marking, a sign; the lamp cue read those pixels
(a lane marking below a red van as its "headlights", a red sign above a car as a second band of red that made its
tail lamps unusable) and the fit turned the car end for end. :func:`sdn3d.derender._lamps_on_fits` reads each fitted
proposal's lamps again on its mask cut to its fitted 3D shape, and :func:`sdn3d.derender.derender` fits the proposals
whose reading changed again with it; ground-truth masks (an oracle) are never read again.
"""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import geometric_net

import sdn3d.derender as dr
from sdn3d.geometric.facing import APPEARANCE_KEYS, FRONT_KEYS, Appearance
from sdn3d.geometric.lamps import LampCue, red_lamps, white_lamps
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.transforms import bottom_to_center
from sdn3d.meshes.bank import default_bank
from sdn3d.models import Models
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes

WORK = Intrinsics(fx=150.0, fy=150.0, cx=80.0, cy=32.0, width=160, height=64)


def _red_van_back(stray_white: bool) -> tuple[torch.Tensor, torch.Tensor, tuple[torch.Tensor, ...], torch.Tensor]:
    """``(image, masks, geometry, shape)``: a red car seen from behind (template 0, 6 m ahead, alpha = -90 degrees),
    its body red, its rear window dark; its proposal's mask is its silhouette ``shape`` and, with ``stray_white``, a
    block of road left of its lower half with a white lane marking in it and a red neighbour's edge beyond it, as a
    semantic proposal spills (the marking between red on its rows: the headlight test's body rule,
    :func:`~sdn3d.geometric.lamps.in_the_body`, keeps it; only the cut to the fitted shape drops it)."""
    geometry = (torch.tensor([0]), torch.tensor([[3.9, 1.5, 1.7]], dtype=torch.float64),
                torch.tensor([-math.pi / 2], dtype=torch.float64), torch.tensor([[0.0, 1.6, 6.0]], dtype=torch.float64),
                torch.zeros(1, 64, 3))
    template, dims, ry, location, phi = geometry
    verts, faces = pose_meshes(default_bank(), template, dims.float(), ry.float(),
                               bottom_to_center(location, dims[:, 1]).float(), phi)
    shape = rasterize_meshes(verts, faces, WORK.matrix().float(), RasterSettings((64, 160))).mask
    image = torch.full((3, 64, 160), 0.4)
    image[:, shape[0]] = torch.tensor([0.75, 0.08, 0.08])[:, None]
    rows = shape[0].any(1).nonzero().flatten()
    cols = shape[0].any(0).nonzero().flatten()
    top, bottom, left, right = int(rows.min()), int(rows.max()), int(cols.min()), int(cols.max())
    image[:, top:top + (bottom - top) // 3, left + 3:right - 3] = 0.05  # the rear window: clear air's darks
    masks = shape.clone()
    if stray_white:
        low = (top + bottom) // 2 + 2
        masks[0, low:bottom + 1, left - 7:left] = True  # the road beside the car
        image[:, low:bottom + 1, left - 5:left - 3] = 0.95  # a lane marking on it
        image[:, low:bottom + 1, left - 7:left - 5] = torch.tensor([0.75, 0.08, 0.08])[:, None, None]  # red beyond
    return image, masks, geometry, shape


def _models() -> Models:
    torch.manual_seed(0)
    return Models(geometric=GeometricPredictor(geometric_net(), lamp_cue=LampCue(min_mask=50)), crop_size=48,
                  margin=0.1)


def _appearance(models: Models, image: torch.Tensor, masks: torch.Tensor) -> Appearance:
    """The reading :func:`sdn3d.derender._geometry` gives the proposal (the predictor's, on its whole mask)."""
    _, appearance = dr._geometry(image, WORK, masks, torch.tensor([12001]), None, models, 1, None)
    return appearance


def test_read_lamps_is_the_predictors_reading():
    from sdn3d.box_objects import fitted_silhouettes
    from sdn3d.geometric.lamps import read_lamps

    models = _models()
    image, masks, geometry, shape = _red_van_back(stray_white=True)
    assert torch.equal(fitted_silhouettes(WORK, geometry, torch.tensor([0])), shape)  # the test's own drawing
    appearance = _appearance(models, image, masks)
    boxes = dr.pixel_centre_boxes(dr.mask_boxes(masks))
    windows = dr._windows(boxes, models)
    crop = dr.crop_windows(image[None], windows, 48, "bilinear")
    mask = dr.crop_windows(masks[:, None].float(), windows, 48, "nearest")
    red, white = read_lamps(crop * mask, mask, models.geometric.lamp_cue)
    for keys, reading in ((("lamp_present", "lamp_usable", "lamp_offset"), red), (FRONT_KEYS, white)):
        for k, v in zip(keys, reading, strict=True):
            torch.testing.assert_close(appearance.values[k], v)
    cue = models.geometric.lamp_cue
    torch.testing.assert_close(torch.stack(red), torch.stack(red_lamps(crop * mask, mask, cue)))
    torch.testing.assert_close(torch.stack(white), torch.stack(white_lamps(crop * mask, mask, cue)))


def test_a_lane_marking_the_mask_spills_onto_is_no_headlight_once_the_mask_is_cut_to_the_fitted_shape():
    models = _models()
    image, masks, geometry, shape = _red_van_back(stray_white=True)
    appearance = _appearance(models, image, masks)
    assert bool(appearance.values["front_usable"][0]) and bool(appearance.values["front_present"][0])
    reread, changed = dr._lamps_on_fits(image, WORK, masks, None, torch.tensor([0]), geometry, appearance, models,
                                        None)
    assert changed.tolist() == [0]
    assert bool(reread.values["front_usable"][0]) and not bool(reread.values["front_present"][0])
    for k in APPEARANCE_KEYS[:2]:  # the net's yaw and the ray are kept
        torch.testing.assert_close(reread.values[k], appearance.values[k])
    # The back view's belief: "no headlights on a red body" says back (alpha = -90 degrees); the marking said front.
    alpha = torch.tensor([[-math.pi / 2, math.pi / 2]])
    ry = alpha + appearance.values["ray"][:, None]
    before = appearance.belief(bins=False)(ry)[0]
    after = reread.belief(bins=False)(ry)[0]
    assert float(after[0] - after[1]) > 0 > float(before[0] - before[1]) - 0.5  # the back now believed more


def test_a_mask_that_its_fitted_shape_covers_reads_as_before():
    models = _models()
    image, masks, geometry, shape = _red_van_back(stray_white=False)
    appearance = _appearance(models, image, masks)
    reread, changed = dr._lamps_on_fits(image, WORK, masks, None, torch.tensor([0]), geometry, appearance, models,
                                        None)
    assert len(changed) == 0
    for k, v in appearance.values.items():
        torch.testing.assert_close(reread.values[k], v)


@pytest.mark.fits
@pytest.mark.parametrize("source", ["semantic", "gt"])
def test_derender_chooses_again_for_the_semantic_proposals_whose_reading_changed(monkeypatch, source):
    """The proposals whose reading on the cut masks changed are chosen again among the first fit's hypotheses under
    that reading (what fitting them again gives); ground-truth masks (an oracle) are not read again."""
    from sdn3d.derender import GroundTruth, derender
    from sdn3d.geometric.fit import FitSettings
    from sdn3d.semantic.predict import Segmentation

    image, masks, _, _ = _red_van_back(stray_white=True)
    instances = torch.where(masks[0], 12001, 0)
    semantic = torch.where(masks[0], 12, 3)

    class Stub:
        classes = None

        def __call__(self, image):
            return Segmentation(semantic[None], instances[None], torch.zeros(1, 14, 64, 160))

    models = _models()
    from sdn3d.labels import CLASS_LISTS
    Stub.classes = CLASS_LISTS["vkitti"]
    models = Models(Stub(), models.geometric, crop_size=48, margin=0.1)
    gt = GroundTruth("frame", "vkitti", semantic, instances, {1: dr.pixel_centre_boxes(dr.mask_boxes(masks))[0]})
    calls = []
    reads = []
    fit_proposals = dr.fit_proposals

    def spy_fit(intr, masks, ids, rows, geometry, settings, appearance=None, *a, **k):
        calls.append((rows.tolist(), None if appearance is None else appearance.values["front_present"].tolist()))
        return fit_proposals(intr, masks, ids, rows, geometry, settings, appearance, *a, **k)

    lamps_on_fits = dr._lamps_on_fits

    def spy_read(*a, **k):
        reads.append(a[4].tolist())
        return lamps_on_fits(*a, **k)

    chosen = []
    choose_again = dr.choose_proposals_again

    def spy_choose(first, ids, rows, again, geometry, settings, appearance):
        chosen.append((again.tolist(), appearance.values["front_present"][again].tolist()))
        return choose_again(first, ids, rows, again, geometry, settings, appearance)

    monkeypatch.setattr(dr, "fit_proposals", spy_fit)
    monkeypatch.setattr(dr, "_lamps_on_fits", spy_read)
    monkeypatch.setattr(dr, "choose_proposals_again", spy_choose)
    fit = FitSettings(coarse_steps=3, fine_steps=3, keep=1, camera_height=1.6, poor_iou=0.0)
    scene = derender(image, WORK, models, source, gt, min_pixels=1, fit=fit)
    if source == "gt":
        assert reads == [] and len(calls) == 1 and chosen == []
        return
    assert [c[0] for c in calls] == [[0]] and reads == [[0]]  # fitted once, read again on the cut mask ...
    assert calls[0][1] == [True] and chosen == [([0], [False])]  # ... the marking's "headlights", then none
    assert len(scene.meta["fits"]) == 1 and scene.meta["fits"][0]["fit_iou"] is not None


def test_choosing_again_is_fitting_again_under_the_new_belief():
    """The fine stage's hypotheses and fits do not read the yaw belief: choosing again among them under another
    belief (:func:`~sdn3d.geometric.fit.choose_again`) gives what fitting again with it gives, on the same road."""
    from sdn3d.geometric.fit import FitSettings, choose_again, fit_to_masks

    _, masks, geometry, _ = _red_van_back(stray_white=False)
    boxes = dr.mask_boxes(masks).float()
    settings = FitSettings(coarse_steps=3, fine_steps=3, keep=2, camera_height=None, camera_height_range=(0.01, 100.0),
                           facing_tie=5.0)  # the belief decides the end
    starts = {"start_ry": geometry[2].float(), "start_dims": geometry[1].float(), "start_template": geometry[0],
              "start_location": geometry[3].float()}

    def facing(sign: float):  # believes the fits facing one way
        return lambda ry: sign * torch.cos(ry - starts["start_ry"][:, None])

    first = fit_to_masks(masks, boxes, WORK, settings=settings, yaw_belief=facing(1.0), **starts)
    again = fit_to_masks(masks, boxes, WORK, settings=settings, yaw_belief=facing(-1.0), **starts)
    chosen = choose_again(first.choice, facing(-1.0))
    assert int(first.hypothesis[0]) != int(again.hypothesis[0])  # the belief decided
    for name in ("template", "hypothesis", "fitted"):
        assert torch.equal(getattr(chosen, name), getattr(again, name)), name
    for name in ("dims", "ry", "location", "phi", "iou", "loss"):
        torch.testing.assert_close(getattr(chosen, name), getattr(again, name), rtol=1e-5, atol=1e-6, msg=name)
    assert chosen.camera_height == again.camera_height == first.camera_height
