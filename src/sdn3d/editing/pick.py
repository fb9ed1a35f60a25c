"""Which object an edit's point names: the one picking rule of the editor, ``sdn3d-edit`` and the benchmark.

A point ``(u, v)`` (working pixels) picks, in order (:attr:`PickBy.VISIBLE`, what a user sees):

1. the object whose listed centre it is: its projected centre (:func:`projected_centers`, as the listing prints it)
   within :data:`CENTRE_SNAP` of the image width, even where another object hides it (a listed centre pasted as the
   point, and the synthetic benchmark's ``from`` points, which are the cars' projected centres);
2. else the object whose mask is under the point: the front one, from the composed instance map
   (:func:`~sdn3d.scene.maps.compose_instances`);
3. else, among the objects whose listed box (the box of their visible mask, as the listing prints it) holds the point,
   the nearest in front (objects without geometry last);
4. else the object whose projected centre is nearest, within ``max_distance`` pixels.

Several points (a benchmark entry's operations) are resolved together by a minimum-cost one-to-one assignment whose
cost puts every tier before the next (a mask hit before any box, a box before any centre), so two picks never take
the same object: a second point on the same car falls to its next tier.

Edits that need 3D geometry (move, turn, zoom, duplicate, the benchmark's ``modify``) pick among the objects that
have it in every tier. What happens where the front object under such a point has a mask only (under ``min_pixels``,
or no usable prediction) is :class:`MaskOnlyUnder`: a user's point (``sdn3d-edit``'s and the editor's ``at``) is
refused, naming that object (:attr:`MaskOnlyUnder.REFUSE`: moving another car than the one pointed at would
surprise); a benchmark's ``from`` point passes over it to the next tier (:attr:`MaskOnlyUnder.PASS_OVER`: a box
holding the point, a centre within ``max_distance``, as the benchmark always did), and only where none is left is it
refused, naming it. Refusing benchmark entries at once would leave them unscored for 3D-SDN alone, which would
flatter its means.

:attr:`PickBy.CENTRE` is the projected-centre tier alone: the synthetic benchmark's definition of the car an
operation edits (its ``from`` point is that car's projected centre, :mod:`sdn3d.data.synth.edits`), used on the
ground-truth scene for the edited regions (:func:`sdn3d.evaluation.edit_benchmark.edit_regions`).

The 3D-SDN paper's benchmark picks the proposal whose 2D box centre is nearest the point, each point on its own
(ysymyth/3D-SDN ``geometric/scripts/main.py``); rules 2 and 3 keep it on the visible proposal as that does whatever
the 3D fit, and the assignment keeps two operations off one object.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from enum import StrEnum

import torch
from torch import Tensor

from sdn3d.editing.ops import EditError, _uv, shown_point
from sdn3d.image_ops import any_along, any_set, mask_boxes, mask_centroids
from sdn3d.math3d.camera import project_points
from sdn3d.meshes.bank import MeshBank
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import compose_instances

__all__ = ["PickBy", "MaskOnlyUnder", "pick_objects", "projected_centers", "CENTRE_SNAP"]

#: A point within this share of the image width of an object's projected centre picks that object first (2 px at
#: 312 wide; docs/results/2026-11-30_cpu/session18/pick: a wider snap takes mis-fitted proposals' centres).
CENTRE_SNAP = 1 / 150

#: Maps a working pixel to the user's pixels (for messages).
ToUser = Callable[[tuple[float, float]], tuple[float, float]]

# Assignment costs: each tier's costs lie below the next tier's base, whatever the points' number (at most a few).
_MASK = 1e2  # the snap tier costs its distance, under CENTRE_SNAP of the width
_BOX_BASE = 1e4  # + the object's depth (metres, capped): the nearest in front first
_NO_DEPTH = 5e3  # the depth an object without geometry counts with in the box tier
_CENTRE_BASE = 1e8  # + the distance to the projected centre (pixels)
_BARRED = 1e15


class PickBy(StrEnum):
    """How :func:`pick_objects` reads a point (module doc)."""

    VISIBLE = "visible"
    CENTRE = "centre"


class MaskOnlyUnder(StrEnum):
    """What a point whose edit needs geometry does where the front object under it has a mask only (module doc)."""

    REFUSE = "refuse"
    PASS_OVER = "pass_over"


def projected_centers(scene: SceneCode) -> tuple[Tensor, Tensor]:
    """``(N, 2)`` float64 pixel of each object's box centre (mask centroid without geometry) and
    ``(N,)`` bool validity (centre in front of the camera, or a non-empty mask)."""
    obj = scene.objects
    center = obj.center
    valid_3d = obj.has_geometry & (center[:, 2] > 0)
    safe = torch.where(valid_3d[:, None], center, center.new_tensor([0.0, 0.0, 1.0]))
    uv = project_points(safe, scene.intrinsics.matrix(torch.float64))
    use_mask = ~obj.has_geometry & any_along(obj.mask.flatten(1), 1)
    if any_set(use_mask):
        uv = torch.where(use_mask[:, None], mask_centroids(obj.mask), uv)
    return uv, valid_3d | use_mask


def pick_objects(scene: SceneCode, points: Sequence[tuple[float, float]], need_geometry: Sequence[bool] | None = None,
                 max_distance: float | None = None, by: PickBy = PickBy.VISIBLE, instance_map: Tensor | None = None,
                 bank: MeshBank | None = None, to_user: ToUser | None = None,
                 shown: Sequence[tuple[float, float]] | None = None,
                 mask_only: MaskOnlyUnder = MaskOnlyUnder.PASS_OVER) -> list[int]:
    """Instance ids of the objects ``points`` pick (module doc), one object per point.

    Args:
        scene: the unedited scene.
        points: ``(u, v)`` in the scene's pixels.
        need_geometry: per point, whether its edit needs 3D geometry (default: none does).
        max_distance: the farthest (pixels) a projected centre may be from its point (the centre tier); None: any.
        by: :class:`PickBy`.
        instance_map: ``(H, W)`` the scene's composed instance map, when the caller has it (else it is composed
            with ``bank``; only :attr:`PickBy.VISIBLE` reads it).
        to_user, shown: for messages: the map from working pixels to the user's, and the points as the user wrote
            them (default: the points themselves).
        mask_only: :class:`MaskOnlyUnder`, for the points that need geometry (only :attr:`PickBy.VISIBLE` reads it).

    Raises:
        EditError: more points than objects to pick from; a point no tier matches (naming it and the nearest
            objects; a point needing geometry whose front object has a mask only names that object).
    """
    by, mask_only = PickBy(by), MaskOnlyUnder(mask_only)
    points = [_uv(p, "pick") for p in points]
    if not points:
        return []
    obj = scene.objects
    centers, valid = projected_centers(scene)
    need = torch.tensor(list(need_geometry) if need_geometry is not None else [False] * len(points), dtype=torch.bool)
    usable = ~need[:, None] | obj.has_geometry[None, :]  # (P, N)
    at = torch.tensor(points, dtype=torch.float64)
    dist = torch.cdist(at, centers) if len(obj) else torch.zeros(len(points), 0, dtype=torch.float64)
    in_reach = valid[None, :] & (dist <= max_distance if max_distance is not None else torch.ones_like(usable))
    cost = torch.where(usable & in_reach, _CENTRE_BASE + dist, torch.full_like(dist, _BARRED))
    visible = by is PickBy.VISIBLE and len(obj) > 0
    # (P,) the instance id of the front object under each point, 0 = none
    under = _under(scene, at, instance_map, bank) if visible else torch.zeros(len(points), dtype=torch.long)
    is_under = obj.instance_id[None, :] == under[:, None]  # (P, N)
    on_mask_only = (is_under & ~usable).any(1)  # (P,) the front object under the point has no geometry it needs

    def refuse_mask_only(r: int) -> EditError:
        shown_at = shown[r] if shown is not None else points[r]
        return EditError(_mask_only(scene, int(under[r]), shown_at, dist[r], valid, to_user, mask_only))

    if mask_only is MaskOnlyUnder.REFUSE and bool(on_mask_only.any()):
        raise refuse_mask_only(int(on_mask_only.nonzero()[0]))
    if visible:
        boxes = mask_boxes(obj.mask).double()
        holds = ((boxes[None, :, 0] <= at[:, None, 0]) & (at[:, None, 0] < boxes[None, :, 2])
                 & (boxes[None, :, 1] <= at[:, None, 1]) & (at[:, None, 1] < boxes[None, :, 3])
                 & (boxes[None, :, 2] > boxes[None, :, 0]))  # (P, N)
        depth = torch.where(obj.has_geometry, obj.location[:, 2].double().clamp(0, _NO_DEPTH - 1), _NO_DEPTH)
        cost = torch.where(holds & usable, (_BOX_BASE + depth)[None, :].expand_as(cost), cost)
        cost = torch.where(is_under & usable, torch.full_like(cost, _MASK), cost)
        snap = CENTRE_SNAP * scene.image_size[0]
        snap = min(snap, max_distance) if max_distance is not None else snap
        cost = torch.where(usable & valid[None, :] & (dist <= snap), dist, cost)
    candidates = int((valid | obj.mask.flatten(1).any(1)).sum())
    if len(points) > candidates:
        raise EditError(f"{len(points)} edits but only {candidates} objects to pick from")
    from scipy.optimize import linear_sum_assignment  # here: importing scipy.optimize costs every edit call ~0.3 s

    rows, cols = linear_sum_assignment(cost.numpy())
    out = [0] * len(points)
    for r, c in zip(rows.tolist(), cols.tolist(), strict=True):
        if cost[r, c] >= _BARRED:
            if on_mask_only[r]:
                raise refuse_mask_only(r)
            shown_at = shown[r] if shown is not None else points[r]
            raise EditError(_miss(scene, points[r], dist[r], valid & usable[r], max_distance, by, to_user, shown_at))
        out[r] = int(obj.instance_id[c])
    return out


def _under(scene: SceneCode, at: Tensor, instance_map: Tensor | None, bank: MeshBank | None) -> Tensor:
    """``(P,)`` int64 the instance id of the front object at each point ``at (P, 2)`` (0: none, or off the image)."""
    if instance_map is None:
        instance_map = compose_instances(scene, bank)
    instance_map = instance_map.cpu()
    height, width = instance_map.shape
    inside = (at[:, 0] >= -0.5) & (at[:, 0] <= width - 0.5) & (at[:, 1] >= -0.5) & (at[:, 1] <= height - 0.5)
    cols = at[:, 0].round().clamp(0, width - 1).long()
    rows = at[:, 1].round().clamp(0, height - 1).long()
    return torch.where(inside, instance_map[rows, cols].long(), 0)


def _nearest(scene: SceneCode, shown_at: tuple[float, float], dist: Tensor, allowed: Tensor,
             to_user: ToUser | None, count: int = 3) -> str:
    """The ``count`` nearest ``allowed`` objects by projected centre, in the user's pixels:
    "id (d px, centre [u, v])"."""
    centers, _ = projected_centers(scene)
    order = torch.argsort(torch.where(allowed, dist, torch.full_like(dist, math.inf)))
    near = []
    for row in order.tolist()[:count]:
        if bool(allowed[row]):
            u, v = (to_user or (lambda uv: uv))((float(centers[row, 0]), float(centers[row, 1])))
            far = math.hypot(u - shown_at[0], v - shown_at[1])
            near.append(f"{int(scene.objects.instance_id[row])} ({far:.0f} px, centre {shown_point((u, v))})")
    return ", ".join(near)


def _miss(scene: SceneCode, point: tuple[float, float], dist: Tensor, allowed: Tensor, max_distance: float | None,
          by: PickBy, to_user: ToUser | None,
          shown_at: tuple[float, float]) -> str:
    """Why ``point`` (shown as ``shown_at``) picks no object: its tiers, and the nearest objects it may pick."""
    near = _nearest(scene, shown_at, dist, allowed, to_user)
    tiers = "no mask or listed box holds it, and " if by is PickBy.VISIBLE else ""
    reach = f"within {max_distance} px (working size)" if max_distance is not None else "left to pick"
    return (f"no object at {shown_point(shown_at)}: {tiers}no centre is {reach}"
            + (f"; the nearest: {near}" if near else "; the scene has no object to pick"))


def _mask_only(scene: SceneCode, iid: int, shown_at: tuple[float, float], dist: Tensor, valid: Tensor,
               to_user: ToUser | None, mask_only: MaskOnlyUnder) -> str:
    """The refusal of a point needing geometry whose front object ``iid`` has a mask only (with
    :attr:`MaskOnlyUnder.PASS_OVER`: and no object with geometry holds the point in its box or has its centre within
    reach)."""
    pixels = int(scene.objects.mask[scene.objects.index_of(iid)].sum())
    near = _nearest(scene, shown_at, dist, valid & scene.objects.has_geometry, to_user)
    passed = (", and no object with geometry holds the point or is within reach"
              if mask_only is MaskOnlyUnder.PASS_OVER else "")
    return (f"the edit at {shown_point(shown_at)} lands on object {iid}, which has no 3D geometry, only its mask of "
            f"{pixels} pixels (under min_pixels, or no usable prediction): it can be deleted or recoloured, not "
            f"moved, turned or zoomed{passed}" + (f"; the nearest objects with geometry: {near}" if near else ""))
