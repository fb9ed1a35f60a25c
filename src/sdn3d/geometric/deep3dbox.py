"""Deep3DBox translation from a 2D box (Mousavian et al., CVPR 2017): the box fit of Table 2's baseline
(:mod:`sdn3d.geometric.deep3dbox_net` predicts its yaw and dimensions).

Given an object's dimensions ``(l, h, w)``, yaw ``ry`` and calibration ``K``, the box centre
``T`` is chosen so that the projected 3D box fits tightly in the 2D box ``(l, t, r, b)``: each
side of the 2D box touches the projection of one of the 8 corners. For a corner at offset
``X`` from the centre (camera frame) and a side at pixel coordinate ``p`` along image row
``k`` of ``K`` (``k = 0`` for the left/right sides, ``1`` for top/bottom)::

    (K_k - p K_2) . (X + T) = 0      <=>      a . T = -a . X,   a = K_k - p K_2

which is linear in ``T``. The four sides give four equations in three unknowns, solved in
the least-squares sense for every candidate corner assignment.

Assignments: boxes here only rotate about the camera y axis, so every box edge along y is
vertical in the camera frame. The two corners of a vertical edge share ``x`` and ``z`` and
hence project to the same ``u``, and the top corner of an edge always projects above its
bottom corner (``z > 0``). So the top side touches one of the 4 top corners, the bottom side
one of the 4 bottom corners, and the left/right sides each one of the 4 vertical edges
(different ones): ``4 * 3 * 4 * 4 = 192`` assignments (the ``upright`` set), which always
contains the true one. Mousavian et al. reduce this to 64 with a heuristic on the
observation angle; enumerating all 192 is cheap and needs no heuristic.

The matrix ``A`` (rows ``a``) does not depend on the assignment, only the right-hand side
does, so one pseudo-inverse per object solves all 192 systems. Each candidate is scored by
projecting its 8 corners and comparing the tight box with the 2D box (IoU); candidates with a
corner at ``z <= 0`` are rejected, ties go to the smaller pixel error of the box sides.

Truncated objects: a side of the 2D box cut by the image border does not touch the projected
box. ``sides`` marks, per object, the sides to use; an unused side drops out of the linear
system, and when scoring, the candidate's projected box is clipped to the 2D box on that side
(a projection reaching past the border costs nothing there, one falling short still does).
At least three sides (so one of l/r and one of t/b) are needed for a unique solution; objects
with fewer use all four.

Solving runs in float64 (the systems mix pixel-scale and metre-scale terms); outputs come
back in the input dtype. No gradients are needed or provided (``torch.no_grad`` inside).
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import torch
from torch import Tensor

from sdn3d.math3d.camera import project_points
from sdn3d.math3d.transforms import box_corners, center_to_bottom

__all__ = [
    "Deep3DBoxSolution",
    "upright_assignments",
    "box_iou",
    "border_sides",
    "solve_translation",
    "deep3dbox_translation",
]

# Which row of K each box side constrains: l -> u, t -> v, r -> u, b -> v.
_SIDE_ROWS = (0, 1, 0, 1)
# Two candidates whose IoUs differ by less than this are ties, resolved by the residual.
_IOU_TIE = 1e-9


class Deep3DBoxSolution(NamedTuple):
    """Result of :func:`solve_translation` for ``N`` objects.

    Attributes:
        location: ``(N, 3)`` bottom-face centre (KITTI ``x3d, y3d, z3d``); NaN where no candidate is valid.
        center: ``(N, 3)`` box centre; NaN where no candidate is valid.
        iou: ``(N,)`` IoU of the chosen candidate's projected box with the 2D box (0 where invalid).
        residual: ``(N,)`` root-mean-square pixel error of the four box sides of the chosen candidate
            (NaN where invalid).
        assignment: ``(N, 4)`` int64 corner indices (order of
            :func:`~sdn3d.math3d.transforms.canonical_box_corners`) touching the sides ``l, t, r, b``.
        valid: ``(N,)`` bool, some candidate had every corner in front of the camera.
    """

    location: Tensor
    center: Tensor
    iou: Tensor
    residual: Tensor
    assignment: Tensor
    valid: Tensor


def upright_assignments(device: torch.device | str | None = None) -> Tensor:
    """The ``(192, 4)`` int64 corner assignments ``(left, top, right, bottom)`` of yaw-only boxes.

    Corners follow :func:`~sdn3d.math3d.transforms.canonical_box_corners`: 0-3 bottom face,
    4-7 top face, corner ``k + 4`` directly above corner ``k``. Left and right use the bottom
    corner ``k`` to stand for vertical edge ``k`` (both of its corners project to the same ``u``).
    """
    rows = [
        (left, top, right, bottom)
        for left, top, right, bottom in itertools.product(range(4), range(4, 8), range(4), range(4))
        if left != right
    ]
    return torch.tensor(rows, dtype=torch.long, device=device)


def box_iou(a: Tensor, b: Tensor) -> Tensor:
    """Element-wise IoU of boxes ``(..., 4)`` as ``(l, t, r, b)`` (continuous coordinates), shape ``(...)``.

    Degenerate boxes (zero area) give IoU 0 with anything.
    """
    if a.shape[-1] != 4 or b.shape[-1] != 4:
        raise ValueError(f"boxes must have a last dimension of 4 (l, t, r, b), got {tuple(a.shape)} "
                         f"and {tuple(b.shape)}")
    lt = torch.maximum(a[..., :2], b[..., :2])
    rb = torch.minimum(a[..., 2:], b[..., 2:])
    inter = (rb - lt).clamp(min=0).prod(-1)
    area_a = (a[..., 2:] - a[..., :2]).clamp(min=0).prod(-1)
    area_b = (b[..., 2:] - b[..., :2]).clamp(min=0).prod(-1)
    union = area_a + area_b - inter
    return torch.where(union > 0, inter / union.clamp(min=torch.finfo(union.dtype).tiny), torch.zeros_like(union))


def _check_inputs(box: Tensor, dims: Tensor, ry: Tensor, K: Tensor) -> Tensor:
    """Validate shapes/values; return ``K`` as ``(N, 3, 3)``."""
    if box.dim() != 2 or box.shape[-1] != 4:
        raise ValueError(f"box must have shape (N, 4) as (l, t, r, b), got {tuple(box.shape)}")
    n = box.shape[0]
    if dims.shape != (n, 3):
        raise ValueError(f"dims must have shape ({n}, 3) as (l, h, w) to match box, got {tuple(dims.shape)}")
    if ry.shape != (n,):
        raise ValueError(f"ry must have shape ({n},) to match box, got {tuple(ry.shape)}")
    if K.shape == (3, 3):
        K = K.expand(n, 3, 3)
    elif K.dim() != 3 or K.shape[1:] != (3, 3) or K.shape[0] not in (1, n):
        raise ValueError(f"K must have shape (3, 3) or ({n}, 3, 3), got {tuple(K.shape)}")
    K = K.expand(n, 3, 3)
    for name, tensor in (("box", box), ("dims", dims), ("ry", ry), ("K", K)):
        if not bool(torch.isfinite(tensor).all()):
            raise ValueError(f"{name} contains NaN or infinite values")
    if bool((dims <= 0).any()):
        raise ValueError("dims must be positive (l, h, w in metres)")
    if bool((box[:, 2] <= box[:, 0]).any()) or bool((box[:, 3] <= box[:, 1]).any()):
        raise ValueError("box must have r > l and b > t")
    if bool((K[:, 0, 0] <= 0).any()) or bool((K[:, 1, 1] <= 0).any()):
        raise ValueError("K must have positive focal lengths fx = K[0, 0] and fy = K[1, 1]")
    return K


def _solve_chunk(box: Tensor, offsets: Tensor, K: Tensor, assign: Tensor, use: Tensor) -> tuple[Tensor, ...]:
    """All candidates of one chunk (float64). box ``(N, 4)``, offsets ``(N, 8, 3)``, K ``(N, 3, 3)``,
    assign ``(M, 4)``, use ``(N, 4)`` bool. Returns center ``(N, 3)``, iou, residual ``(N,)``,
    index ``(N,)``, valid ``(N,)``."""
    n, m = box.shape[0], assign.shape[0]
    rows = K[:, list(_SIDE_ROWS), :]  # (N, 4, 3): K_k per side
    A = rows - box.unsqueeze(-1) * K[:, 2:3, :]  # (N, 4, 3): a = K_k - p K_2
    aX = A @ offsets.transpose(1, 2)  # (N, 4, 8): a_s . X_c for every side and corner
    side = torch.arange(4, device=box.device)
    weight = use.to(A.dtype)
    rhs = -aX[:, side, assign] * weight.unsqueeze(1)  # (N, M, 4): b[n, m, s] = -a_s . X_{assign[m, s]}
    # Zero rows of unused sides leave pinv's least-squares solution of the other rows unchanged.
    T = torch.einsum("nks,nms->nmk", torch.linalg.pinv(A * weight.unsqueeze(-1)), rhs)  # (N, M, 3)

    corners = offsets.unsqueeze(1) + T.unsqueeze(2)  # (N, M, 8, 3)
    valid = (corners[..., 2] > 0).all(-1)  # (N, M)
    # Project only candidates in front of the camera; the others get a dummy depth and are masked.
    safe = torch.where(valid[..., None, None], corners, torch.ones_like(corners))
    uv = project_points(safe, K[:, None, None])  # (N, M, 8, 2)
    proj = torch.cat([uv.amin(2), uv.amax(2)], -1)  # (N, M, 4)
    # Unused (truncated) sides: clip the projection to the 2D box there.
    target = box.unsqueeze(1).expand(n, m, 4)
    clipped = torch.cat([torch.maximum(proj[..., :2], target[..., :2]), torch.minimum(proj[..., 2:], target[..., 2:])],
                        -1)
    proj = torch.where(use.unsqueeze(1), proj, clipped)
    iou = torch.where(valid, box_iou(proj, target), torch.full_like(valid, -1.0, dtype=box.dtype))
    residual = (proj - target).pow(2).mean(-1).sqrt()  # (N, M) pixels

    best = iou.amax(1, keepdim=True)
    ties = valid & (iou >= best - _IOU_TIE)
    index = torch.where(ties, residual, torch.full_like(residual, float("inf"))).argmin(1)  # (N,)
    pick = index[:, None]
    ok = valid.any(1)
    center = torch.gather(T, 1, pick[..., None].expand(n, 1, 3))[:, 0]
    center = torch.where(ok[:, None], center, torch.full_like(center, float("nan")))
    residual = torch.gather(residual, 1, pick)[:, 0]
    residual = torch.where(ok, residual, torch.full_like(residual, float("nan")))
    return center, torch.gather(iou, 1, pick)[:, 0].clamp(min=0), residual, index, ok


def solve_translation(
    box: Tensor,
    dims: Tensor,
    ry: Tensor,
    K: Tensor,
    assignments: Tensor | None = None,
    sides: Tensor | None = None,
    chunk_size: int = 1024,
) -> Deep3DBoxSolution:
    """Deep3DBox translation of ``N`` objects from their 2D boxes (see the module doc).

    Args:
        box: ``(N, 4)`` 2D boxes ``(l, t, r, b)`` in pixels (continuous coordinates: the extent of the
            object's projection, not inclusive pixel indices).
        dims: ``(N, 3)`` dimensions ``(l, h, w)`` in metres.
        ry: ``(N,)`` yaw about the camera y axis.
        K: ``(3, 3)`` or ``(N, 3, 3)`` calibration.
        assignments: ``(M, 4)`` candidate corner indices for the sides ``(l, t, r, b)``;
            default :func:`upright_assignments` (exact for yaw-only boxes).
        sides: ``(N, 4)`` bool, the box sides ``(l, t, r, b)`` that the projection touches (False for
            sides cut by the image border); default all. Objects with fewer than 3 use all 4.
        chunk_size: objects solved at once (bounds memory: about ``chunk_size * M * 0.5`` KB).

    Returns:
        :class:`Deep3DBoxSolution` (location and center in the dtype of ``box``).
    """
    K = _check_inputs(box, dims, ry, K)
    if chunk_size <= 0:
        raise ValueError(f"chunk_size must be positive, got {chunk_size}")
    device, dtype = box.device, box.dtype
    assign = upright_assignments(device) if assignments is None else assignments.to(device=device)
    if assign.dim() != 2 or assign.shape[1] != 4 or assign.shape[0] == 0:
        raise ValueError(f"assignments must have shape (M, 4) with M > 0, got {tuple(assign.shape)}")
    if bool((assign < 0).any()) or bool((assign > 7).any()):
        raise ValueError("assignments must hold corner indices in [0, 7]")

    use = torch.ones(box.shape[0], 4, dtype=torch.bool, device=device) if sides is None else sides.to(device)
    if use.shape != (box.shape[0], 4) or use.dtype != torch.bool:
        raise ValueError(f"sides must be a bool tensor of shape ({box.shape[0]}, 4), got {use.dtype} "
                         f"{tuple(use.shape)}")
    use = torch.where(use.sum(-1, keepdim=True) >= 3, use, torch.ones_like(use))

    with torch.no_grad():
        box64, K64 = box.double(), K.double()
        dims64, ry64 = dims.double(), ry.double()
        offsets = box_corners(dims64, ry64, torch.zeros_like(dims64))  # (N, 8, 3) corners about the centre
        parts = [
            _solve_chunk(box64[i:i + chunk_size], offsets[i:i + chunk_size], K64[i:i + chunk_size], assign,
                         use[i:i + chunk_size])
            for i in range(0, box.shape[0], chunk_size)
        ]
        if parts:
            center, iou, residual, index, valid = (torch.cat(p) for p in zip(*parts, strict=True))
        else:
            center = box64.new_zeros(0, 3)
            iou, residual = box64.new_zeros(0), box64.new_zeros(0)
            index, valid = torch.zeros(0, dtype=torch.long, device=device), torch.zeros(0, dtype=torch.bool,
                                                                                       device=device)
        location = center_to_bottom(center, dims64[:, 1])
    return Deep3DBoxSolution(location.to(dtype), center.to(dtype), iou.to(dtype), residual.to(dtype),
                             assign[index], valid)


def deep3dbox_translation(box: Tensor, dims: Tensor, ry: Tensor, K: Tensor) -> tuple[Tensor, Tensor]:
    """``(location (N, 3), center (N, 3))``: bottom-face and box centres; see :func:`solve_translation`."""
    solution = solve_translation(box, dims, ry, K)
    return solution.location, solution.center


def border_sides(box: Tensor, image_size: tuple[int, int], tol: float = 1.0) -> Tensor:
    """``(N, 4)`` bool: the sides of ``(N, 4)`` boxes that lie more than ``tol`` pixels inside the image.

    A side within ``tol`` of the image border (``-0.5`` or ``W - 0.5`` / ``H - 0.5``, pixel-centre
    convention) is taken as cut by the border; pass the result as ``sides`` to :func:`solve_translation`.

    Args:
        box: ``(N, 4)`` boxes ``(l, t, r, b)`` in pixels.
        image_size: ``(W, H)``.
    """
    if box.dim() != 2 or box.shape[-1] != 4:
        raise ValueError(f"box must have shape (N, 4) as (l, t, r, b), got {tuple(box.shape)}")
    width, height = image_size
    if width <= 0 or height <= 0:
        raise ValueError(f"image_size must be positive (W, H), got {image_size}")
    lo = box.new_tensor([-0.5, -0.5]) + tol
    hi = box.new_tensor([width - 0.5, height - 0.5]) - tol
    return torch.cat([box[:, :2] > lo, box[:, 2:] < hi], dim=-1)
