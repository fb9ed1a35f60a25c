"""Semantic branch of 3D-SDN (plain PyTorch): DRN segmentation, instance proposals, PQ, inference API.

- :mod:`~sdn3d.semantic.panoptic`: Panoptic-DeepLab centre / offset targets and grouping, so
  instances come without ground-truth masks.
- :mod:`~sdn3d.semantic.pq`: panoptic quality per thing class.
- :mod:`~sdn3d.semantic.predict`: :class:`SemanticPredictor` (image in, label + instance maps out)
  loading a ``SemanticModule`` checkpoint.
- :mod:`~sdn3d.semantic.augment`: batched random crop / flip, colour jitter (training).
- :mod:`~sdn3d.semantic.tta`: flip test-time augmentation (image and mirror image in one batch).
The network itself is :class:`sdn3d.nets.drn.DRNSeg`.
"""

from sdn3d.semantic.augment import color_jitter, crop_size_for, random_crop_flip
from sdn3d.semantic.balance import CLASS_WEIGHTINGS, class_weights, label_histogram
from sdn3d.semantic.panoptic import (
    PanopticTargets,
    center_focal_loss,
    center_heatmap,
    find_centers,
    group_instances,
    group_vehicles,
    instance_segments,
    panoptic_targets,
    thing_label,
    thing_mask,
)
from sdn3d.semantic.pq import pq_from_stats, pq_stats
from sdn3d.semantic.predict import GROUPING_DEFAULTS, Segmentation, SemanticPredictor, segment
from sdn3d.semantic.tta import flip_averaged_outputs, hflip_outputs

__all__ = [
    "CLASS_WEIGHTINGS",
    "class_weights",
    "label_histogram",
    "color_jitter",
    "crop_size_for",
    "random_crop_flip",
    "PanopticTargets",
    "thing_mask",
    "instance_segments",
    "center_heatmap",
    "center_focal_loss",
    "panoptic_targets",
    "find_centers",
    "thing_label",
    "group_instances",
    "group_vehicles",
    "pq_stats",
    "pq_from_stats",
    "GROUPING_DEFAULTS",
    "Segmentation",
    "SemanticPredictor",
    "segment",
    "flip_averaged_outputs",
    "hflip_outputs",
]
