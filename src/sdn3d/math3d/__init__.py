"""Camera, rotations, attribute encodings and free-form deformation."""

from sdn3d.math3d.camera import (
    VKITTI_INTRINSICS,
    Intrinsics,
    intrinsics_matrix,
    project_points,
    unproject_pixels,
)
from sdn3d.math3d.encodings import (
    AttributeEncoding,
    decode_attributes,
    encode_attributes,
    rotation_loss,
)
from sdn3d.math3d.ffd import (
    FreeFormDeformation,
    bernstein_basis,
    expand_half_ffd,
    ffd_deform,
    half_indices,
    symmetrize_ffd,
)
from sdn3d.math3d.rotations import NUM_POSE_BINS, alpha_bins, observation_angle, roty, wrap_angle
from sdn3d.math3d.transforms import (
    bottom_to_center,
    box_corners,
    center_to_bottom,
    convex_overlap,
    dims_from_whl,
    from_kitti_fields,
    ground_footprints,
    object_to_camera,
    project_box,
    to_kitti_fields,
)

__all__ = [
    "Intrinsics",
    "VKITTI_INTRINSICS",
    "intrinsics_matrix",
    "project_points",
    "unproject_pixels",
    "roty",
    "wrap_angle",
    "observation_angle",
    "alpha_bins",
    "NUM_POSE_BINS",
    "object_to_camera",
    "bottom_to_center",
    "center_to_bottom",
    "box_corners",
    "project_box",
    "ground_footprints",
    "convex_overlap",
    "dims_from_whl",
    "from_kitti_fields",
    "to_kitti_fields",
    "AttributeEncoding",
    "encode_attributes",
    "decode_attributes",
    "rotation_loss",
    "bernstein_basis",
    "ffd_deform",
    "symmetrize_ffd",
    "expand_half_ffd",
    "half_indices",
    "FreeFormDeformation",
]
