"""3D-aware edits of a :class:`~sdn3d.scene.code.SceneCode` (3D-SDN, Sec. 4): pure geometry, no networks.

Operations address objects by instance id (:func:`ops_from_benchmark` resolves the benchmark's
pixel picks). Positions refer to the box centre ``c = (x3d, y3d - h/2, z3d)`` and its projection.

- :class:`Move` ``(u, v)``: the object stays on its ground plane: the centre keeps its height
  ``c_y`` (so the bottom ``y3d`` stays) and moves to where the camera ray through ``(u, v)`` meets
  the plane ``y = c_y``; the centre then projects to ``(u, v)`` exactly. Yaw ``ry`` is kept.
- :class:`Zoom`: the distance ``|c|`` is divided by ``zoom``. Default: along the viewing ray
  (``c / zoom``, the projected centre stays; the 3D-SDN benchmark's meaning). ``on_ground=True``
  keeps the height ``c_y`` and scales ``(x, z)`` instead (same azimuth, same ``u``, exact distance).
- :class:`Rotate`: adds to ``ry`` (wrapped to ``[-pi, pi)``).
- :class:`Modify`: one benchmark ``modify``: the centre goes onto the ray through ``to_uv`` (its own
  ray when None) at distance ``|c| / zoom``, and ``ry`` increases by ``delta_ry``.
- :class:`Delete`, :class:`SetCode`, :class:`SetBackgroundCode`, :class:`Duplicate` (a copy with a
  new instance id, placed like :class:`Move`).

Freed pixels: when an *observed* object (see :mod:`sdn3d.scene.code`) ends up moved or deleted, the
pixels it occupied in the image take background labels (:func:`sdn3d.scene.maps.fill_background`).
Its footprint is its mask (or, without one, where it wins among the observed objects'
rendered silhouettes), grown by ``grow`` pixels into unclaimed pixels of its own class (the
semantic map's object region is rarely exactly the mask or silhouette; "claimed" pixels are those
of the other observed objects, i.e. their masks, so nothing is rendered unless an observed object lacks
a mask). Moved objects lose their mask and are drawn from geometry. An object whose pose ends where
it started (e.g. rotated by ``2 pi``) is left exactly as it was.

Amodal completion (the paper's occlusion recovery, its Fig. 4d and 6a): the freed pixels do not all turn
into background. Every unmoved object with geometry and a mask also covers the freed pixels where its
rendered silhouette lies, nearest object first (:func:`_reclaim`): the car that stood behind a deleted or
moved one comes back whole. Only freed pixels no such object covers take background labels.
``amodal=False`` turns this off (every freed pixel takes a background label): what an editor without 3D
geometry can do, the 2D and 2D+ baselines (:mod:`sdn3d.evaluation.baselines`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from enum import StrEnum

import torch
from torch import Tensor

from sdn3d.data.edit_benchmark import VKITTI_FRAME_SIZE, BenchmarkEntry, BenchmarkOperation, scale_operation
from sdn3d.editing.ops import (
    Delete,
    Duplicate,
    EditError,
    EditOp,
    Modify,
    Move,
    Rotate,
    SetBackgroundCode,
    SetCode,
    Zoom,
)
from sdn3d.editing.pick import pick_objects, projected_centers
from sdn3d.image_ops import dilate_cross
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.camera import Intrinsics, project_points
from sdn3d.math3d.rotations import wrap_angle
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode
from sdn3d.scene.fill import fill_background
from sdn3d.scene.maps import compose_instances

__all__ = [
    "EditError",
    "Move",
    "Zoom",
    "Rotate",
    "Modify",
    "Delete",
    "SetCode",
    "SetBackgroundCode",
    "Duplicate",
    "EditOp",
    "apply_edits",
    "ops_from_benchmark",
    "ModifyAnchor",
    "MIN_CLEARANCE",
    "MAX_DISTANCE",
    "edited_table",
    "copy_id",
    "clear_place",
    "DUPLICATE_GAP",
]


# -- the operations live in sdn3d.editing.ops (re-exported here) -----------------------------------

#: Bounds on an edited object's distance ``|c|`` (metres): its centre stays beyond the rasterizer's near
#: plane by at least half its length (:data:`MIN_CLEARANCE` + l / 2) and within its far plane; scenes are
#: drawn with the default :class:`~sdn3d.render.settings.RasterSettings`. A Zoom or Modify that changes the
#: distance is checked against both (``zoom: 1e9`` would put the camera inside the car, ``1e-9`` send it
#: 3e10 m away), a Move or Duplicate against the far one (a target just below the horizon).
MIN_CLEARANCE = RasterSettings.near
MAX_DISTANCE = RasterSettings.far

# -- geometry -----------------------------------------------------------------------------------


def _ray(uv: tuple[float, float], intr: Intrinsics) -> Tensor:
    """``(3,)`` float64 direction ``K^-1 (u, v, 1)``."""
    return torch.tensor([(uv[0] - intr.cx) / intr.fx, (uv[1] - intr.cy) / intr.fy, 1.0], dtype=torch.float64)


def _check_in_frame(uv: tuple[float, float], intr: Intrinsics, what: str) -> None:
    if not (-0.5 <= uv[0] <= intr.width - 0.5 and -0.5 <= uv[1] <= intr.height - 0.5):
        raise EditError(f"{what} {uv} lies outside the {intr.width}x{intr.height} frame")


def _on_ground(center: Tensor, uv: tuple[float, float], intr: Intrinsics, what: str) -> Tensor:
    """Centre on the ray through ``uv`` at the height ``center[1]`` (module doc, :class:`Move`)."""
    d = _ray(uv, intr)
    t = float(center[1]) / float(d[1]) if d[1] != 0 else math.inf
    if not (math.isfinite(t) and t > 0):
        raise EditError(f"{what}: the ray through {uv} never meets the object's ground plane y = {float(center[1]):.3f}"
                        " in front of the camera (target on or above its horizon)")
    return d * t


def _check_distance(center: Tensor, length: float, what: str, near: bool = True) -> None:
    """An edit must leave the object's centre between :data:`MIN_CLEARANCE` + half its length (``near``)
    and :data:`MAX_DISTANCE` metres from the camera (the range the rasterizer draws it in)."""
    distance, low = float(center.norm()), MIN_CLEARANCE + length / 2
    if near and not distance >= low:
        raise EditError(f"{what} would end {distance:.3g} m from the camera, closer than {low:.2f} m (the near plane "
                        f"{MIN_CLEARANCE:g} m + half its length {length:.2f} m): the camera would be inside it and it "
                        "would not be drawn; use a smaller zoom")
    if not distance <= MAX_DISTANCE:  # also NaN
        hint = "use a larger zoom" if near else "pick a target farther below the horizon"
        raise EditError(f"{what} would end {distance:.3g} m from the camera, farther than {MAX_DISTANCE:g} m (the "
                        f"far plane, beyond which nothing is drawn); {hint}")


# -- applying -----------------------------------------------------------------------------------


def _set_row(table: ObjectTable, i: int, **values: Tensor) -> ObjectTable:
    changes = {}
    for name, value in values.items():
        column = getattr(table, name).clone()
        column[i] = value
        changes[name] = column
    return table.replace(**changes)


class _Copies:
    """The rows :class:`Duplicate` ops made that are not yet in the table: a run of duplicates is appended with
    one concatenation (:meth:`into`) instead of one per op (which copied the whole table each time: quadratic)."""

    def __init__(self) -> None:
        self.rows: list[ObjectTable] = []
        self.ids: set[int] = set()
        self.top: dict[int, int] = {}  # per class, the largest k of the pending ids

    def into(self, table: ObjectTable) -> ObjectTable:
        """``table`` with the pending rows appended (in op order); nothing is pending afterwards."""
        if not self.rows:
            return table
        parts = [table, *self.rows]
        merged = ObjectTable(**{f.name: torch.cat([getattr(t, f.name) for t in parts])
                                for f in dataclasses.fields(ObjectTable)})
        self.rows, self.ids, self.top = [], set(), {}
        return merged


def _apply_one(scene: SceneCode, table: ObjectTable, codes: Tensor, op: EditOp,
               copies: _Copies | None = None) -> tuple[ObjectTable, Tensor]:
    """``op`` applied to ``table`` / ``codes``; a :class:`Duplicate`'s copy goes to ``copies`` (None: appended now)."""
    intr = scene.intrinsics
    if isinstance(op, SetBackgroundCode):
        if not 0 <= int(op.class_id) < codes.shape[0]:
            raise EditError(f"SetBackgroundCode: class {op.class_id} is outside [0, {codes.shape[0]})")
        if len(op.code) != codes.shape[1]:
            raise EditError(f"SetBackgroundCode: code has {len(op.code)} values, scene codes {codes.shape[1]}")
        codes = codes.clone()
        codes[int(op.class_id)] = torch.tensor(op.code, dtype=codes.dtype)
        return table, codes
    name = type(op).__name__
    try:
        i = table.index_of(op.instance_id)
    except KeyError as exc:
        raise EditError(f"{name}: {exc.args[0]}") from None
    if isinstance(op, Delete):
        return table.select(torch.arange(len(table)) != i), codes
    if isinstance(op, SetCode):
        if len(op.code) != table.code.shape[1]:
            raise EditError(f"SetCode: code has {len(op.code)} values, the scene's codes have {table.code.shape[1]}")
        return _set_row(table, i, code=torch.tensor(op.code, dtype=table.code.dtype)), codes
    if not bool(table.has_geometry[i]):
        raise EditError(f"{name}: object {op.instance_id} has no 3D geometry (mask only); it can only be deleted "
                        "or re-coded")
    center, h = table.center[i], float(table.dims[i, 1])
    if isinstance(op, Rotate):
        return _set_row(table, i, ry=wrap_angle(table.ry[i] + op.delta_ry)), codes
    if isinstance(op, (Move, Duplicate)):
        _check_in_frame(op.uv, intr, f"{name}.uv")
        new_center = _on_ground(center, op.uv, intr, name)
    elif isinstance(op, Zoom):
        new_center = center / op.zoom
        if op.on_ground:
            distance, horizontal = float(center.norm()) / op.zoom, float(center[[0, 2]].norm())
            if distance <= abs(float(center[1])) or horizontal == 0:
                raise EditError(f"Zoom: distance {distance:.3f} m cannot keep the object at its height "
                                f"{float(center[1]):.3f} m")
            scale = math.sqrt(distance**2 - float(center[1]) ** 2) / horizontal
            new_center = center * center.new_tensor([scale, 1.0, scale])
    elif isinstance(op, Modify):
        if op.to_uv is None:
            new_center = center / op.zoom
        else:
            if op.check_frame:
                _check_in_frame(op.to_uv, intr, "Modify.to_uv")
            d = _ray(op.to_uv, intr)
            new_center = d / d.norm() * (center.norm() / op.zoom)
    else:
        raise EditError(f"unknown edit operation {op!r}")
    # Zoom / Modify change the distance: both bounds; Move / Duplicate slide on the object's ground plane:
    # the far bound (a target just below the horizon), the ground and the frame bound how close it comes.
    changes_distance = isinstance(op, (Zoom, Modify)) and op.zoom != 1.0
    _check_distance(new_center, float(table.dims[i, 0]), f"{name}: object {op.instance_id}", near=changes_distance)
    location = new_center + new_center.new_tensor([0.0, h / 2, 0.0])
    if isinstance(op, Duplicate):
        pending = _Copies() if copies is None else copies
        pending.rows.append(_duplicate(table, i, op, location, pending))
        return (pending.into(table) if copies is None else table), codes
    ry = wrap_angle(table.ry[i] + op.delta_ry) if isinstance(op, Modify) else table.ry[i]
    return _set_row(table, i, location=location, ry=ry), codes


def _duplicate(table: ObjectTable, i: int, op: Duplicate, location: Tensor, copies: _Copies) -> ObjectTable:
    """The one-row copy a :class:`Duplicate` of row ``i`` makes (its id free in ``table`` and among ``copies``,
    whose ids it is added to); the caller appends it."""
    cls = int(table.class_id[i])
    if op.new_id is None:
        same = table.instance_id[table.class_id == cls] % INSTANCE_DIVISOR
        new_id = cls * INSTANCE_DIVISOR + max(int(same.max()), copies.top.get(cls, -1)) + 1
    else:
        new_id = int(op.new_id)
    if new_id // INSTANCE_DIVISOR != cls or new_id in copies.ids or bool((table.instance_id == new_id).any()):
        raise EditError(f"Duplicate: new id {new_id} must be a free id {cls} * 1000 + k, 0 <= k <= 999")
    copies.ids.add(new_id)
    copies.top[cls] = max(copies.top.get(cls, -1), new_id % INSTANCE_DIVISOR)
    copy = table.select(torch.tensor([i]))
    return copy.replace(instance_id=torch.tensor([new_id]), location=location[None],
                        mask=torch.zeros_like(copy.mask), has_mask=torch.zeros(1, dtype=torch.bool),
                        observed=torch.zeros(1, dtype=torch.bool))


def edited_table(scene: SceneCode, table: ObjectTable, codes: Tensor, op: EditOp) -> tuple[ObjectTable, Tensor]:
    """``op`` applied to ``table`` (the objects) and ``codes`` (the background codes) alone: ids, poses and codes
    after it, without the freed footprints and masks :func:`apply_edits` works out (no rendering; a duplicate's copy
    is appended at once). What an edit spec's later ops see (:func:`sdn3d.editing.spec.resolve_ops`)."""
    return _apply_one(scene, table, codes, op, None)


def copy_id(table: ObjectTable, row: int) -> int:
    """The id a :class:`Duplicate` of ``table``'s row ``row`` without ``new_id`` gets: the next ``k`` of its class."""
    cls = int(table.class_id[row])
    same = table.instance_id[table.class_id == cls] % INSTANCE_DIVISOR
    return cls * INSTANCE_DIVISOR + int(same.max()) + 1


#: Metres of road kept between a copy placed by an edit spec's ``duplicate`` and every other car (:func:`clear_place`).
DUPLICATE_GAP = 0.5


def _floor(location: Tensor, dims: Tensor, ry: Tensor, gap: float) -> Tensor:
    """``(4, 2)`` float64 ``(x, z)`` corners of an object's footprint on the ground, grown by ``gap / 2`` metres."""
    half_l, half_w = float(dims[0]) / 2 + gap / 2, float(dims[2]) / 2 + gap / 2
    c, s = math.cos(float(ry)), math.sin(float(ry))
    forward, side = torch.tensor([c, -s], dtype=torch.float64), torch.tensor([s, c], dtype=torch.float64)
    centre = location.double()[[0, 2]]
    return torch.stack([centre + a * half_l * forward + b * half_w * side
                        for a, b in ((1, 1), (1, -1), (-1, -1), (-1, 1))])


def _overlap(a: Tensor, b: Tensor) -> bool:
    """Whether the convex quadrilaterals ``a`` and ``b`` ``(4, 2)`` overlap (separating axis test)."""
    for poly in (a, b):
        edges = poly.roll(-1, 0) - poly
        for edge in edges:
            axis = torch.stack([-edge[1], edge[0]])
            pa, pb = a @ axis, b @ axis
            if float(pa.max()) <= float(pb.min()) or float(pb.max()) <= float(pa.min()):
                return False
    return True


def clear_place(scene: SceneCode, table: ObjectTable, row: int, uv: tuple[float, float], gap: float = DUPLICATE_GAP,
                step: float = 0.25) -> tuple[tuple[float, float], float, int | None]:
    """Where a copy of ``table``'s row ``row`` placed at pixel ``uv`` (as :class:`Duplicate`) stands clear of every
    object with geometry in ``table`` (``gap`` metres of road between their footprints): ``(uv, 0.0, None)`` when it
    already does; else the copy is pushed along its own length (the road's direction), away from the car it hits, by
    ``step`` metres at a time, up to three car lengths each way, and ``(the pixel its centre then projects to, the
    metres pushed (signed: + forward), None)``. ``(uv, nan, id of the car it overlaps)`` when no place inside the
    picture clears."""
    intr = scene.intrinsics
    center, dims, ry = table.center[row], table.dims[row], table.ry[row]
    start = _on_ground(center, uv, intr, "Duplicate")
    others = [(int(table.instance_id[k]), _floor(table.location[k], table.dims[k], table.ry[k], gap))
              for k in range(len(table)) if bool(table.has_geometry[k])]

    def hit(c: Tensor) -> int | None:
        mine = _floor(c, dims, ry, gap)
        return next((iid for iid, poly in others if _overlap(mine, poly)), None)

    first = hit(start)
    if first is None:
        return uv, 0.0, None
    forward = torch.tensor([math.cos(float(ry)), 0.0, -math.sin(float(ry))], dtype=torch.float64)
    blocker = table.center[table.index_of(first)].double()
    sign = 1.0 if float((start - blocker) @ forward) >= 0 else -1.0
    K = intr.matrix(torch.float64)
    reach = 3 * float(dims[0]) + gap
    for direction in (sign, -sign):
        for k in range(1, int(reach / step) + 1):
            c = start + direction * k * step * forward
            if not (float(c[2]) > MIN_CLEARANCE + float(dims[0]) / 2 and float(c.norm()) <= MAX_DISTANCE):
                break
            u, v = project_points(c[None], K)[0].tolist()
            if not (-0.5 <= u <= intr.width - 0.5 and -0.5 <= v <= intr.height - 0.5):
                break
            if hit(c) is None:
                return (u, v), direction * k * step, None
    return uv, math.nan, first


def apply_edits(scene: SceneCode, ops: Sequence[EditOp], bank: MeshBank | None = None, grow: int = 2,
                amodal: bool = True) -> SceneCode:
    """Apply ``ops`` in order; returns a new scene (``scene`` is not modified).

    Args:
        scene: the scene to edit.
        ops: edit operations (module doc).
        bank: meshes for the footprints of observed objects without masks (default templates).
        grow: pixels a freed footprint grows into unclaimed pixels of the object's class.
        amodal: the objects behind a moved or deleted one cover the freed pixels their rendered silhouettes
            lie on (module doc); False: all freed pixels become background (an editor without 3D).

    Raises:
        EditError: unknown instance id, target outside the frame or below/above reach, an object moved
            closer than :data:`MIN_CLEARANCE` + half its length or farther than :data:`MAX_DISTANCE`, wrong
            code size.

    Example:
        >>> import torch
        >>> from sdn3d.editing.ops import Delete, Zoom
        >>> from sdn3d.math3d.camera import Intrinsics
        >>> from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
        >>> car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), location=(0.0, 1.6, 12.0))
        >>> scene = SceneCode(Intrinsics(60.0, 60.0, 31.5, 11.5, width=64, height=24),
        ...                   torch.zeros(24, 64, dtype=torch.long), "vkitti",
        ...                   ObjectTable.from_objects([car], 24, 64), background_codes={})
        >>> closer = apply_edits(scene, [Zoom(12001, 2.0)])  # half the distance, along the viewing ray
        >>> [round(x, 3) for x in closer.objects.center[0].tolist()], scene.objects.center[0, 2].item()
        ([0.0, 0.425, 6.0], 12.0)
        >>> len(apply_edits(scene, [Delete(12001)]).objects)
        0
    """
    return _apply_edits(scene, ops, bank, grow, _footprints, amodal)


def _apply_edits(scene: SceneCode, ops: Sequence[EditOp], bank: MeshBank | None, grow: int,
                 footprints: Callable[[SceneCode, Tensor, MeshBank | None, int], Tensor],
                 amodal: bool = True) -> SceneCode:
    table, codes = scene.objects, scene.background_codes
    copies = _Copies()  # duplicates are appended together, when an op names one of them or at the end: linear
    for op in ops:
        if copies.ids and int(getattr(op, "instance_id", -1)) in copies.ids:
            table = copies.into(table)
        table, codes = _apply_one(scene, table, codes, op, copies)
    table = copies.into(table)
    before = scene.objects
    # Rows of the input's observed objects in the result (-1: deleted).
    hit = (before.instance_id[:, None] == table.instance_id[None, :]).nonzero()
    row = torch.full((len(before),), -1, dtype=torch.long)
    row[hit[:, 0]] = hit[:, 1]
    kept = row >= 0
    same = torch.zeros(len(before), dtype=torch.bool)
    if bool(kept.any()):
        r = row[kept]
        same[kept] = ((table.location[r] - before.location[kept]).abs().amax(1) < 1e-9) & (
            wrap_angle(table.ry[r] - before.ry[kept]).abs() < 1e-9)
        # Unmoved objects stay exactly as they were (yaw bit-for-bit, mask, observed).
        r_same = row[same]
        ry, location = table.ry.clone(), table.location.clone()
        ry[r_same], location[r_same] = before.ry[same], before.location[same]
        moved = torch.zeros(len(table), dtype=torch.bool)
        moved[row[kept & ~same]] = True
        table = table.replace(ry=ry, location=location, mask=table.mask & ~moved[:, None, None],
                              has_mask=table.has_mask & ~moved, observed=table.observed & ~moved)
    vacate = before.observed & ~same
    semantic = scene.semantic
    if bool(vacate.any()):
        vacated = footprints(scene, vacate, bank, grow)
        if amodal:
            table = _reclaim(scene.replace(objects=table), vacated, bank)
        semantic = fill_background(scene.semantic, vacated, scene.thing_classes)
    return scene.replace(semantic=semantic, objects=table, background_codes=codes)


def _reclaim(scene: SceneCode, vacated: Tensor, bank: MeshBank | None) -> ObjectTable:
    """``scene.objects`` with each unmoved masked object's mask grown by its share of the ``vacated (H, W)``
    pixels: those where its rendered silhouette is the nearest among such objects' silhouettes (module doc)."""
    obj = scene.objects
    rows = (obj.has_mask & obj.has_geometry).nonzero().flatten()
    if not len(rows):
        return obj
    # Their silhouettes alone, composed in depth order (no masks: each object covers its render).
    alone = obj.select(rows)
    alone = alone.replace(mask=torch.zeros_like(alone.mask), has_mask=torch.zeros_like(alone.has_mask))
    silhouettes = compose_instances(scene.replace(objects=alone), bank).cpu()
    gained = vacated[None] & (silhouettes[None] == alone.instance_id[:, None, None])  # (R, H, W)
    if not bool(gained.any()):
        return obj
    mask = obj.mask.clone()
    mask[rows] |= gained
    return obj.replace(mask=mask)


def _footprints(scene: SceneCode, vacate: Tensor, bank: MeshBank | None, grow: int) -> Tensor:
    """``(H, W)`` pixels the objects ``vacate (N,)`` (observed) occupied in the image (module doc)."""
    obj = scene.objects
    region = obj.mask[vacate & obj.has_mask].any(0)
    if bool(obj.has_mask[obj.observed].all()):
        # Every observed object covers exactly its mask (sdn3d.scene.maps, step 2): nothing to render.
        occupied = obj.mask[obj.observed].any(0)
    else:
        inst = compose_instances(scene.replace(objects=obj.select(obj.observed)), bank).cpu()
        region |= torch.isin(inst, obj.instance_id[vacate])
        occupied = inst != 0
    return _grow(scene, vacate, region, occupied, grow)


def _grow(scene: SceneCode, vacate: Tensor, region: Tensor, occupied: Tensor, grow: int) -> Tensor:
    """``region`` grown by ``grow`` pixels into pixels of the vacating objects' classes not ``occupied``
    by other observed objects."""
    if grow > 0:
        grown = dilate_cross(region, int(grow))
        claimed = occupied & ~region
        same_class = torch.isin(scene.semantic.cpu(), scene.objects.class_id[vacate])
        region = region | (grown & same_class & ~claimed)
    return region


class ModifyAnchor(StrEnum):
    """Where a benchmark ``modify`` puts the picked object (:func:`ops_from_benchmark`).

    ``pick``: the object moves so that the point ``from`` lands on ``to``, its offset from there scaled by
    ``zoom``, as the 2D baselines paste it (:mod:`sdn3d.evaluation.baselines`) and as a drag moves a car in the
    editor; a de-rendered centre a few pixels off ``from`` keeps that offset. ``centre``: the object's de-rendered box
    centre goes to ``to`` (the offset of the de-rendered centre from ``from`` is added to every pixel's move).
    Both are the same for a centre that projects onto ``from``.
    """

    PICK = "pick"
    CENTRE = "centre"


def ops_from_benchmark(entry: BenchmarkEntry | Sequence[BenchmarkOperation], scene: SceneCode,
                       frame_size: tuple[int, int] | None = VKITTI_FRAME_SIZE, strict: bool = True,
                       max_distance: float | None = None, anchor: ModifyAnchor = ModifyAnchor.PICK,
                       bank: MeshBank | None = None) -> list[EditOp]:
    """Convert benchmark operations (:mod:`sdn3d.data.edit_benchmark`) to :class:`Modify` / :class:`Delete`.

    Args:
        entry: an entry or its operations.
        scene: the source scene; ``from`` picks objects as every edit does (:func:`sdn3d.editing.pick.pick_objects`:
            the mask under the point, else a box holding it, else the nearest projected centre; one object per
            operation, all resolved on the unedited scene; ``modify`` only picks objects with geometry).
        frame_size: ``(W, H)`` the coordinates refer to (the benchmark's 1242x375); they are mapped
            to the scene's size. None: already in the scene's pixels.
        strict: reject ``to`` points outside the frame (the published file needs ``strict=False``).
        max_distance: reject picks by centre farther than this many pixels (scene size) from any object.
        anchor: :class:`ModifyAnchor`, where a ``modify`` puts the object.
        bank: the scene's meshes (its composed instance map; default: the 8 templates).
    """
    anchor = ModifyAnchor(anchor)
    ops = list(entry.operations if isinstance(entry, BenchmarkEntry) else entry)
    if frame_size is not None and tuple(frame_size) != scene.image_size:
        ops = [scale_operation(op, tuple(frame_size), scene.image_size) for op in ops]
    ids = pick_objects(scene, [op.from_uv for op in ops], [op.kind == "modify" for op in ops], max_distance, bank=bank)
    if anchor is ModifyAnchor.PICK and any(op.kind == "modify" and op.to_uv is not None for op in ops):
        centers, _ = projected_centers(scene)
        row = {int(v): k for k, v in enumerate(scene.objects.instance_id.tolist())}
    out: list[EditOp] = []
    for op, i in zip(ops, ids, strict=True):
        if op.kind == "delete":
            out.append(Delete(i))
            continue
        to = op.to_uv
        if anchor is ModifyAnchor.PICK and to is not None:
            c = centers[row[i]].tolist()
            to = (to[0] + op.zoom * (c[0] - op.from_uv[0]), to[1] + op.zoom * (c[1] - op.from_uv[1]))
        out.append(Modify(i, to, op.zoom, op.ry, check_frame=strict))
    return out
