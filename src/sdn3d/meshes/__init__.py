"""Vehicle meshes: procedural templates, ShapeNet OBJ loading and a padded tensor bank."""

from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.shapenet import (
    SHAPENET_TO_CANONICAL,
    cluster_simplify,
    load_mesh_directory,
    load_shapenet_obj,
)
from sdn3d.meshes.templates import (
    TEMPLATE_CATEGORY,
    TEMPLATE_DIMENSIONS,
    TEMPLATE_NAMES,
    all_templates,
    build_template,
    normalize_to_unit_box,
)

__all__ = [
    "TEMPLATE_NAMES",
    "TEMPLATE_DIMENSIONS",
    "TEMPLATE_CATEGORY",
    "build_template",
    "all_templates",
    "normalize_to_unit_box",
    "SHAPENET_TO_CANONICAL",
    "load_shapenet_obj",
    "load_mesh_directory",
    "cluster_simplify",
    "MeshBank",
]
