"""torch Datasets of the three 3D-SDN branches (plain PyTorch, no Lightning).

- :class:`SemanticDataset`: one frame per item (image, semantic and instance maps).
- :class:`GeometricDataset`: one object per item (masked square crop, masks, 3D targets).
- :class:`TexturalDataset`: one frame per item (label / instance / boundary / normal / pose maps).

Frames come from a :class:`SourceConfig` (one ``conf/data`` file) through :func:`load_split`;
everything is resized to the working size with intrinsics following
(:mod:`sdn3d.data.frames`).
"""

from sdn3d.data.datasets.geometric import (
    GeometricDataset,
    ObjectFilter,
    closer_object_mask,
    object_mask,
    template_id,
    track_pixel_counts,
)
from sdn3d.data.datasets.semantic import SemanticDataset
from sdn3d.data.datasets.textural import TexturalDataset, render_geometry_maps

__all__ = [
    "SemanticDataset",
    "GeometricDataset",
    "TexturalDataset",
    "ObjectFilter",
    "object_mask",
    "closer_object_mask",
    "template_id",
    "track_pixel_counts",
    "render_geometry_maps",
]
