"""Mesh primitives of the synthetic street scenes and a builder that merges them into one mesh.

All geometry is in the world frame of a sequence (x right, y down, z forward along the road,
ground plane ``y = 0``). Each face carries the attributes the renderer and the texturer need:
semantic class id, material id (which procedural texture), base albedo (linear RGB) and eight
material parameters (e.g. a facade's window grid).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["StaticMesh", "MeshBuilder", "box_mesh", "prism_mesh", "regular_polygon", "icosphere"]

# Unit cube corners and outward-wound triangles (right-hand rule gives outward normals).
_CUBE_VERTS = (
    np.array(
        [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]],
        dtype=np.float64,
    )
    * 0.5
)
_CUBE_FACES = np.array(
    [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 6, 2],
        [3, 7, 6],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ],
    dtype=np.int64,
)


def box_mesh(center: np.ndarray, size: np.ndarray, yaw: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A closed box: ``(8, 3)`` vertices and ``(12, 3)`` faces.

    Args:
        center: ``(3,)`` box centre.
        size: ``(3,)`` extents along x, y, z before the yaw.
        yaw: rotation about y (same sense as the camera convention's ``roty``).
    """
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    verts = (_CUBE_VERTS * np.asarray(size, dtype=np.float64)) @ rot.T + np.asarray(center, dtype=np.float64)
    return verts, _CUBE_FACES.copy()


def regular_polygon(sides: int, radius: float, rotation: float = 0.0) -> np.ndarray:
    """``(sides, 2)`` corners of a regular polygon centred at the origin, counter-clockwise.

    ``rotation`` (radians) turns the first corner away from ``+x``; ``pi / 2`` puts it on ``+y``.
    """
    if sides < 3:
        raise ValueError(f"a polygon needs at least 3 sides, got {sides}")
    angle = rotation + 2.0 * np.pi * np.arange(sides) / sides
    return radius * np.stack([np.cos(angle), np.sin(angle)], axis=1)


def prism_mesh(
    polygon: np.ndarray, depth: float, center: np.ndarray, yaw: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """A closed flat prism: a convex polygon in the x-y plane extruded ``depth`` along z (a sign plate).

    Args:
        polygon: ``(K, 2)`` convex polygon corners (x, y) around the origin, in order.
        depth: thickness along z.
        center: ``(3,)`` centre of the prism.
        yaw: rotation about y (as :func:`box_mesh`).

    Returns:
        ``(2K, 3)`` vertices and ``(4K - 4, 3)`` outward-wound faces (fan caps and side quads).
    """
    poly = np.asarray(polygon, dtype=np.float64)
    k = len(poly)
    if poly.ndim != 2 or poly.shape[1] != 2 or k < 3:
        raise ValueError(f"polygon must be (K >= 3, 2) corners, got shape {poly.shape}")
    half = depth / 2.0
    verts = np.concatenate([np.c_[poly, np.full(k, -half)], np.c_[poly, np.full(k, half)]])
    fan = np.stack([np.zeros(k - 2, np.int64), np.arange(1, k - 1), np.arange(2, k)], axis=1)
    i, j = np.arange(k), (np.arange(k) + 1) % k
    sides = np.concatenate([np.stack([i, j, j + k], 1), np.stack([i, j + k, i + k], 1)])
    faces = np.concatenate([fan, fan + k, sides])
    # Orient every face away from the centroid (the prism is convex): outward winding whatever the order.
    tri = verts[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = (normal * (tri.mean(axis=1) - verts.mean(axis=0))).sum(axis=1) < 0
    faces[inward] = faces[inward][:, ::-1]
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return verts @ rot.T + np.asarray(center, dtype=np.float64), faces


def _icosahedron() -> tuple[np.ndarray, np.ndarray]:
    t = (1.0 + 5.0**0.5) / 2.0
    verts = np.array(
        [
            [-1, t, 0],
            [1, t, 0],
            [-1, -t, 0],
            [1, -t, 0],
            [0, -1, t],
            [0, 1, t],
            [0, -1, -t],
            [0, 1, -t],
            [t, 0, -1],
            [t, 0, 1],
            [-t, 0, -1],
            [-t, 0, 1],
        ],
        dtype=np.float64,
    )
    faces = np.array(
        [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ],
        dtype=np.int64,
    )
    return verts / np.linalg.norm(verts, axis=1, keepdims=True), faces


def _subdivide(verts: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split every triangle into four; shared edge midpoints are merged."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edges = np.sort(edges, axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    mid = verts[unique].mean(axis=1)
    mid /= np.linalg.norm(mid, axis=1, keepdims=True)
    base = len(verts)
    count = len(faces)
    m01, m12, m20 = (inverse[i * count : (i + 1) * count] + base for i in range(3))
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    new_faces = np.concatenate(
        [np.stack(f, axis=1) for f in ((a, m01, m20), (b, m12, m01), (c, m20, m12), (m01, m12, m20))]
    )
    return np.concatenate([verts, mid]), new_faces


_ICO_CACHE: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def icosphere(subdivisions: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Unit sphere: ``(V, 3)`` vertices and ``(F, 3)`` outward-wound faces (20 * 4^s faces)."""
    if subdivisions < 0:
        raise ValueError(f"subdivisions must be >= 0, got {subdivisions}")
    if subdivisions not in _ICO_CACHE:
        verts, faces = _icosahedron()
        for _ in range(subdivisions):
            verts, faces = _subdivide(verts, faces)
        _ICO_CACHE[subdivisions] = (verts, faces)
    verts, faces = _ICO_CACHE[subdivisions]
    return verts.copy(), faces.copy()


@dataclass
class StaticMesh:
    """The static part of a world as one triangle mesh with per-face attributes.

    Attributes:
        verts: ``(V, 3)`` float32 world-frame vertices.
        faces: ``(F, 3)`` int64 vertex indices.
        face_class: ``(F,)`` int64 class ids (``classes.CLASS_NAMES`` indices).
        face_material: ``(F,)`` int64 material ids (``classes.Material``).
        face_color: ``(F, 3)`` float32 base albedo, linear RGB in ``[0, 1]``.
        face_param: ``(F, 8)`` float32 material parameters.
        face_zmin / face_zmax: ``(F,)`` world z range of each face (for culling by distance).
    """

    verts: np.ndarray
    faces: np.ndarray
    face_class: np.ndarray
    face_material: np.ndarray
    face_color: np.ndarray
    face_param: np.ndarray
    face_zmin: np.ndarray = field(init=False)
    face_zmax: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        z = self.verts[self.faces][..., 2] if len(self.faces) else np.zeros((0, 3), np.float32)
        self.face_zmin = z.min(axis=1) if len(self.faces) else np.zeros(0, np.float32)
        self.face_zmax = z.max(axis=1) if len(self.faces) else np.zeros(0, np.float32)

    @property
    def num_faces(self) -> int:
        return int(len(self.faces))


class MeshBuilder:
    """Accumulates parts (vertices, faces, one attribute set per part) into a :class:`StaticMesh`."""

    def __init__(self) -> None:
        self._verts: list[np.ndarray] = []
        self._faces: list[np.ndarray] = []
        self._attrs: list[tuple[int, int, np.ndarray, np.ndarray, int]] = []
        self._count = 0

    def add(
        self,
        verts: np.ndarray,
        faces: np.ndarray,
        cls: int,
        material: int,
        color: tuple[float, float, float] | np.ndarray,
        param: tuple[float, ...] | np.ndarray = (0.0, 0.0, 0.0, 0.0),
    ) -> None:
        """Add one part; every face of it gets the same class, material, colour and parameters."""
        values = np.asarray(param, dtype=np.float64).ravel()[:8]
        param = np.zeros(8)
        param[: len(values)] = values
        self._verts.append(np.asarray(verts, dtype=np.float64))
        self._faces.append(np.asarray(faces, dtype=np.int64) + self._count)
        self._attrs.append((int(cls), int(material), np.asarray(color, np.float64), param, len(faces)))
        self._count += len(verts)

    def add_box(self, center, size, cls: int, material: int, color, param=(0.0,), yaw: float = 0.0) -> None:
        verts, faces = box_mesh(np.asarray(center), np.asarray(size), yaw)
        self.add(verts, faces, cls, material, color, param)

    def add_prism(self, polygon, depth: float, center, cls: int, material: int, color, param=(0.0,)) -> None:
        """Add a flat prism (:func:`prism_mesh`) facing along z."""
        verts, faces = prism_mesh(np.asarray(polygon), depth, np.asarray(center))
        self.add(verts, faces, cls, material, color, param)

    def build(self) -> StaticMesh:
        if not self._faces:
            raise ValueError("MeshBuilder.build: no parts were added")
        counts = [a[4] for a in self._attrs]
        return StaticMesh(
            verts=np.concatenate(self._verts).astype(np.float32),
            faces=np.concatenate(self._faces),
            face_class=np.repeat([a[0] for a in self._attrs], counts).astype(np.int64),
            face_material=np.repeat([a[1] for a in self._attrs], counts).astype(np.int64),
            face_color=np.repeat(np.stack([a[2] for a in self._attrs]), counts, axis=0).astype(np.float32),
            face_param=np.repeat(np.stack([a[3] for a in self._attrs]), counts, axis=0).astype(np.float32),
        )
