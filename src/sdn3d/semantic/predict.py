"""Inference API of the semantic branch, without Lightning: image in, label map and instance map out.

    from sdn3d.semantic import SemanticPredictor
    predictor = SemanticPredictor.from_checkpoint("outputs/train/semantic/<run>/checkpoints/last.ckpt")
    result = predictor(image)            # image (3, H, W) or (B, 3, H, W) float in [0, 1]
    result.label                         # (B, H, W) int64 class ids
    result.instance                      # (B, H, W) int64 class_id * 1000 + k, 0 = none

A checkpoint written by ``lightning_modules.SemanticModule``, or its inference export
(:mod:`sdn3d.inference_export`), is read with ``torch.load(weights_only=True)``: its ``hyper_parameters``
rebuild the network and the grouping settings, its ``state_dict`` (prefix ``net.``) fills the network.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.inference_export import BranchWeights, load_branch_weights, module_with_weights
from sdn3d.labels import SemanticClass, class_list, thing_class_ids
from sdn3d.nets.drn import DRNSeg
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.tta import flip_averaged_outputs

__all__ = ["Segmentation", "SemanticPredictor", "segment", "network_size", "GROUPING_DEFAULTS"]

#: Default grouping settings (``SemanticModule`` hyper-parameters of the same names override them):
#: centre detection (``center_threshold``, ``nms_kernel``, ``top_k``), the smallest instance (``min_area``), which
#: pixels are things (``thing_odds``: :func:`~sdn3d.semantic.panoptic.thing_label`; None: the arg-max) and the split of
#: two vehicles under one centre (``split_separation``; None: off), the instances' spatially separate parts that vote
#: elsewhere (``part_separation``; None: kept); :mod:`sdn3d.semantic.panoptic`'s module doc says why. ``thing_odds``,
#: ``split_separation`` and ``part_separation`` were chosen on the Table 1 tuning trees with the demo's weights
#: (docs/results/2026-11-30_cpu/session19/inst, docs/results/2026-11-30_cpu/session20/comp).
GROUPING_DEFAULTS = {"center_threshold": 0.1, "nms_kernel": 7, "top_k": 50, "min_area": 16, "thing_odds": 0.6,
                     "split_separation": 4.0, "part_separation": 4.0}
_STATE_PREFIX = "net."


@dataclass
class Segmentation:
    """Output of :class:`SemanticPredictor` (all ``(B, H, W)`` at the input image's size).

    Attributes:
        label: int64 semantic class per pixel (instance pixels carry their instance's class).
        instance: int64 ``class_id * 1000 + k``, 0 = no instance (all zeros without an instance head).
        probability: float32 ``(B, C, H, W)`` softmax of the semantic logits.
    """

    label: Tensor
    instance: Tensor
    probability: Tensor


class SemanticPredictor:
    """A trained :class:`~sdn3d.nets.drn.DRNSeg` with its class list and grouping settings.

    Args:
        net: the network (put in eval mode).
        classes: the class list (or its name, e.g. ``'vkitti'``).
        thing_classes: class ids split into instances; None = classes with ``has_instances``.
        grouping: overrides of :data:`GROUPING_DEFAULTS`.
        image_size: optional working size ``(W, H)``: images are resized to it for the network
            and the maps resized back (nearest) to the image size; None: :func:`network_size` of
            ``trained_size``.
        trained_size: optional ``(W, H)`` of the frames the branch trained on (its export's or run's,
            :func:`sdn3d.models.semantic_trained_size`): without ``image_size``, each image is resized to
            :func:`network_size` (about that many pixels, the image's aspect), where its objects have about the scale
            the network learnt; None (and no ``image_size``) runs at the image size.
        flip: test-time augmentation: average the outputs on the image and on its mirror image
            (:func:`~sdn3d.semantic.tta.flip_averaged_outputs`; twice the compute).
    """

    def __init__(
        self,
        net: DRNSeg,
        classes: str | Sequence[SemanticClass],
        thing_classes: Sequence[int] | None = None,
        grouping: Mapping[str, Any] | None = None,
        image_size: tuple[int, int] | None = None,
        flip: bool = False,
        trained_size: tuple[int, int] | None = None,
    ) -> None:
        self.net = net.eval()
        self.flip = bool(flip)
        self.classes = class_list(classes)
        if len(self.classes) != net.num_classes:
            raise ValueError(f"classes has {len(self.classes)} entries but the network predicts {net.num_classes}")
        self.thing_classes = thing_class_ids(self.classes) if thing_classes is None else list(thing_classes)
        unknown = set(grouping or {}) - set(GROUPING_DEFAULTS)
        if unknown:
            raise ValueError(f"grouping has unknown keys {sorted(unknown)}; known: {sorted(GROUPING_DEFAULTS)}")
        self.grouping = {**GROUPING_DEFAULTS, **dict(grouping or {})}
        self.image_size = None if image_size is None else (int(image_size[0]), int(image_size[1]))
        self.trained_size = None if trained_size is None else (int(trained_size[0]), int(trained_size[1]))

    @classmethod
    def from_checkpoint(cls, path: str | os.PathLike, map_location: str | torch.device = "cpu",
                        image_size: tuple[int, int] | None = None, flip: bool | None = None) -> SemanticPredictor:
        """Load a ``SemanticModule`` Lightning checkpoint or its inference export (``weights_only=True``);
        ``flip=None`` takes the module's ``test_flip`` setting."""
        return cls.from_weights(load_branch_weights(path, "semantic", map_location), map_location, image_size, flip)

    @classmethod
    def from_weights(cls, weights: BranchWeights, map_location: str | torch.device = "cpu",
                     image_size: tuple[int, int] | None = None, flip: bool | None = None,
                     trained_size: tuple[int, int] | None = None) -> SemanticPredictor:
        """The predictor of loaded semantic-branch weights (:func:`~sdn3d.inference_export.load_branch_weights`;
        the network takes over their tensors)."""
        hp = dict(weights.hyper_parameters)
        classes = class_list(hp.get("classes", "vkitti"))

        def build() -> DRNSeg:
            return DRNSeg(len(classes), arch=hp.get("arch", "drn_d_22"), instance_head=hp.get("instance_head", True),
                          head_channels=hp.get("head_channels", 128), pretrained=None,
                          decoder=hp.get("decoder", "bilinear"),
                          decoder_channels=hp.get("decoder_channels", (64, 32, 16)),
                          **({"channels": hp["channels"]} if hp.get("channels") else {}))

        state = {k[len(_STATE_PREFIX):]: v for k, v in weights.state_dict.items() if k.startswith(_STATE_PREFIX)}
        net = module_with_weights(build, state, weights.path).to(map_location)
        things = hp.get("thing_classes")
        return cls(net, classes, thing_classes=None if things is None else thing_class_ids(classes, things),
                   grouping={k: hp[k] for k in GROUPING_DEFAULTS if k in hp}, image_size=image_size,
                   flip=bool(hp.get("test_flip", False)) if flip is None else flip, trained_size=trained_size)

    def to(self, device: str | torch.device) -> SemanticPredictor:
        self.net.to(device)
        return self

    @torch.no_grad()
    def __call__(self, image: Tensor) -> Segmentation:
        """Segment ``image`` ``(3, H, W)`` or ``(B, 3, H, W)`` float in [0, 1] (a uint8 image is scaled)."""
        if image.dim() == 3:
            image = image.unsqueeze(0)
        if image.dim() != 4 or image.shape[1] != 3:
            raise ValueError(f"image must be (3, H, W) or (B, 3, H, W), got {tuple(image.shape)}")
        if image.dtype == torch.uint8:
            image = image.float() / 255.0
        device = next(self.net.parameters()).device
        image = image.to(device=device, dtype=torch.float32)
        size = image.shape[-2:]
        target = self.image_size
        if target is None and self.trained_size is not None:
            target = network_size((size[1], size[0]), self.trained_size)
        if target is not None and (size[1], size[0]) != target:
            work = F.interpolate(image, size=(target[1], target[0]), mode="bilinear", align_corners=False,
                                 antialias=True)
        else:
            work = image
        out = flip_averaged_outputs(self.net, work) if self.flip else self.net(work)
        probability = out["logits"].softmax(1)
        label = probability.argmax(1)
        if "center" in out and self.thing_classes:
            g = self.grouping
            instance, label = group_vehicles(label, probability, out["center"], out["offset"], self.thing_classes,
                                             thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                                             nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"],
                                             split_separation=g["split_separation"],
                                             part_separation=g["part_separation"])
        else:
            instance = torch.zeros_like(label)
        if work.shape[-2:] != size:
            probability = F.interpolate(probability, size=size, mode="bilinear", align_corners=False)
            label = F.interpolate(label[:, None].float(), size=size, mode="nearest")[:, 0].long()
            instance = F.interpolate(instance[:, None].double(), size=size, mode="nearest")[:, 0].long()
        return Segmentation(label=label, instance=instance, probability=probability)


def network_size(size: tuple[int, int], trained_size: tuple[int, int]) -> tuple[int, int]:
    """``(W, H)`` the semantic network sees an image of ``size (W, H)`` at: as many pixels as ``trained_size``
    (the frames it trained on), at the image's aspect, each side a multiple of 8 (the network's stride; at least 8).
    An image of the trained aspect gets the trained size itself.

    Example:
        >>> [network_size(size, (312, 96)) for size in ((624, 192), (1242, 375), (400, 300))]
        [(312, 96), (312, 96), (200, 152)]
    """
    (w, h), (tw, th) = size, trained_size
    scale = math.sqrt(tw * th / (w * h))
    return max(8, round(w * scale / 8) * 8), max(8, round(h * scale / 8) * 8)


def segment(image: Tensor, predictor: SemanticPredictor | str | os.PathLike) -> tuple[Tensor, Tensor]:
    """``(label, instance)`` maps of ``image`` (see :meth:`SemanticPredictor.__call__`); ``predictor`` may be a
    checkpoint path (loaded on every call: keep a :class:`SemanticPredictor` for repeated use)."""
    if not isinstance(predictor, SemanticPredictor):
        predictor = SemanticPredictor.from_checkpoint(predictor)
    result = predictor(image)
    return result.label, result.instance
