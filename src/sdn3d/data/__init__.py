"""Dataset readers (Virtual KITTI 1.3.1 / 2.0.3, Cityscapes), shared records and the
3D-SDN edit-benchmark format.

Readers index a dataset into :class:`FrameRecord` objects (``vkitti1.read_frames``,
``vkitti2.read_frames``, ``cityscapes.read_frames``); :func:`load_rgb`,
:func:`load_semantic`, :func:`load_instances` and :func:`load_depth` read arrays
lazily for any record. :mod:`sdn3d.data.fixtures` writes tiny datasets in the
same formats (not imported here: it is a test and generator helper).
"""

from sdn3d.data import cityscapes, vkitti1, vkitti2
from sdn3d.data.edit_benchmark import (
    BenchmarkEntry,
    BenchmarkOperation,
    load_edit_benchmark,
    save_edit_benchmark,
    scale_entry,
    scale_operation,
    validate_in_frame,
)
from sdn3d.data.errors import DataFormatError, MissingDataError
from sdn3d.data.records import (
    FrameRecord,
    ObjectAnnotation,
    load_depth,
    load_instances,
    load_rgb,
    load_semantic,
    visible_pixel_counts,
)
from sdn3d.data.vkitti1 import paper_object_filter, paper_split

__all__ = [
    "cityscapes",
    "vkitti1",
    "vkitti2",
    "DataFormatError",
    "MissingDataError",
    "FrameRecord",
    "ObjectAnnotation",
    "visible_pixel_counts",
    "load_rgb",
    "load_semantic",
    "load_instances",
    "load_depth",
    "paper_object_filter",
    "paper_split",
    "BenchmarkEntry",
    "BenchmarkOperation",
    "load_edit_benchmark",
    "save_edit_benchmark",
    "scale_operation",
    "scale_entry",
    "validate_in_frame",
]
