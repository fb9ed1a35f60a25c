"""Static scenery of a synthetic street: ground bands, buildings, vegetation, street furniture.

Everything is built as world-frame boxes and icospheres into one :class:`StaticMesh` (see
``primitives.py``). The ground is cut into tiles (a few metres along the road) because the
renderer clips triangles at the near plane per frame: small tiles keep the clipped geometry
small and the far ground coarse.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sdn3d.data.synth.classes import CLASS_ID, Material
from sdn3d.data.synth.primitives import MeshBuilder, StaticMesh, icosphere

__all__ = ["WorldStyle", "WORLD_STYLES", "RoadGeometry", "build_static_scene"]

_FACADE_COLORS = np.array(
    [
        [0.45, 0.40, 0.33],
        [0.55, 0.50, 0.42],
        [0.35, 0.20, 0.15],
        [0.60, 0.58, 0.55],
        [0.30, 0.30, 0.32],
        [0.55, 0.42, 0.25],
        [0.40, 0.36, 0.38],
        [0.62, 0.55, 0.45],
        [0.25, 0.22, 0.20],
        [0.50, 0.33, 0.22],
    ]
)
_TRUCK_COLORS = np.array([[0.6, 0.6, 0.6], [0.5, 0.05, 0.03], [0.05, 0.1, 0.35], [0.7, 0.55, 0.05]])
_SIGN_COLORS = np.array([[0.55, 0.03, 0.02], [0.03, 0.12, 0.45], [0.75, 0.60, 0.02], [0.04, 0.25, 0.08]])


@dataclass(frozen=True)
class WorldStyle:
    """Street type of a world: cross-section and how dense each kind of scenery is."""

    fwd_lanes: int
    bwd_lanes: int
    lane_width: float
    parking: tuple[bool, bool]  # (left, right) parking strips with parked cars
    sidewalk: float  # sidewalk width (0: a narrow shoulder, then terrain)
    building_prob: float  # share of the roadside occupied by buildings
    building_height: tuple[float, float]
    tree_spacing: float  # mean spacing of roadside trees (0: none)
    forest: float  # trees per 100 m and side behind the roadside
    guard_rail: bool
    lamps: bool
    hedge_prob: float
    traffic_lights: bool
    trucks: int  # at most this many parked trucks


#: Styles of the five Virtual KITTI world names (loosely after the KITTI sequences they clone):
#: 0001 town street, 0002 country road, 0006 wide suburban road, 0018 tree-lined street,
#: 0020 highway. Other 4-digit names get a style drawn from their seed.
WORLD_STYLES: dict[str, WorldStyle] = {
    "0001": WorldStyle(1, 1, 3.5, (True, True), 2.5, 0.75, (6.0, 22.0), 10.0, 1.0, False, True, 0.2, True, 1),
    "0002": WorldStyle(1, 1, 3.3, (False, True), 0.0, 0.12, (4.0, 8.0), 0.0, 14.0, True, False, 0.5, False, 0),
    "0006": WorldStyle(2, 2, 3.5, (True, True), 3.0, 0.6, (8.0, 30.0), 13.0, 0.0, False, True, 0.3, True, 1),
    "0018": WorldStyle(1, 1, 3.4, (True, True), 2.0, 0.35, (5.0, 12.0), 7.0, 6.0, False, True, 0.4, False, 1),
    "0020": WorldStyle(2, 2, 3.7, (False, False), 0.0, 0.04, (5.0, 10.0), 0.0, 10.0, True, True, 0.3, False, 0),
}

@dataclass(frozen=True)
class RoadGeometry:
    """Cross-section of the street (world x of every band and lane, metres).

    ``lane_centers`` / ``lane_directions`` list every driving lane (+1 drives along +z);
    ``parking_centers`` the parking strips; the road surface spans ``[kerb_left, kerb_right]``,
    sidewalks ``[verge_left, kerb_left]`` and ``[kerb_right, verge_right]`` (empty when the
    width is 0), terrain lies beyond. ``marking_x`` / ``marking_dashed`` are the painted lines.
    """

    lane_width: float
    lane_centers: tuple[float, ...]
    lane_directions: tuple[int, ...]
    parking_centers: tuple[float, ...]
    parking_sides: tuple[int, ...]
    kerb_left: float
    kerb_right: float
    verge_left: float
    verge_right: float
    marking_x: tuple[float, ...]
    marking_dashed: tuple[bool, ...]
    marking_width: float = 0.14

    @property
    def forward_lanes(self) -> tuple[float, ...]:
        return tuple(x for x, d in zip(self.lane_centers, self.lane_directions, strict=True) if d > 0)

    @classmethod
    def from_style(cls, style: WorldStyle, rng: np.random.Generator) -> RoadGeometry:
        lw = style.lane_width
        fwd = [lw * (i + 0.5) for i in range(style.fwd_lanes)]
        bwd = [-lw * (i + 0.5) for i in range(style.bwd_lanes)]
        right, left = lw * style.fwd_lanes, -lw * style.bwd_lanes
        parking_centers, parking_sides = [], []
        marks = [(0.0, False)]
        marks += [(lw * i, True) for i in range(1, style.fwd_lanes)]
        marks += [(-lw * i, True) for i in range(1, style.bwd_lanes)]
        marks += [(right - 0.2, False), (left + 0.2, False)]
        if style.parking[1]:
            parking_centers.append(right + 1.2)
            parking_sides.append(1)
            right += 2.4
        else:
            right += 0.8
        if style.parking[0]:
            parking_centers.append(left - 1.2)
            parking_sides.append(-1)
            left -= 2.4
        else:
            left -= 0.8
        sidewalk = style.sidewalk * float(rng.uniform(0.9, 1.1))
        return cls(
            lane_width=lw,
            lane_centers=tuple(fwd + bwd),
            lane_directions=tuple([1] * len(fwd) + [-1] * len(bwd)),
            parking_centers=tuple(parking_centers),
            parking_sides=tuple(parking_sides),
            kerb_left=left,
            kerb_right=right,
            verge_left=left - sidewalk,
            verge_right=right + sidewalk,
            marking_x=tuple(m[0] for m in marks),
            marking_dashed=tuple(m[1] for m in marks),
        )


def _split(lo: float, hi: float, step: float) -> list[tuple[float, float]]:
    n = max(1, int(np.ceil((hi - lo) / step - 1e-9)))
    edges = np.linspace(lo, hi, n + 1)
    return list(zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True))


def _ground(builder: MeshBuilder, road: RoadGeometry, z_lo: float, z_hi: float, rng: np.random.Generator) -> None:
    """Tiles of road, sidewalk and terrain; fine near the path, coarse far ahead and aside."""
    terrain = (CLASS_ID["Terrain"], Material.TERRAIN, np.array([0.16, 0.20, 0.07]) * rng.uniform(0.8, 1.2))
    asphalt = (CLASS_ID["Road"], Material.ROAD, np.array([0.075, 0.075, 0.08]) * rng.uniform(0.8, 1.2))
    paving = (CLASS_ID["Road"], Material.SIDEWALK, np.array([0.30, 0.28, 0.26]) * rng.uniform(0.85, 1.1))
    bands = []
    for side in (-1, 1):
        verge = road.verge_left if side < 0 else road.verge_right
        kerb = road.kerb_left if side < 0 else road.kerb_right
        outer = [
            (verge, verge + side * 20.0, 8.0),
            (verge + side * 20.0, side * 80.0, 20.0),
            (side * 80.0, side * 400.0, 320.0),
        ]
        for a, b, step in outer:
            bands += [(min(p), max(p), terrain) for p in _split(min(a, b), max(a, b), step)]
        if abs(verge - kerb) > 1e-6:
            bands.append((min(verge, kerb), max(verge, kerb), paving))
    bands += [(a, b, asphalt) for a, b in _split(road.kerb_left, road.kerb_right, 8.0)]
    z_edges = [(a, b) for a, b in _split(z_lo, z_hi, 6.0)] + _split(z_hi, z_hi + 600.0, 100.0)
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    for x0, x1, (cls, material, color) in bands:
        for z0, z1 in z_edges:
            verts = np.array([[x0, 0.0, z0], [x1, 0.0, z0], [x1, 0.0, z1], [x0, 0.0, z1]])
            builder.add(verts, quad, cls, material, color)


def _tree(builder: MeshBuilder, rng: np.random.Generator, x: float, z: float, scale: float = 1.0) -> None:
    trunk_h = rng.uniform(1.6, 3.2) * scale
    radius = rng.uniform(1.4, 3.0) * scale
    builder.add_box(
        [x, -trunk_h / 2 - 0.3, z],
        [0.3 * scale, trunk_h + 0.6, 0.3 * scale],
        CLASS_ID["Tree"],
        Material.TRUNK,
        np.array([0.12, 0.08, 0.05]) * rng.uniform(0.7, 1.3),
    )
    verts, faces = icosphere(1)
    verts = verts * (1.0 + rng.uniform(-0.15, 0.15, size=(len(verts), 1)))
    verts = verts * np.array([radius, radius * rng.uniform(0.9, 1.4), radius])
    verts += np.array([x, -trunk_h - radius * 0.8, z])
    green = np.array([0.05, 0.13, 0.025]) * rng.uniform(0.7, 1.3) + np.array([0.02, 0.0, 0.0]) * rng.uniform()
    builder.add(verts, faces, CLASS_ID["Tree"], Material.CROWN, green, (rng.uniform(0, 1000),))


def _bush(builder: MeshBuilder, rng: np.random.Generator, x: float, z: float) -> None:
    verts, faces = icosphere(1)
    r = rng.uniform(0.5, 1.3)
    verts = verts * (1.0 + rng.uniform(-0.12, 0.12, size=(len(verts), 1))) * np.array([r, r * 0.7, r * 1.3])
    verts += np.array([x, -r * 0.45, z])
    builder.add(
        verts,
        faces,
        CLASS_ID["Vegetation"],
        Material.BUSH,
        np.array([0.07, 0.16, 0.03]) * rng.uniform(0.7, 1.3),
        (rng.uniform(0, 1000),),
    )


def _lots(
    builder: MeshBuilder,
    rng: np.random.Generator,
    style: WorldStyle,
    road: RoadGeometry,
    side: int,
    z_lo: float,
    z_hi: float,
    trucks_left: list[int],
) -> None:
    """Roadside lots one after another along z: building, parked truck or open ground."""
    verge = road.verge_left if side < 0 else road.verge_right
    z = z_lo
    while z < z_hi:
        kind = rng.uniform()
        if kind < style.building_prob:
            length, depth = rng.uniform(8.0, 25.0), rng.uniform(8.0, 16.0)
            height = rng.uniform(*style.building_height)
            setback = rng.uniform(0.3, 4.0)
            cx = verge + side * (setback + depth / 2)
            color = _FACADE_COLORS[rng.integers(len(_FACADE_COLORS))] * rng.uniform(0.8, 1.15)
            # param: window column spacing, floor height, window width share, shop-front flag
            param = (
                rng.uniform(2.2, 4.0),
                rng.uniform(2.8, 3.6),
                rng.uniform(0.35, 0.65),
                float(rng.uniform() < 0.4),
            )
            builder.add_box(
                [cx, -height / 2, z + length / 2],
                [depth, height, length],
                CLASS_ID["Building"],
                Material.FACADE,
                color,
                param,
            )
            if rng.uniform() < 0.5:  # roof box of another shade: a simple cornice
                builder.add_box(
                    [cx, -height - 0.3, z + length / 2],
                    [depth + 0.4, 0.6, length + 0.4],
                    CLASS_ID["Building"],
                    Material.ROOF,
                    color * 0.6,
                )
        elif kind < style.building_prob + 0.08 and trucks_left[0] > 0:
            trucks_left[0] -= 1
            length = rng.uniform(9.0, 13.0)
            cx = verge + side * rng.uniform(2.5, 5.0)
            color = _TRUCK_COLORS[rng.integers(len(_TRUCK_COLORS))]
            cargo_h = rng.uniform(3.0, 3.8)
            builder.add_box(
                [cx, -cargo_h / 2 - 0.5, z + length * 0.38],
                [2.5, cargo_h, length * 0.76],
                CLASS_ID["Truck"],
                Material.PLAIN,
                np.array([0.6, 0.6, 0.58]),
            )
            builder.add_box(
                [cx, -1.5, z + length * 0.88],
                [2.4, 2.9, length * 0.22],
                CLASS_ID["Truck"],
                Material.PLAIN,
                color,
            )
            builder.add_box(
                [cx, -0.35, z + length / 2],
                [2.3, 0.7, length * 0.98],
                CLASS_ID["Truck"],
                Material.PLAIN,
                np.array([0.03, 0.03, 0.03]),
            )
        else:
            length = rng.uniform(10.0, 35.0)
            for _ in range(int(rng.poisson(length * 0.12))):
                _bush(builder, rng, verge + side * rng.uniform(1.5, 10.0), z + rng.uniform(0, length))
            if rng.uniform() < style.hedge_prob:
                builder.add_box(
                    [verge + side * 0.8, -0.6, z + length / 2],
                    [0.9, rng.uniform(0.9, 1.6), length],
                    CLASS_ID["Vegetation"],
                    Material.BUSH,
                    np.array([0.05, 0.12, 0.03]),
                    (rng.uniform(0, 1000),),
                )
        z += length + rng.uniform(0.0, 5.0)


def _street_furniture(
    builder: MeshBuilder,
    rng: np.random.Generator,
    style: WorldStyle,
    road: RoadGeometry,
    side: int,
    z_lo: float,
    z_hi: float,
) -> None:
    kerb = road.kerb_left if side < 0 else road.kerb_right
    verge = road.verge_left if side < 0 else road.verge_right
    metal = np.array([0.25, 0.25, 0.26])
    if style.lamps:
        for z in np.arange(z_lo + rng.uniform(0, 30), z_hi, rng.uniform(22.0, 35.0)):
            h = rng.uniform(6.0, 8.0)
            x = kerb + side * 0.5
            builder.add_box([x, -h / 2, z], [0.18, h, 0.18], CLASS_ID["Pole"], Material.METAL, metal)
            builder.add_box([x - side * 0.9, -h + 0.05, z], [1.8, 0.1, 0.12], CLASS_ID["Pole"], Material.METAL, metal)
            builder.add_box(
                [x - side * 1.7, -h + 0.05, z],
                [0.6, 0.15, 0.3],
                CLASS_ID["Pole"],
                Material.METAL,
                np.array([0.5, 0.5, 0.45]),
            )
    for z in np.arange(z_lo + rng.uniform(0, 60), z_hi, rng.uniform(40.0, 90.0)):
        x = kerb + side * rng.uniform(0.4, 1.0)
        h = rng.uniform(2.2, 2.8)
        builder.add_box([x, -h / 2, z], [0.08, h, 0.08], CLASS_ID["Pole"], Material.METAL, metal)
        color = _SIGN_COLORS[rng.integers(len(_SIGN_COLORS))]
        size = rng.uniform(0.55, 0.8)
        center = [x, -h - size / 2 + 0.1, z - 0.06]
        # param: sign type, plate size, plate centre (the texture draws the sign in plate coordinates)
        builder.add_box(
            center,
            [size, size, 0.05],
            CLASS_ID["TrafficSign"],
            Material.SIGN,
            color,
            (float(rng.integers(3)), size, *center),
        )
    if style.traffic_lights:
        for z in np.arange(z_lo + rng.uniform(20, 80), z_hi, rng.uniform(70.0, 120.0)):
            x = kerb + side * 0.6
            h = rng.uniform(3.2, 4.5)
            builder.add_box([x, -h / 2, z], [0.14, h, 0.14], CLASS_ID["Pole"], Material.METAL, metal)
            center = [x, -h - 0.45, z - 0.15]
            # param: which lamp is lit (0 red, 1 amber, 2 green), housing centre
            builder.add_box(
                center,
                [0.35, 0.95, 0.3],
                CLASS_ID["TrafficLight"],
                Material.LIGHT,
                np.array([0.04, 0.04, 0.03]),
                (float(rng.integers(3)), 0.0, *center),
            )
    if style.guard_rail:
        x = (kerb + side * 0.4) if abs(verge - kerb) < 1e-6 else verge + side * 0.3
        for z0, z1 in _split(z_lo, z_hi, 8.0):
            builder.add_box(
                [x, -0.62, (z0 + z1) / 2],
                [0.08, 0.32, z1 - z0],
                CLASS_ID["GuardRail"],
                Material.METAL,
                np.array([0.45, 0.46, 0.47]),
            )
            builder.add_box(
                [x + side * 0.1, -0.38, z0 + 0.5],
                [0.12, 0.76, 0.12],
                CLASS_ID["GuardRail"],
                Material.METAL,
                np.array([0.3, 0.3, 0.3]),
            )
    # Misc: bins, benches and fence pieces on the sidewalk or the verge.
    for _ in range(int(rng.poisson((z_hi - z_lo) / 40.0))):
        z = rng.uniform(z_lo, z_hi)
        kind = rng.integers(3)
        x = verge + side * rng.uniform(0.3, 1.5) if kind == 2 else kerb + side * rng.uniform(0.8, 1.6)
        size = ([0.6, 1.0, 0.6], [0.6, 0.9, 1.8], [0.1, 1.2, rng.uniform(3.0, 10.0)])[kind]
        builder.add_box(
            [x, -size[1] / 2, z],
            size,
            CLASS_ID["Misc"],
            Material.PLAIN,
            np.array([0.15, 0.12, 0.10]) * rng.uniform(0.6, 1.6),
        )


def build_static_scene(
    rng: np.random.Generator, style: WorldStyle, road: RoadGeometry, z_range: tuple[float, float]
) -> StaticMesh:
    """The static mesh of a world: ground, lots, roadside trees, forest, street furniture.

    Args:
        rng: the world's scenery generator.
        style: street style.
        road: cross-section.
        z_range: world z span with detailed scenery (the ground continues 600 m beyond).
    """
    z_lo, z_hi = z_range
    builder = MeshBuilder()
    _ground(builder, road, z_lo, z_hi, rng)
    trucks_left = [int(rng.integers(0, style.trucks + 1))]
    for side in (-1, 1):
        verge = road.verge_left if side < 0 else road.verge_right
        _lots(builder, rng, style, road, side, z_lo, z_hi, trucks_left)
        _street_furniture(builder, rng, style, road, side, z_lo, z_hi)
        if style.tree_spacing > 0:
            z = z_lo + rng.uniform(0, style.tree_spacing)
            while z < z_hi:
                if rng.uniform() < 0.85:
                    x = (
                        verge - side * 0.7
                        if abs(verge - (road.kerb_left if side < 0 else road.kerb_right)) > 1.5
                        else verge + side * 1.0
                    )
                    _tree(builder, rng, x, z)
                z += style.tree_spacing * rng.uniform(0.6, 1.4)
        forest = rng.poisson(style.forest * (z_hi - z_lo) / 100.0)
        # Behind the building lots (at most 20 m deep) where there are buildings.
        start = 4.0 if style.building_prob < 0.3 else 21.0
        for _ in range(int(forest)):
            x = verge + side * (start + rng.exponential(12.0))
            _tree(builder, rng, x, rng.uniform(z_lo, z_hi), scale=rng.uniform(0.9, 1.5))
    return builder.build()
