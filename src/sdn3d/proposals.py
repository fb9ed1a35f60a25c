"""Where a de-render's objects and semantics come from: :class:`Proposals`, and the one choice of sources
(:func:`choose_sources`) that :func:`sdn3d.derender.derender` follows and the tools ask in advance
(:meth:`Proposals.needs_semantic_branch`).

A user's string (``proposals=`` of ``sdn3d-edit``, ``sdn3d-app``, a config) becomes a :class:`Proposals` at the edge
(:meth:`Proposals.parse`); a :class:`Proposals` is a ``str`` equal to its value, so records and messages that wrote
the string write the same.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum

import torch
from torch import Tensor

from sdn3d.box_objects import box_fits
from sdn3d.errors import UserInputError

__all__ = ["PROPOSALS", "Proposals", "Sources", "choose_sources", "predicted_masks"]


class Proposals(StrEnum):
    """``auto``: semantics from the semantic branch (the ground truth's without one), masks from the ground-truth
    instance map if there is one, else the branch's instance head; ``gt``: both from the frame's ground truth (an
    oracle); ``semantic``: both from the semantic branch; ``boxes``: the objects are the boxes a person named alone
    (semantics from the branch, else the ground truth, else none)."""

    AUTO = "auto"
    GT = "gt"
    SEMANTIC = "semantic"
    BOXES = "boxes"

    @classmethod
    def parse(cls, value: object, error: type[Exception] = ValueError) -> Proposals:
        """``value`` (a user's string, or a :class:`Proposals`) as a :class:`Proposals`.

        Raises:
            error: naming the values, for anything else.
        """
        try:
            return cls(value)
        except ValueError:
            raise error(f"proposals must be one of {', '.join(PROPOSALS)}, got {value!r}") from None

    def needs_semantic_branch(self, ground_truth: bool) -> bool:
        """Whether a de-render cannot do without the semantic branch, given whether the input has a ground truth
        (a dataset frame) that can stand in for it: not with ``boxes``; with ``semantic``; else without one."""
        if self is Proposals.BOXES:
            return False
        return not ground_truth or self is Proposals.SEMANTIC


#: The values, in the order messages list them.
PROPOSALS = tuple(p.value for p in Proposals)


@dataclass(frozen=True)
class Sources:
    """What a de-render takes its masks and its semantic map from (``scene.meta['proposals']`` / ``['semantic']``).

    Attributes:
        masks: ``'gt'`` (the oracle), ``'semantic'`` (the branch's instance head) or ``'boxes'`` (no proposal but the
            boxes).
        semantics: ``'branch'``, ``'gt'`` or ``'none'`` (every pixel 255, ignore).
    """

    masks: str
    semantics: str

    @property
    def runs_branch(self) -> bool:
        """Whether the semantic branch runs (for its semantics or its masks)."""
        return self.semantics == "branch" or self.masks == "semantic"


def choose_sources(proposals: Proposals, semantic_model: bool, ground_truth: bool, gt_instances: bool,
                   gt_key: str = "") -> Sources:
    """The one choice of where a de-render's masks and semantics come from (:class:`Proposals`), given what there
    is: a semantic model, a ground truth, and whether it has an instance map (``gt_key`` names it in messages).

    Raises:
        UserInputError: a source the choice needs is missing.
    """
    if proposals is Proposals.BOXES:  # the boxes alone; semantics from the branch, else the ground truth, else none
        return Sources("boxes", "branch" if semantic_model else "gt" if ground_truth else "none")
    use_branch = proposals is Proposals.SEMANTIC or (proposals is Proposals.AUTO and semantic_model)
    use_gt_masks = proposals is Proposals.GT or (proposals is Proposals.AUTO and ground_truth and gt_instances)
    if (use_branch or not use_gt_masks) and not semantic_model:
        raise UserInputError(f"proposals={proposals.value!r} needs a semantic model"
                             + ("" if use_branch else " (no ground truth with an instance map was given)"))
    if (not use_branch or use_gt_masks) and not ground_truth:
        raise UserInputError(f"proposals={proposals.value!r} needs the frame's ground truth (ground_truth=)")
    if use_gt_masks and not gt_instances:
        raise UserInputError(f"proposals={proposals.value!r}: ground truth {gt_key} has no instance map")
    return Sources("gt" if use_gt_masks else "semantic", "branch" if use_branch else "gt")


def predicted_masks(meta: Mapping, instance_ids: Tensor) -> Tensor:
    """``(N,)`` bool: which objects of ``instance_ids (N,)`` of a de-rendered scene (``meta``: its ``SceneCode.meta``)
    have masks the semantic branch predicted: the scene's masks came from the branch (``meta['proposals']``, the
    source :func:`choose_sources` chose) and the object was not named by a box (``meta['boxes']``, whose masks
    GrabCut found in the box)."""
    predicted = torch.full((len(instance_ids),), meta.get("proposals") == "semantic", dtype=torch.bool)
    boxes = [fit.instance_id for fit in box_fits(meta)]
    if boxes and len(instance_ids):
        predicted &= ~torch.isin(instance_ids.cpu(), torch.tensor(boxes, dtype=instance_ids.dtype))
    return predicted
