"""The traffic side's weight on a car cut by the image border (issue 40, session 36 flips): on a car that the left or
right border cuts, an absence of lamps is replaced by the side's evidence ``-side_weight * side * sin(alpha)``
(``LampCue.side_weight``, apart from ``absent_weight``, which keeps weighing the absence on whole cars). Below
``-flip_below`` it can no longer turn the branch's own yaw."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric.lamps import LampCue, evidence_of, face_by_reading

# A back view whose back (its near end) lies to the right of its middle, and its reverse (ray 0: ry = alpha).
BACK_RIGHT = -math.pi / 2 - 0.6
FRONT_RIGHT = BACK_RIGHT + math.pi
NO_LAMPS = (torch.tensor([False]), torch.tensor([True]), torch.zeros(1))


def test_the_side_weight_weighs_the_side_on_cut_cars_and_the_absence_weight_the_rest():
    ry = torch.tensor([[BACK_RIGHT, FRONT_RIGHT]])
    sin = torch.sin(ry)
    for weight in (0.0, 0.2, 0.5, 1.0):
        cue = LampCue(min_mask=0, side_weight=weight, absent_weight=0.9)
        cut = evidence_of(*NO_LAMPS, ry, cue, border=torch.tensor([1.0]))
        torch.testing.assert_close(cut, -weight * sin)  # cut by the right border: the back, at side_weight
        torch.testing.assert_close(evidence_of(*NO_LAMPS, ry, cue, border=torch.tensor([-1.0])), weight * sin)
        whole = evidence_of(*NO_LAMPS, ry, cue, border=torch.tensor([0.0]))
        torch.testing.assert_close(whole, 0.9 * sin)  # not cut: the absence, at absent_weight
    # a red body without headlights, cut: the side's evidence too
    front = (torch.tensor([False]), torch.tensor([True]), torch.zeros(1))
    unread = (torch.tensor([False]), torch.tensor([False]), torch.zeros(1))
    cue = LampCue(min_mask=0, side_weight=0.2)
    torch.testing.assert_close(evidence_of(*unread, ry, cue, front=front, border=torch.tensor([1.0])), -0.2 * sin)


def test_a_side_weight_below_flip_below_no_longer_turns_the_branchs_yaw():
    """A front view, as the branch believes, of a car cut by the right border without lamps: at the default the
    side's rule turns it to a back; at ``-flip_below`` (0.3) or less the evidence never gets below ``flip_below``."""
    ry, ray, border = torch.tensor([FRONT_RIGHT]), torch.zeros(1), torch.tensor([1.0])
    turned = face_by_reading(ry, ray, NO_LAMPS, None, LampCue(min_mask=0), border)
    assert math.sin(float(turned[0])) < -0.5
    for weight in (0.0, 0.3):
        kept = face_by_reading(ry, ray, NO_LAMPS, None, LampCue(min_mask=0, side_weight=weight), border)
        torch.testing.assert_close(kept, ry)


@pytest.mark.parametrize("weight", [-0.1, 1.5, math.nan, True, "0.5", None])
def test_a_side_weight_outside_0_1_is_refused_by_name(weight):
    with pytest.raises(ValueError, match="LampCue.side_weight"):
        LampCue(side_weight=weight)
