"""Object placement: canonical mesh frame to camera frame, 3D boxes and KITTI label fields.

Conventions (docs/ARCHITECTURE.md): the canonical frame is the unit box ``[-0.5, 0.5]^3`` with
+x the vehicle front (length l), +y down (height h, wheels at +0.5) and z the width w.
A canonical vertex ``v`` goes to the camera frame as ``R_y(ry) diag(l, h, w) v + c`` where
``c`` is the box centre. KITTI / Virtual KITTI labels give the centre of the *bottom* face
``(x3d, y3d, z3d)`` (y points down, so ``c = (x3d, y3d - h/2, z3d)``) and store the
dimensions as ``w3d h3d l3d``; the library's ``dims`` tensor is always ``(l, h, w)``.
"""

from __future__ import annotations

import torch
from torch import Tensor

from sdn3d.math3d.camera import project_points
from sdn3d.math3d.rotations import roty

__all__ = [
    "object_to_camera",
    "camera_to_object",
    "bottom_to_center",
    "center_to_bottom",
    "canonical_box_corners",
    "box_corners",
    "project_box",
    "ground_footprints",
    "convex_overlap",
    "dims_from_whl",
    "whl_from_dims",
    "from_kitti_fields",
    "to_kitti_fields",
]


def _check_last_dim(name: str, tensor: Tensor, size: int) -> None:
    if tensor.dim() < 1 or tensor.shape[-1] != size:
        raise ValueError(f"{name} must have a last dimension of size {size}, got shape {tuple(tensor.shape)}")


def _check_placement(dims: Tensor, ry: Tensor, center: Tensor) -> None:
    if dims.dim() != 2 or dims.shape[-1] != 3:
        raise ValueError(f"dims must have shape (B, 3) as (l, h, w), got {tuple(dims.shape)}")
    batch = dims.shape[0]
    if ry.shape != (batch,):
        raise ValueError(f"ry must have shape ({batch},) to match dims, got {tuple(ry.shape)}")
    if center.shape != (batch, 3):
        raise ValueError(f"center must have shape ({batch}, 3) to match dims, got {tuple(center.shape)}")


def object_to_camera(verts: Tensor, dims: Tensor, ry: Tensor, center: Tensor) -> Tensor:
    """Place canonical vertices in the camera frame: ``R_y(ry) diag(l, h, w) v + c``.

    Args:
        verts: ``(B, V, 3)`` canonical vertices (or ``(V, 3)``, shared by all objects).
        dims: ``(B, 3)`` dimensions ``(l, h, w)`` in metres.
        ry: ``(B,)`` yaw about the camera y axis.
        center: ``(B, 3)`` box centre in the camera frame.

    Returns:
        ``(B, V, 3)`` camera-frame vertices.
    """
    _check_placement(dims, ry, center)
    _check_last_dim("verts", verts, 3)
    if verts.dim() == 2:
        verts = verts.unsqueeze(0)
    if verts.dim() != 3 or verts.shape[0] not in (1, dims.shape[0]):
        raise ValueError(f"verts must have shape (B, V, 3) or (V, 3) with B={dims.shape[0]}, "
                         f"got {tuple(verts.shape)}")
    rot = roty(ry)
    # Row vectors: (v * dims) @ R^T applies diag(dims) then R to each vertex.
    return (verts * dims.unsqueeze(1)) @ rot.transpose(-1, -2) + center.unsqueeze(1)


def camera_to_object(points: Tensor, dims: Tensor, ry: Tensor, center: Tensor) -> Tensor:
    """Inverse of :func:`object_to_camera`: ``diag(1/l, 1/h, 1/w) R_y(ry)^T (p - c)``.

    Args:
        points: ``(B, V, 3)`` camera-frame points.
        dims, ry, center: as in :func:`object_to_camera`; ``dims`` must be positive.

    Returns:
        ``(B, V, 3)`` canonical coordinates.
    """
    _check_placement(dims, ry, center)
    _check_last_dim("points", points, 3)
    rot = roty(ry)
    return ((points - center.unsqueeze(1)) @ rot) / dims.unsqueeze(1)


def bottom_to_center(location: Tensor, h: Tensor) -> Tensor:
    """Box centre from the KITTI bottom-face centre: ``(x, y - h/2, z)`` (y points down).

    Args:
        location: ``(B, 3)`` bottom-face centres ``(x3d, y3d, z3d)``.
        h: ``(B,)`` heights.

    Returns:
        ``(B, 3)`` box centres.
    """
    _check_last_dim("location", location, 3)
    offset = torch.stack([torch.zeros_like(h), h / 2, torch.zeros_like(h)], -1)
    return location - offset


def center_to_bottom(center: Tensor, h: Tensor) -> Tensor:
    """Inverse of :func:`bottom_to_center`: ``(x, y + h/2, z)``."""
    _check_last_dim("center", center, 3)
    offset = torch.stack([torch.zeros_like(h), h / 2, torch.zeros_like(h)], -1)
    return center + offset


def canonical_box_corners(
    dtype: torch.dtype = torch.float32, device: torch.device | str | None = None
) -> Tensor:
    """The ``(8, 3)`` corners of the canonical unit box in KITTI devkit order.

    Corners 0-3 are the bottom face (y = +0.5, y points down) and 4-7 the top face, each
    face ordered front-left, front-right, back-right, back-left as the devkit's
    ``computeBox3D`` does: x = (+,+,-,-), z = (+,-,-,+).
    """
    x = [0.5, 0.5, -0.5, -0.5, 0.5, 0.5, -0.5, -0.5]
    y = [0.5, 0.5, 0.5, 0.5, -0.5, -0.5, -0.5, -0.5]
    z = [0.5, -0.5, -0.5, 0.5, 0.5, -0.5, -0.5, 0.5]
    return torch.tensor([x, y, z], dtype=dtype, device=device).T.contiguous()


def box_corners(dims: Tensor, ry: Tensor, center: Tensor) -> Tensor:
    """The 8 corners of each 3D box in the camera frame.

    Args:
        dims: ``(B, 3)`` as ``(l, h, w)``.
        ry: ``(B,)`` yaw.
        center: ``(B, 3)`` box centres.

    Returns:
        ``(B, 8, 3)`` corners, order of :func:`canonical_box_corners`.
    """
    corners = canonical_box_corners(dims.dtype, dims.device)
    return object_to_camera(corners, dims, ry, center)


def project_box(dims: Tensor, ry: Tensor, center: Tensor, K: Tensor) -> Tensor:
    """Tight 2D box ``(l, t, r, b)`` in pixels around the projected 3D box corners.

    No clipping to the image is done (a truncated object gets a box that leaves the image).

    Args:
        dims, ry, center: as in :func:`box_corners`.
        K: ``(3, 3)`` or ``(B, 3, 3)`` calibration.

    Returns:
        ``(B, 4)`` boxes.

    Raises:
        ValueError: if a corner lies at or behind the camera plane (``z <= 0``), where the
            projection of the box is not the box of the projection.
    """
    corners = box_corners(dims, ry, center)
    if bool((corners[..., 2] <= 0).any()):
        raise ValueError("project_box: some box corners have z <= 0 (behind the camera); cannot project")
    if K.dim() == 3:
        K = K.unsqueeze(1)
    uv = project_points(corners, K)
    return torch.cat([uv.amin(dim=1), uv.amax(dim=1)], dim=-1)


def ground_footprints(dims: Tensor, ry: Tensor, location: Tensor) -> Tensor:
    """``(B, 4, 2)`` float64: each box's bottom face seen from above, its corners' ``(x, z)`` in order around it
    (:func:`canonical_box_corners`' bottom face), from ``dims (B, 3)`` (l, h, w), ``ry (B,)`` and the bottom-face
    centres ``location (B, 3)`` (KITTI's ``x3d, y3d, z3d``).

    >>> f = ground_footprints(torch.tensor([[4.0, 1.5, 2.0]]), torch.zeros(1), torch.tensor([[1.0, 1.6, 10.0]]))
    >>> f[0].tolist()
    [[3.0, 11.0], [3.0, 9.0], [-1.0, 9.0], [-1.0, 11.0]]
    """
    _check_last_dim("location", location, 3)
    corners = box_corners(dims.double(), ry.double(), bottom_to_center(location.double(), dims[:, 1].double()))
    return corners[:, :4][..., [0, 2]]


def _signed_area(poly: list[tuple[float, float]]) -> float:
    return sum(poly[i - 1][0] * poly[i][1] - poly[i][0] * poly[i - 1][1] for i in range(len(poly))) / 2


def convex_overlap(a: Tensor, b: Tensor) -> float:
    """The area two convex polygons ``a (P, 2)`` and ``b (Q, 2)`` (corners in order around each, either way round)
    share: ``b`` clipped by each edge of ``a`` (Sutherland-Hodgman), 0 where they do not meet.

    >>> square = torch.tensor([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    >>> convex_overlap(square, square + 1), convex_overlap(square, square.flip(0) + 3)
    (1.0, 0.0)
    """
    clipper, poly = [tuple(p) for p in a.tolist()], [tuple(p) for p in b.tolist()]
    if _signed_area(clipper) < 0:  # the inside test below holds for counter-clockwise corners
        clipper = clipper[::-1]
    for i in range(len(clipper)):
        (x0, y0), (x1, y1) = clipper[i - 1], clipper[i]
        side = [(x1 - x0) * (y - y0) - (y1 - y0) * (x - x0) for x, y in poly]  # >= 0: left of the edge, inside
        out = []
        for j in range(len(poly)):
            (p, sp), (q, sq) = (poly[j - 1], side[j - 1]), (poly[j], side[j])
            if (sp >= 0) != (sq >= 0):  # the edge p -> q crosses the clipping line: keep the crossing
                t = sp / (sp - sq)
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
            if sq >= 0:
                out.append(q)
        poly = out
        if len(poly) < 3:
            return 0.0
    return abs(_signed_area(poly))


def dims_from_whl(w: Tensor, h: Tensor, l: Tensor) -> Tensor:
    """Stack the label file's ``w3d, h3d, l3d`` (each ``(...)``) into ``dims (..., 3)`` = (l, h, w).

    The order matches the canonical axes: x = length, y = height, z = width.
    """
    return torch.stack([l, h, w], dim=-1)


def whl_from_dims(dims: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Inverse of :func:`dims_from_whl`: ``(w, h, l)`` from ``dims (..., 3)`` = (l, h, w)."""
    _check_last_dim("dims", dims, 3)
    return dims[..., 2], dims[..., 1], dims[..., 0]


def from_kitti_fields(
    w3d: Tensor, h3d: Tensor, l3d: Tensor, x3d: Tensor, y3d: Tensor, z3d: Tensor, ry: Tensor
) -> tuple[Tensor, Tensor, Tensor]:
    """Library placement from (Virtual) KITTI label fields, each ``(B,)``.

    Returns:
        ``dims (B, 3)`` as (l, h, w), ``ry (B,)`` and the box centre ``center (B, 3)``.
    """
    dims = dims_from_whl(w3d, h3d, l3d)
    center = bottom_to_center(torch.stack([x3d, y3d, z3d], dim=-1), h3d)
    return dims, ry, center


def to_kitti_fields(dims: Tensor, ry: Tensor, center: Tensor) -> dict[str, Tensor]:
    """Inverse of :func:`from_kitti_fields`: keys ``w3d h3d l3d x3d y3d z3d ry``, each ``(B,)``."""
    w, h, l = whl_from_dims(dims)
    bottom = center_to_bottom(center, h)
    return {"w3d": w, "h3d": h, "l3d": l, "x3d": bottom[..., 0], "y3d": bottom[..., 1],
            "z3d": bottom[..., 2], "ry": ry}
