"""The red tail-lamp test reads the band under a semantic proposal's mask (issue 40, session 10's semflip).

The semantic branch's masks often stop above a car's tail lamps; the lamp cue then read "no red lamps: a front" and
the fit turned the car end for end. For semantic proposals whose mask shows no red lamps the red test reads the mask
and the band under it (:func:`sdn3d.proposal_fit.unsure_below`), the headlights' test does not, and nothing changes
for ground-truth masks.
"""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import geometric_net, semantic_net, textural_spec

from sdn3d.data import vkitti1
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.derender import derender
from sdn3d.geometric.lamps import LampCue, face_by_lamps, face_by_reading, red_lamps, white_lamps
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.models import Models
from sdn3d.proposal_fit import unsure_below
from sdn3d.semantic.predict import Segmentation, SemanticPredictor
from sdn3d.textural.renderer import TexturalRenderer

SIZE = (160, 64)


def _back_view(n: int = 2, size: int = 32) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(crop, mask, tail)``: grey car backs whose red tail lamps (rows 21-23, both corners) lie under the mask
    (rows 4-19), inside the tail band (rows 4-25)."""
    crop = torch.full((n, 3, size, size), 0.45)
    crop[:, :, 6:10, 8:24] = 0.08  # the rear window: the crop's darks, clear air
    crop[:, :, 21:24, 6:10] = torch.tensor([0.8, 0.1, 0.1])[:, None, None]
    crop[:, :, 21:24, 22:26] = torch.tensor([0.8, 0.1, 0.1])[:, None, None]
    mask = torch.zeros(n, 1, size, size)
    mask[:, :, 4:20, 5:27] = 1
    tail = torch.zeros(n, 1, size, size)
    tail[:, :, 4:26, 5:27] = 1
    return crop, mask, tail


def test_face_by_reading_turns_as_face_by_lamps():
    torch.manual_seed(0)
    crop, mask, _ = _back_view(6)
    crop[3:] = torch.rand(3, 3, 32, 32)  # and three crops of noise
    mask[0, :, 19:25] = 1  # the first three see their lamps
    mask[1:3, :, 4:26, 5:27] = 1
    cue = LampCue(min_mask=50)
    ry, ray = torch.tensor([1.5, 1.2, -1.4, 1.5, -1.5, 0.3]), torch.rand(6) * 0.4 - 0.2  # fronts and a back
    reading = face_by_reading(ry, ray, red_lamps(crop, mask, cue), white_lamps(crop, mask, cue), cue)
    torch.testing.assert_close(reading, face_by_lamps(ry, ray, crop, mask, cue))
    assert not torch.allclose(reading[:2], ry[:2]) and torch.allclose(reading[2], ry[2])  # the fronts turned


def test_the_tail_mask_reads_red_lamps_under_the_mask_and_the_net_sees_the_same_crop():
    torch.manual_seed(0)
    predictor = GeometricPredictor(geometric_net(), lamp_cue=LampCue(min_mask=50))
    crop, mask, tail = _back_view()
    box = torch.tensor([[40.0, 20.0, 60.0, 36.0], [80.0, 22.0, 96.0, 34.0]])
    intr = torch.tensor([[100.0, 100.0, 80.0, 32.0]]).expand(2, 4)
    plain = predictor.predict(crop * mask, mask, box, intr)
    read = predictor.predict(crop, mask, box, intr, tail_mask=tail)
    assert not plain["lamp_present"].any() and plain["lamp_usable"].all()  # "no red lamps": a front
    assert read["lamp_present"].all() and read["lamp_usable"].all()
    assert read["lamp_offset"].abs().max() < 0.05  # both corners: centred
    for key in ("net_ry", "dims", "location", "front_present", "front_usable", "front_offset"):
        torch.testing.assert_close(read[key], plain[key])  # the net's input and the headlights' reading as before
    # A mask that shows red lamps (here a neighbour's, high on the right, below the top LampCue.lamp_top of the mask's
    # rows, whose red is never read) is read as before: the band is not added.
    crop[:, :, 9:11, 23:26] = torch.tensor([0.8, 0.1, 0.1])[:, None, None]
    shown = predictor.predict(crop * mask, mask, box, intr)
    both = predictor.predict(crop, mask, box, intr, tail_mask=tail)
    assert shown["lamp_present"].all() and shown["lamp_offset"].min() > 0.2
    for key in ("lamp_present", "lamp_usable", "lamp_offset"):
        torch.testing.assert_close(both[key], shown[key])
    # Red the mask shows but cannot use (two rows of red: the neighbour's and a low one): the band's reading instead.
    crop[:, :, 17:19, 6:9] = torch.tensor([0.8, 0.1, 0.1])[:, None, None]
    spread = predictor.predict(crop * mask, mask, box, intr)
    wider = predictor.predict(crop, mask, box, intr, tail_mask=tail)
    assert spread["lamp_present"].all() and not spread["lamp_usable"].any()
    band = red_lamps(crop * tail, tail, LampCue(min_mask=50))
    for key, value in zip(("lamp_present", "lamp_usable", "lamp_offset"), band, strict=True):
        torch.testing.assert_close(wider[key], value)
    crop[:, :, 9:11, 23:26] = 0.45
    crop[:, :, 17:19, 6:9] = 0.45
    # A back view (alpha = -90 degrees) the net took for a front is turned end for end by the lamps under the mask.
    front = torch.full((2,), math.pi / 2)
    red = (read["lamp_present"], read["lamp_usable"], read["lamp_offset"])
    assert torch.allclose(face_by_reading(front, torch.zeros(2), red, None, predictor.lamp_cue).abs(),
                          torch.full((2,), math.pi / 2), atol=1e-5)
    assert torch.allclose(face_by_reading(front, torch.zeros(2), red, None, predictor.lamp_cue), -front, atol=1e-5)


class _Spy(GeometricPredictor):
    """Records the lamp masks the geometric branch is given."""

    def __init__(self, net) -> None:
        super().__init__(net)
        self.calls: list[dict] = []

    def predict(self, crop, mask, box, intrinsics, *args, lamp_mask=None, tail_mask=None, image_width=None):
        self.calls.append({"crop": crop, "mask": mask, "lamp_mask": lamp_mask, "tail_mask": tail_mask})
        return super().predict(crop, mask, box, intrinsics, *args, lamp_mask=lamp_mask, tail_mask=tail_mask,
                               image_width=image_width)


class _CutSemantic:
    """A semantic branch whose instances are the ground truth's with each object's lowest third of rows cut off
    (labelled road), as the semantic branch's masks often stop above a car's bottom."""

    def __init__(self, gt_instances: torch.Tensor, gt_semantic: torch.Tensor) -> None:
        self.classes = SemanticPredictor(semantic_net(), "vkitti").classes
        inst, label = gt_instances.clone(), gt_semantic.clone()
        for i in inst.unique().tolist():
            if i < INSTANCE_DIVISOR:
                continue
            rows = (inst == i).any(1).nonzero().flatten()
            cut = int(rows.max()) - (int(rows.max()) - int(rows.min()) + 1) // 3
            below = (inst == i) & (torch.arange(inst.shape[0])[:, None] > cut)
            inst[below], label[below] = 0, 5
        self.instance, self.label = inst, label

    def __call__(self, image: torch.Tensor) -> Segmentation:
        return Segmentation(self.label[None], self.instance[None], torch.zeros(1, len(self.classes), *self.label.shape))


@pytest.fixture(scope="module")
def frame(tiny_synth):
    record = vkitti1.read_frames(tiny_synth)[4]
    return record, load_frame(record, SIZE, semantic=True, instances=True)


def test_semantic_proposals_read_the_tail_band_and_ground_truth_masks_do_not(frame):
    record, f = frame
    gt = ground_truth(record, SIZE)
    torch.manual_seed(0)
    spy = _Spy(geometric_net())
    models = Models(_CutSemantic(gt.instances, gt.semantic), spy, TexturalRenderer(textural_spec()), crop_size=32,
                    margin=0.1)
    scene = derender(f.image, f.intrinsics, models, "semantic", gt, min_pixels=1)
    (call,) = spy.calls
    assert scene.meta["proposals"] == "semantic" and call["tail_mask"] is not None
    whole, tail = call["mask"] > 0.5, call["tail_mask"] > 0.5
    assert bool((whole <= tail).all()) and int(tail.sum()) > int(whole.sum())  # the mask and the band under it
    # The band is unsure_below's, read over the same windows; the net's crop is the unmasked one (masked inside).
    masks = scene.objects.mask[scene.objects.template_id >= 0]
    assert int(unsure_below(scene.objects.mask).sum()) > 0 and len(masks) == len(tail)
    assert bool((call["crop"][(~whole).expand_as(call["crop"])] != 0).any())
    spy.calls.clear()
    derender(f.image, f.intrinsics, models, "gt", gt, min_pixels=1)
    (call,) = spy.calls
    assert call["tail_mask"] is None and bool((call["crop"][(call["mask"] < 0.5).expand_as(call["crop"])] == 0).all())
