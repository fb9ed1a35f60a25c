"""Held-out vehicle shapes: a family of lofted vehicles the 8 bank templates only approximate.

The synthetic generator draws its vehicle bodies from this family by default (``vehicles: heldout``
in ``conf/synth.yaml``), so that the geometric branch, which chooses among the 8 templates of
:mod:`sdn3d.meshes.templates`, never sees its own meshes in the data (real cars are never one of its
CAD models either). Every shape is built with the templates' lofting machinery
(:class:`~sdn3d.meshes.templates.VehicleSpec`, :func:`~sdn3d.meshes.templates.loft_vehicle`): same
canonical frame (unit box ``[-0.5, 0.5]^3``, ``+x`` front, ``+y`` down, ``z`` width), watertight,
mirror-symmetric, four wheels.

Each :class:`FamilyShape` has a name, real dimensions (its spec), a Virtual KITTI category and its
*approximating template*: the template whose unit-box voxel occupancy has the highest IoU with it
(:func:`unit_box_occupancy`, :func:`occupancy_iou`; ``tests/test_vehicle_family.py`` checks every
declared template against that criterion, and that no shape is one of the templates: every IoU is
below :data:`DISTINCT_IOU`). Readers map a family name to its approximating template
(:func:`approximating_template`), so on held-out data "mesh accuracy" means "picked the approximating
template".

Categories follow the templates' rule: passenger cars, SUVs, pickups and car-sized minivans / MPVs are
``Car``; panel and high-roof vans, minibuses, small box trucks and buses are ``Van`` (Virtual KITTI's
object classes are ``Car`` and ``Van``; ``Van`` is the closest to the box-shaped ones).

Vehicle shape ids: :data:`VEHICLE_SHAPE_NAMES` lists the 8 templates (ids 0-7, the template ids) then
the family (ids 8 ...), one id space for the generator's car tracks and its renderer.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING

import numpy as np

from sdn3d.meshes.templates import (
    TEMPLATE_CATEGORY,
    TEMPLATE_NAMES,
    TEMPLATE_SPECS,
    VehicleSpec,
    loft_vehicle_parts,
)

if TYPE_CHECKING:  # imported where a Trimesh is built
    import trimesh

__all__ = [
    "FamilyShape",
    "FAMILY",
    "FAMILY_NAMES",
    "FAMILY_CATEGORY",
    "FAMILY_DIMENSIONS",
    "FAMILY_TEMPLATE",
    "VEHICLE_SHAPE_NAMES",
    "VEHICLE_SHAPE_CATEGORY",
    "DISTINCT_IOU",
    "OCCUPANCY_RESOLUTION",
    "approximating_template",
    "family_arrays",
    "family_parts",
    "build_family_shape",
    "all_family_shapes",
    "unit_box_occupancy",
    "occupancy_iou",
    "canonical_belt",
]

#: A family shape counts as distinct from a template when their unit-box voxel IoU is below this. Measured at
#: :data:`OCCUPANCY_RESOLUTION`: two different templates of the bank score 0.56-0.92 against each other, and the
#: generator's random FFD (``synth/layout.py``) takes a template to 0.94-0.98 against itself (mean 0.96 over 40
#: draws); so a shape below 0.95 differs from every template by more than a typical FFD does (the generated
#: bodies get that FFD on top).
DISTINCT_IOU = 0.95
#: Voxels per axis of the unit box in :func:`unit_box_occupancy`.
OCCUPANCY_RESOLUTION = 48


@dataclass(frozen=True)
class FamilyShape:
    """One held-out vehicle shape.

    Attributes:
        name: e.g. ``'sedan_long'``; the motgt ``model`` column of the generated data.
        spec: its lofting spec (real dimensions in metres, category).
        template: name of its approximating template (nearest by unit-box voxel IoU).
        weight: relative frequency in the generated traffic.
        lane_only: drawn only in driving lanes, never parked (buses).
    """

    name: str
    spec: VehicleSpec
    template: str
    weight: float
    lane_only: bool = False


def _car(length: float, height: float, width: float, top: tuple[tuple[float, float], ...], belt: float,
         clearance: float = 0.15, wheel_radius: float = 0.32, axles: tuple[float, float] = (0.19, 0.81),
         **kw: object) -> VehicleSpec:
    return VehicleSpec(length, height, width, top, belt, clearance, wheel_radius, axles, **kw)


def _box(length: float, height: float, width: float, top: tuple[tuple[float, float], ...], belt: float,
         clearance: float, wheel_radius: float, axles: tuple[float, float], **kw: object) -> VehicleSpec:
    """A ``Van``-category box-shaped vehicle: flat sides (little tumblehome), squarer ends."""
    defaults = {"bumper_lift": (0.10, 0.12), "tumble": 0.04, "plan_round": 0.05, "category": "Van"}
    return VehicleSpec(length, height, width, top, belt, clearance, wheel_radius, axles, **{**defaults, **kw})


FAMILY: tuple[FamilyShape, ...] = (
    # --- sedans and coupes: three-box roof lines of other proportions ---
    FamilyShape("sedan_compact", _car(
        4.35, 1.44, 1.76,
        ((0.0, 0.74), (0.02, 0.90), (0.06, 0.98), (0.16, 1.02), (0.22, 1.07), (0.34, 1.37), (0.40, 1.44),
         (0.60, 1.44), (0.66, 1.36), (0.75, 1.00), (0.95, 0.86), (0.99, 0.75), (1.0, 0.63)),
        0.97, wheel_radius=0.31, axles=(0.19, 0.80)), "sedan", 0.04),
    FamilyShape("sedan_long", _car(
        5.05, 1.47, 1.87,
        ((0.0, 0.74), (0.02, 0.92), (0.05, 1.00), (0.17, 1.04), (0.24, 1.09), (0.35, 1.40), (0.41, 1.47),
         (0.58, 1.47), (0.64, 1.39), (0.72, 1.02), (0.95, 0.88), (0.99, 0.76), (1.0, 0.64)),
        1.00, wheel_radius=0.33, axles=(0.21, 0.80)), "sedan", 0.04),
    FamilyShape("sedan_fastback", _car(
        4.75, 1.42, 1.84,
        ((0.0, 0.76), (0.02, 0.92), (0.05, 1.00), (0.12, 1.06), (0.36, 1.40), (0.44, 1.42), (0.60, 1.42),
         (0.66, 1.34), (0.76, 0.99), (0.95, 0.85), (0.99, 0.74), (1.0, 0.62)),
        0.96), "sedan", 0.04),
    FamilyShape("coupe", _car(
        4.50, 1.36, 1.82,
        ((0.0, 0.72), (0.02, 0.88), (0.06, 0.96), (0.18, 1.00), (0.30, 1.30), (0.42, 1.36), (0.56, 1.36),
         (0.63, 1.27), (0.74, 0.95), (0.95, 0.82), (0.99, 0.71), (1.0, 0.60)),
        0.94, clearance=0.13), "sedan", 0.025),
    FamilyShape("coupe_sport", _car(
        4.40, 1.26, 1.88,
        ((0.0, 0.70), (0.02, 0.86), (0.06, 0.93), (0.16, 0.98), (0.34, 1.22), (0.44, 1.26), (0.55, 1.26),
         (0.62, 1.17), (0.72, 0.93), (0.95, 0.83), (0.99, 0.70), (1.0, 0.58)),
        0.90, clearance=0.11, wheel_radius=0.31, tumble=0.28), "sedan", 0.025),
    # --- hatchbacks ---
    FamilyShape("hatchback_small", _car(
        3.65, 1.50, 1.66,
        ((0.0, 0.82), (0.02, 1.05), (0.06, 1.32), (0.12, 1.46), (0.18, 1.50), (0.58, 1.50), (0.65, 1.40),
         (0.76, 0.98), (0.94, 0.86), (0.99, 0.75), (1.0, 0.64)),
        0.98, wheel_radius=0.29, axles=(0.16, 0.83)), "hatchback", 0.05),
    FamilyShape("hatchback_sport", _car(
        4.25, 1.42, 1.80,
        ((0.0, 0.80), (0.03, 1.02), (0.16, 1.28), (0.26, 1.40), (0.32, 1.42), (0.55, 1.42), (0.62, 1.33),
         (0.74, 0.95), (0.94, 0.82), (0.99, 0.71), (1.0, 0.60)),
        0.95), "hatchback", 0.05),
    FamilyShape("hatchback_tall", _car(
        4.00, 1.58, 1.72,
        ((0.0, 0.82), (0.015, 1.10), (0.04, 1.45), (0.08, 1.56), (0.12, 1.58), (0.62, 1.58), (0.72, 1.40),
         (0.84, 1.00), (0.96, 0.88), (0.99, 0.77), (1.0, 0.66)),
        1.00, wheel_radius=0.30, axles=(0.16, 0.83)), "van", 0.05),
    # --- wagons ---
    FamilyShape("wagon_estate", _car(
        5.00, 1.48, 1.86,
        ((0.0, 0.76), (0.01, 0.98), (0.04, 1.30), (0.08, 1.44), (0.14, 1.48), (0.54, 1.48), (0.63, 1.37),
         (0.74, 0.97), (0.96, 0.86), (0.99, 0.75), (1.0, 0.62)),
        0.97, axles=(0.20, 0.81)), "wagon", 0.04),
    FamilyShape("wagon_shooting", _car(
        4.85, 1.42, 1.85,
        ((0.0, 0.78), (0.02, 1.00), (0.06, 1.24), (0.12, 1.38), (0.18, 1.42), (0.58, 1.42), (0.65, 1.33),
         (0.77, 0.95), (0.96, 0.82), (0.99, 0.72), (1.0, 0.60)),
        0.95, axles=(0.20, 0.81)), "wagon", 0.04),
    # --- SUVs and crossovers ---
    FamilyShape("suv_compact", _car(
        4.35, 1.66, 1.82,
        ((0.0, 0.96), (0.015, 1.26), (0.06, 1.54), (0.12, 1.66), (0.62, 1.66), (0.70, 1.54), (0.79, 1.16),
         (0.97, 1.10), (0.995, 0.98), (1.0, 0.84)),
        1.14, clearance=0.20, wheel_radius=0.35, axles=(0.18, 0.82), bumper_lift=(0.15, 0.12),
        tumble=0.17), "suv", 0.05),
    FamilyShape("suv_large", _car(
        5.15, 1.92, 2.00,
        ((0.0, 1.04), (0.008, 1.48), (0.02, 1.82), (0.04, 1.92), (0.74, 1.92), (0.79, 1.78), (0.84, 1.30),
         (0.97, 1.24), (0.995, 1.10), (1.0, 0.94)),
        1.30, clearance=0.26, wheel_radius=0.40, axles=(0.18, 0.82), bumper_lift=(0.12, 0.12),
        tumble=0.12), "suv", 0.03),
    FamilyShape("suv_coupe", _car(
        4.80, 1.66, 1.95,
        ((0.0, 1.00), (0.02, 1.22), (0.10, 1.46), (0.22, 1.64), (0.28, 1.66), (0.64, 1.66), (0.71, 1.54),
         (0.80, 1.16), (0.97, 1.10), (0.995, 0.98), (1.0, 0.84)),
        1.16, clearance=0.22, wheel_radius=0.37, bumper_lift=(0.15, 0.12), tumble=0.18), "suv", 0.03),
    FamilyShape("crossover", _car(
        4.45, 1.60, 1.84,
        ((0.0, 0.90), (0.015, 1.20), (0.05, 1.48), (0.10, 1.58), (0.14, 1.60), (0.62, 1.60), (0.69, 1.49),
         (0.79, 1.08), (0.96, 1.00), (0.99, 0.88), (1.0, 0.74)),
        1.12, clearance=0.20, wheel_radius=0.36, bumper_lift=(0.15, 0.12), tumble=0.18), "suv", 0.05),
    FamilyShape("crossover_small", _car(
        4.10, 1.56, 1.77,
        ((0.0, 0.88), (0.015, 1.14), (0.06, 1.44), (0.12, 1.54), (0.16, 1.56), (0.60, 1.56), (0.67, 1.46),
         (0.78, 1.04), (0.96, 0.96), (0.99, 0.84), (1.0, 0.71)),
        1.05, clearance=0.17, wheel_radius=0.33, axles=(0.17, 0.82)), "hatchback", 0.04),
    # --- pickups ---
    FamilyShape("pickup_crew", _car(
        5.60, 1.86, 1.98,
        ((0.0, 0.98), (0.01, 1.12), (0.30, 1.14), (0.31, 1.72), (0.33, 1.86), (0.62, 1.86), (0.67, 1.74),
         (0.75, 1.30), (0.96, 1.22), (0.99, 1.10), (1.0, 0.92)),
        1.20, clearance=0.24, wheel_radius=0.40, axles=(0.15, 0.79), bumper_lift=(0.12, 0.12),
        tumble=0.12), "pickup", 0.04),
    FamilyShape("pickup_single", _car(
        5.20, 1.76, 1.86,
        ((0.0, 0.92), (0.01, 1.04), (0.50, 1.06), (0.51, 1.62), (0.53, 1.76), (0.64, 1.76), (0.68, 1.66),
         (0.75, 1.22), (0.96, 1.14), (0.99, 1.02), (1.0, 0.86)),
        1.12, clearance=0.21, wheel_radius=0.36, axles=(0.17, 0.78), bumper_lift=(0.12, 0.12),
        tumble=0.12), "pickup", 0.03),
    # --- car-sized minivans / MPVs ---
    FamilyShape("minivan", _car(
        5.10, 1.76, 1.95,
        ((0.0, 0.84), (0.01, 1.40), (0.03, 1.67), (0.06, 1.76), (0.60, 1.76), (0.69, 1.61), (0.82, 1.09),
         (0.97, 0.95), (0.995, 0.82), (1.0, 0.66)),
        1.02, clearance=0.17, wheel_radius=0.35, axles=(0.18, 0.82), tumble=0.17), "van", 0.05),
    FamilyShape("mpv_compact", _car(
        4.45, 1.68, 1.80,
        ((0.0, 0.82), (0.01, 1.36), (0.04, 1.60), (0.07, 1.68), (0.58, 1.68), (0.68, 1.52), (0.82, 1.04),
         (0.97, 0.92), (0.995, 0.80), (1.0, 0.66)),
        1.00, wheel_radius=0.31, axles=(0.17, 0.83), tumble=0.17), "van", 0.04),
    # --- vans, minibuses, box trucks (Van) ---
    FamilyShape("van_panel", _box(
        5.00, 1.98, 2.00,
        ((0.0, 0.80), (0.008, 1.70), (0.02, 1.92), (0.04, 1.98), (0.70, 1.98), (0.76, 1.80), (0.86, 1.20),
         (0.97, 1.04), (0.995, 0.90), (1.0, 0.72)),
        1.12, 0.18, 0.34, (0.16, 0.82), tumble=0.06, plan_round=0.07), "van", 0.06),
    FamilyShape("van_highroof", _box(
        5.40, 2.45, 2.00,
        ((0.0, 0.72), (0.005, 2.30), (0.02, 2.45), (0.82, 2.45), (0.85, 2.28), (0.90, 1.32), (0.97, 1.16),
         (0.995, 1.02), (1.0, 0.80)),
        1.25, 0.19, 0.35, (0.19, 0.82)), "minibus", 0.04),
    FamilyShape("van_long", _box(
        6.90, 2.70, 2.05,
        ((0.0, 0.74), (0.005, 2.58), (0.015, 2.70), (0.80, 2.70), (0.83, 2.52), (0.88, 1.45), (0.97, 1.26),
         (0.995, 1.08), (1.0, 0.84)),
        1.32, 0.20, 0.37, (0.20, 0.82)), "minibus", 0.03),
    FamilyShape("minibus_long", _box(
        7.60, 2.85, 2.15,
        ((0.0, 0.80), (0.005, 2.70), (0.015, 2.85), (0.90, 2.85), (0.94, 2.60), (0.98, 1.60), (0.995, 1.20),
         (1.0, 0.90)),
        1.25, 0.24, 0.40, (0.22, 0.84)), "bus", 0.02),
    FamilyShape("box_truck", _box(
        7.20, 3.20, 2.30,
        ((0.0, 0.95), (0.005, 3.10), (0.01, 3.20), (0.74, 3.20), (0.745, 2.55), (0.76, 2.62), (0.86, 2.62),
         (0.89, 2.30), (0.92, 1.60), (0.98, 1.40), (0.995, 1.20), (1.0, 1.00)),
        1.50, 0.30, 0.45, (0.22, 0.84), bumper_lift=(0.15, 0.10), tumble=0.02, plan_round=0.03,
        wheel_width=0.28), "minibus", 0.025),
    FamilyShape("box_truck_small", _box(
        6.20, 2.90, 2.10,
        ((0.0, 0.90), (0.005, 2.80), (0.01, 2.90), (0.84, 2.90), (0.86, 2.75), (0.875, 2.20), (0.90, 1.50),
         (0.98, 1.25), (0.995, 1.10), (1.0, 0.90)),
        1.40, 0.24, 0.40, (0.20, 0.83), tumble=0.02, plan_round=0.03), "minibus", 0.025),
    # --- buses (driving lanes only) ---
    FamilyShape("bus_coach", _box(
        12.40, 3.45, 2.55,
        ((0.0, 2.70), (0.01, 3.30), (0.03, 3.45), (0.94, 3.45), (0.975, 3.25), (0.995, 2.30), (1.0, 1.70)),
        1.50, 0.34, 0.52, (0.22, 0.74), bumper_lift=(0.05, 0.05), tumble=0.02, plan_round=0.04, round=0.08,
        crown=0.04, wheel_width=0.30), "bus", 0.02, lane_only=True),
    FamilyShape("bus_midi", _box(
        9.00, 3.00, 2.40,
        ((0.0, 2.10), (0.02, 2.70), (0.06, 3.00), (0.92, 3.00), (0.96, 2.85), (0.985, 2.20), (1.0, 1.70)),
        1.15, 0.30, 0.46, (0.24, 0.76), bumper_lift=(0.05, 0.05), tumble=0.03, plan_round=0.05, round=0.08,
        crown=0.04, wheel_width=0.28), "bus", 0.02, lane_only=True),
)

#: Family shape names, in family order (shape id ``8 + index``).
FAMILY_NAMES: tuple[str, ...] = tuple(s.name for s in FAMILY)
#: Virtual KITTI category (``Car`` or ``Van``) of each family shape.
FAMILY_CATEGORY: dict[str, str] = {s.name: s.spec.category for s in FAMILY}
#: Real dimensions ``(l, h, w)`` in metres of each family shape.
FAMILY_DIMENSIONS: dict[str, tuple[float, float, float]] = {
    s.name: (s.spec.length, s.spec.height, s.spec.width) for s in FAMILY
}
#: Approximating template name of each family shape.
FAMILY_TEMPLATE: dict[str, str] = {s.name: s.template for s in FAMILY}
#: All vehicle shapes by shape id: the 8 templates (ids = template ids), then the family.
VEHICLE_SHAPE_NAMES: tuple[str, ...] = TEMPLATE_NAMES + FAMILY_NAMES
#: Virtual KITTI category of every vehicle shape, by name.
VEHICLE_SHAPE_CATEGORY: dict[str, str] = {**TEMPLATE_CATEGORY, **FAMILY_CATEGORY}


def canonical_belt(spec: VehicleSpec) -> float:
    """Canonical ``y`` of the belt line (bottom of the side windows; ``y = +0.5`` is the ground)."""
    return 0.5 - spec.belt / max(h for _, h in spec.top)


def approximating_template(model: str) -> str | None:
    """Template that stands for vehicle ``model``: itself for a template name, the approximating template
    for a family shape name, ``None`` for any other name."""
    if model in TEMPLATE_SPECS:
        return model
    return FAMILY_TEMPLATE.get(model)


def _shape(name: str) -> FamilyShape:
    for shape in FAMILY:
        if shape.name == name:
            return shape
    raise ValueError(f"name must be one of {FAMILY_NAMES}, got {name!r}")


@cache
def _family_arrays(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return loft_vehicle_parts(_shape(name).spec)


def family_arrays(name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(verts (V, 3) float64, faces (F, 3) int64)`` of family shape ``name`` (fresh copies)."""
    verts, faces, _ = _family_arrays(name)
    return verts.copy(), faces.copy()


def family_parts(name: str) -> np.ndarray:
    """``(F,)`` int64 :class:`~sdn3d.meshes.parts.Part` of each face of :func:`family_arrays` ``(name)`` (a copy;
    the templates' loft labels them, :func:`~sdn3d.meshes.templates.loft_vehicle_parts`)."""
    return _family_arrays(name)[2].copy()


def build_family_shape(name: str) -> trimesh.Trimesh:
    """The family shape ``name`` in the canonical frame (fresh, ``process=False``; geometry cached)."""
    import trimesh

    return trimesh.Trimesh(*family_arrays(name), process=False)


def all_family_shapes() -> list[trimesh.Trimesh]:
    """All family shapes in :data:`FAMILY_NAMES` order."""
    return [build_family_shape(name) for name in FAMILY_NAMES]


def unit_box_occupancy(verts: np.ndarray, faces: np.ndarray, resolution: int = OCCUPANCY_RESOLUTION) -> np.ndarray:
    """``(R, R, R)`` bool voxel occupancy (index order x, y, z) of a closed, outward-wound mesh in the unit box.

    Voxel centres are ``(i + 0.5) / R - 0.5`` (shifted by 1e-6 in x and y so that no ray meets an edge).
    Exact per column: a ray along ``+z`` through each ``(x, y)`` voxel column meets the faces whose
    ``xy`` projection holds it; each crossing counts ``+1`` (leaving, normal towards ``+z``) or ``-1``
    (entering), and a voxel is inside where the crossings beyond it sum to at least 1 (the winding
    number, so overlapping closed parts such as wheels in a body are handled). Faces parallel to the
    ray are skipped. Cost: one candidate per face and covered column (no dense column x face test).

    Args:
        verts: ``(V, 3)`` vertices; faces: ``(F, 3)`` indices.
    """
    r = int(resolution)
    centres = (np.arange(r) + 0.5) / r - 0.5
    tri = np.asarray(verts, dtype=np.float64)[np.asarray(faces)]  # (F, 3, 3)
    x, y, z = tri[..., 0], tri[..., 1], tri[..., 2]
    area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (y[:, 1] - y[:, 0]) * (x[:, 2] - x[:, 0])
    keep = np.abs(area2) > 1e-15
    x, y, z, area2 = x[keep], y[keep], z[keep], area2[keep]
    shift = 1e-6 * np.array([np.sqrt(2.0), np.sqrt(3.0)])
    # Column index ranges covered by each face's bounding box.
    i0 = np.clip(np.ceil((x.min(1) - shift[0] + 0.5) * r - 0.5), 0, r).astype(np.int64)
    i1 = np.clip(np.floor((x.max(1) - shift[0] + 0.5) * r - 0.5), -1, r - 1).astype(np.int64)
    j0 = np.clip(np.ceil((y.min(1) - shift[1] + 0.5) * r - 0.5), 0, r).astype(np.int64)
    j1 = np.clip(np.floor((y.max(1) - shift[1] + 0.5) * r - 0.5), -1, r - 1).astype(np.int64)
    ni, nj = np.maximum(i1 - i0 + 1, 0), np.maximum(j1 - j0 + 1, 0)
    count = ni * nj
    face = np.repeat(np.arange(len(x)), count)
    local = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    ci = i0[face] + local // nj[face]
    cj = j0[face] + local % nj[face]
    px, py = centres[ci] + shift[0], centres[cj] + shift[1]
    fx, fy = x[face], y[face]
    # Barycentric coordinates of the column point in the face's xy projection.
    w1 = ((px - fx[:, 0]) * (fy[:, 2] - fy[:, 0]) - (py - fy[:, 0]) * (fx[:, 2] - fx[:, 0])) / area2[face]
    w2 = ((fx[:, 1] - fx[:, 0]) * (py - fy[:, 0]) - (fy[:, 1] - fy[:, 0]) * (px - fx[:, 0])) / area2[face]
    inside = (w1 >= 0) & (w2 >= 0) & (w1 + w2 <= 1)
    face, ci, cj, w1, w2 = face[inside], ci[inside], cj[inside], w1[inside], w2[inside]
    zf = z[face]
    z_hit = zf[:, 0] + w1 * (zf[:, 1] - zf[:, 0]) + w2 * (zf[:, 2] - zf[:, 0])
    sign = np.sign(area2[face])  # +1: the outward normal points to +z, the ray leaves the solid
    # Winding number at voxel k = sum of the signs of the crossings beyond it: add the sign to every
    # voxel below the crossing (a difference array, then a cumulative sum along z).
    diff = np.zeros((r, r, r + 1))
    first_above = np.searchsorted(centres, z_hit)  # voxels 0 .. first_above - 1 lie below the crossing
    np.add.at(diff, (ci, cj, np.zeros_like(ci)), sign)
    np.add.at(diff, (ci, cj, first_above), -sign)
    return np.cumsum(diff, axis=2)[..., :r] >= 0.5


def occupancy_iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two bool occupancy grids of one shape."""
    union = np.logical_or(a, b).sum()
    return float(np.logical_and(a, b).sum() / union) if union else 1.0
