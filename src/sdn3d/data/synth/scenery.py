"""Static scenery of a synthetic street: ground bands, buildings, vegetation, street furniture.

Everything is built as world-frame boxes, flat prisms (sign plates) and icospheres into one
:class:`StaticMesh` (see ``primitives.py``). The ground is cut into tiles (a few metres along the road)
because the renderer clips triangles at the near plane per frame: small tiles keep the clipped geometry
small and the far ground coarse.

Street furniture follows the world's :class:`WorldStyle`: intersections with a side street and traffic
signals on every corner (mast arms over the lanes of wide roads) in the towns, street lamps, utility poles
on the country road, sign posts with plates of several shapes (round, triangular, octagonal, diamond,
rectangular boards), sign gantries over the motorway, guard rails along the country road and the motorway,
in the middle of the wide road and on stretches of the tree-lined street, misc objects, and parked trucks
(``Truck`` is a scenery class in Virtual KITTI) in yards and lay-bys. Every world keeps about 9-19k
triangles (trees are most of them).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from sdn3d.data.synth.classes import CLASS_ID, Material
from sdn3d.data.synth.primitives import MeshBuilder, StaticMesh, icosphere, prism_mesh, regular_polygon

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
#: Sign colours: red, blue, yellow, green.
_SIGN_COLORS = np.array([[0.55, 0.03, 0.02], [0.03, 0.12, 0.45], [0.75, 0.60, 0.02], [0.04, 0.25, 0.08]])
#: Pole paint: galvanised grey, dark green, anthracite.
_POLE_COLORS = np.array([[0.25, 0.25, 0.26], [0.06, 0.12, 0.08], [0.09, 0.09, 0.1]])


@dataclass(frozen=True)
class WorldStyle:
    """Street type of a world: cross-section and how dense each kind of scenery is.

    Spacings are mean distances along the road in metres (0: none); ``*_lots`` are shares of the
    roadside lots; ``misc_density`` counts objects per 100 m and side.
    """

    # Cross-section.
    fwd_lanes: int
    bwd_lanes: int
    lane_width: float
    parking: tuple[bool, bool]  # (left, right) parking strips with parked cars
    sidewalk: float  # sidewalk width (0: a narrow shoulder, then terrain)
    # Roadside lots and vegetation.
    building_prob: float  # share of the roadside lots that are buildings
    building_height: tuple[float, float]
    truck_lots: float  # share of the roadside lots that are yards (lay-bys) with a parked truck
    tree_spacing: float  # roadside trees
    forest: float  # trees per 100 m and side behind the roadside
    hedge_prob: float
    # Street furniture.
    lamp_spacing: float  # street lamps, both sides
    utility_pole_spacing: float  # wooden utility poles, one side
    sign_spacing: float  # sign posts, per side
    crossing_spacing: float  # intersections with traffic lights
    gantry_spacing: float  # overhead sign gantries (motorways)
    guard_rail: float  # share of each roadside behind a guard rail
    median_rail: bool  # a guard rail between the two directions
    misc_density: float  # bins, benches, bollards, boxes, fences, shelters

    def varied(self, rng: np.random.Generator) -> WorldStyle:
        """This style with another lane width and building share (worlds without a fixed style)."""
        return replace(
            self,
            lane_width=float(rng.uniform(3.2, 3.8)),
            building_prob=float(np.clip(self.building_prob + rng.uniform(-0.1, 0.1), 0, 1)),
        )


#: Styles of the five Virtual KITTI world names (loosely after the KITTI sequences they clone).
#: Other 4-digit names get one of them, varied (:meth:`WorldStyle.varied`). Spacings follow common
#: European streets: lamps every 25-45 m, a signalised intersection every 100-150 m in towns, sign posts
#: every 30-90 m, utility poles every 40-50 m on country roads, a sign gantry every few hundred metres on
#: motorways.
WORLD_STYLES: dict[str, WorldStyle] = {
    "0001": WorldStyle(  # town street: shops and flats, parking both sides
        fwd_lanes=1, bwd_lanes=1, lane_width=3.5, parking=(True, True), sidewalk=2.5,
        building_prob=0.7, building_height=(6.0, 22.0), truck_lots=0.2, tree_spacing=10.0, forest=1.0,
        hedge_prob=0.2, lamp_spacing=28.0, utility_pole_spacing=0.0, sign_spacing=32.0,
        crossing_spacing=110.0, gantry_spacing=0.0, guard_rail=0.0, median_rail=False, misc_density=5.0,
    ),
    "0002": WorldStyle(  # country road: fields, farms, forest, guard rails
        fwd_lanes=1, bwd_lanes=1, lane_width=3.3, parking=(False, True), sidewalk=0.0,
        building_prob=0.12, building_height=(4.0, 8.0), truck_lots=0.15, tree_spacing=0.0, forest=14.0,
        hedge_prob=0.5, lamp_spacing=0.0, utility_pole_spacing=45.0, sign_spacing=60.0,
        crossing_spacing=0.0, gantry_spacing=0.0, guard_rail=1.0, median_rail=False, misc_density=1.0,
    ),
    "0006": WorldStyle(  # wide suburban road: 2 + 2 lanes, a median rail, commercial lots
        fwd_lanes=2, bwd_lanes=2, lane_width=3.5, parking=(True, True), sidewalk=3.0,
        building_prob=0.55, building_height=(8.0, 30.0), truck_lots=0.2, tree_spacing=13.0, forest=0.0,
        hedge_prob=0.3, lamp_spacing=32.0, utility_pole_spacing=0.0, sign_spacing=35.0,
        crossing_spacing=140.0, gantry_spacing=0.0, guard_rail=0.0, median_rail=True, misc_density=3.0,
    ),
    "0018": WorldStyle(  # tree-lined street: houses, gardens, a guard rail here and there
        fwd_lanes=1, bwd_lanes=1, lane_width=3.4, parking=(True, True), sidewalk=2.0,
        building_prob=0.35, building_height=(5.0, 12.0), truck_lots=0.18, tree_spacing=7.0, forest=6.0,
        hedge_prob=0.4, lamp_spacing=30.0, utility_pole_spacing=0.0, sign_spacing=38.0,
        crossing_spacing=150.0, gantry_spacing=0.0, guard_rail=0.25, median_rail=False, misc_density=2.0,
    ),
    "0020": WorldStyle(  # motorway: 2 + 2 lanes, rails on both sides and in the middle, gantries
        fwd_lanes=2, bwd_lanes=2, lane_width=3.7, parking=(False, False), sidewalk=0.0,
        building_prob=0.04, building_height=(5.0, 10.0), truck_lots=0.15, tree_spacing=0.0, forest=10.0,
        hedge_prob=0.3, lamp_spacing=45.0, utility_pole_spacing=0.0, sign_spacing=90.0,
        crossing_spacing=0.0, gantry_spacing=300.0, guard_rail=1.0, median_rail=True, misc_density=0.5,
    ),
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


def _in_gaps(z: float, gaps: list[tuple[float, float]], margin: float = 0.0) -> bool:
    return any(a - margin <= z <= b + margin for a, b in gaps)


def _minus(spans: list[tuple[float, float]], gaps: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """``spans`` (z intervals) with the ``gaps`` cut out."""
    for g0, g1 in gaps:
        spans = [piece for a, b in spans for piece in ((a, min(b, g0)), (max(a, g1), b)) if piece[1] - piece[0] > 0.5]
    return spans


def _positions(rng: np.random.Generator, spacing: float, z_lo: float, z_hi: float, jitter: float = 0.25) -> np.ndarray:
    """Positions along z at a mean ``spacing`` (each gap ``spacing * U(1 - jitter, 1 + jitter)``)."""
    if spacing <= 0:
        return np.zeros(0)
    z = z_lo + rng.uniform(0.0, spacing)
    out = []
    while z < z_hi:
        out.append(z)
        z += spacing * rng.uniform(1.0 - jitter, 1.0 + jitter)
    return np.array(out)


def _staged_positions(
    rng: np.random.Generator, spacing: float, z_lo: float, z_hi: float, first: tuple[float, float]
) -> np.ndarray:
    """Positions at a mean ``spacing`` of which one lies ``first`` metres ahead of the camera's start (z = 0).

    A sequence is a short drive (the camera starts at z = 0, ``layout.CameraPath``); like a clip cut from a
    long drive where the next signal or gantry is in sight, one of them is placed in the first stretch ahead.
    """
    if spacing <= 0:
        return np.zeros(0)
    anchor = rng.uniform(*first)
    ahead, behind = [anchor], []
    while ahead[-1] < z_hi:
        ahead.append(ahead[-1] + spacing * rng.uniform(0.8, 1.25))
    while (behind[-1] if behind else anchor) > z_lo:
        behind.append((behind[-1] if behind else anchor) - spacing * rng.uniform(0.8, 1.25))
    z = np.array(behind[::-1] + ahead)
    return z[(z > z_lo + 5.0) & (z < z_hi - 5.0)]


def _truck(builder: MeshBuilder, rng: np.random.Generator, cx: float, z0: float) -> float:
    """A parked truck (box truck or articulated lorry) starting at ``z0`` along z; returns its length."""
    semi = rng.uniform() < 0.4
    cab_len, cab_h = rng.uniform(2.0, 2.5), rng.uniform(2.8, 3.2)
    cargo_len = rng.uniform(12.0, 13.6) if semi else rng.uniform(5.0, 8.0)
    cargo_h = rng.uniform(3.0, 3.6) if semi else rng.uniform(2.4, 3.2)
    length = cab_len + 0.3 + cargo_len
    forward = rng.uniform() < 0.5  # cab towards +z or -z
    cab_z = z0 + length - cab_len / 2 if forward else z0 + cab_len / 2
    cargo_z = z0 + cargo_len / 2 if forward else z0 + length - cargo_len / 2
    truck, black = CLASS_ID["Truck"], np.array([0.03, 0.03, 0.03])
    cab_color = _TRUCK_COLORS[rng.integers(len(_TRUCK_COLORS))] * rng.uniform(0.85, 1.1)
    cargo_color = _TRUCK_COLORS[rng.integers(len(_TRUCK_COLORS))] if rng.uniform() < 0.4 else np.full(3, 0.62)
    builder.add_box([cx, -cab_h / 2 - 0.45, cab_z], [2.45, cab_h, cab_len], truck, Material.PLAIN, cab_color)
    builder.add_box([cx, -cargo_h / 2 - 1.1, cargo_z], [2.55, cargo_h, cargo_len], truck, Material.PLAIN,
                    cargo_color * rng.uniform(0.85, 1.1))
    builder.add_box([cx, -0.8, z0 + length / 2], [1.2, 0.5, length * 0.95], truck, Material.PLAIN, black)
    axles = [cab_z] + [cargo_z + d * cargo_len for d in ((-0.3, 0.3) if not semi else (0.25, 0.33, 0.41))]
    for z in axles:  # wheels: one dark box per axle
        builder.add_box([cx, -0.5, z], [2.4, 1.0, 1.0], truck, Material.PLAIN, black)
    return length


def _building(builder: MeshBuilder, rng: np.random.Generator, style: WorldStyle, x: float, z: float,
              side: int, longest: float) -> float:
    """A building lot (8 m to ``longest`` long) starting at ``z`` next to ``x`` (the verge); returns its length."""
    length, depth = rng.uniform(8.0, longest), rng.uniform(8.0, 16.0)
    height = rng.uniform(*style.building_height)
    cx = x + side * (rng.uniform(0.3, 4.0) + depth / 2)
    color = _FACADE_COLORS[rng.integers(len(_FACADE_COLORS))] * rng.uniform(0.8, 1.15)
    # param: window column spacing, floor height, window width share, shop-front flag
    param = (rng.uniform(2.2, 4.0), rng.uniform(2.8, 3.6), rng.uniform(0.35, 0.65), float(rng.uniform() < 0.4))
    building = CLASS_ID["Building"]
    builder.add_box([cx, -height / 2, z + length / 2], [depth, height, length], building, Material.FACADE, color,
                    param)
    if rng.uniform() < 0.5:  # roof box of another shade: a simple cornice
        builder.add_box([cx, -height - 0.3, z + length / 2], [depth + 0.4, 0.6, length + 0.4], building,
                        Material.ROOF, color * 0.6)
    return length


def _lots(
    builder: MeshBuilder,
    rng: np.random.Generator,
    style: WorldStyle,
    road: RoadGeometry,
    side: int,
    z_range: tuple[float, float],
    gaps: list[tuple[float, float]],
) -> None:
    """Roadside lots one after another along z: building, truck yard or open ground; none across a side street."""
    verge = road.verge_left if side < 0 else road.verge_right
    kerb = road.kerb_left if side < 0 else road.kerb_right
    z, z_hi = z_range
    while z < z_hi:
        gap = next(((a, b) for a, b in gaps if b > z), (np.inf, np.inf))
        room = gap[0] - z  # free road side before the next side street
        if room < 8.0:
            z = gap[1] + rng.uniform(0.0, 2.0)
            continue
        kind = rng.uniform()
        if kind < style.building_prob:
            length = _building(builder, rng, style, verge, z, side, min(room, 25.0))
        elif kind < style.building_prob + style.truck_lots and room > 20.0:
            # A yard beside the sidewalk, or a lay-by a few metres off a road without one.
            offset = rng.uniform(2.0, 4.0) if abs(verge - kerb) > 1e-6 else rng.uniform(4.0, 8.0)
            length = _truck(builder, rng, verge + side * offset, z + rng.uniform(0.5, 2.0)) + 2.0
        else:
            length = min(rng.uniform(10.0, 35.0), room)
            for _ in range(int(rng.poisson(length * 0.12))):
                _bush(builder, rng, verge + side * rng.uniform(1.5, 10.0), z + rng.uniform(0, length))
            if rng.uniform() < style.hedge_prob:
                builder.add_box([verge + side * 0.8, -0.6, z + length / 2], [0.9, rng.uniform(0.9, 1.6), length],
                                CLASS_ID["Vegetation"], Material.BUSH, np.array([0.05, 0.12, 0.03]),
                                (rng.uniform(0, 1000),))
        z += length + rng.uniform(0.0, 5.0)


def _cross_street(builder: MeshBuilder, rng: np.random.Generator, road: RoadGeometry, z: float, width: float) -> None:
    """Asphalt of a side street (one or both sides) from the kerb outwards, just above the ground tiles."""
    asphalt = np.array([0.075, 0.075, 0.08]) * rng.uniform(0.8, 1.2)
    sides = [s for s in (-1, 1) if rng.uniform() < 0.75] or [int(rng.choice([-1, 1]))]
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    for side in sides:
        kerb = road.kerb_left if side < 0 else road.kerb_right
        for x0, x1 in _split(0.0, 40.0, 8.0):
            a, b = sorted((kerb + side * x0, kerb + side * x1))
            verts = np.array([[a, -0.01, z - width / 2], [b, -0.01, z - width / 2], [b, -0.01, z + width / 2],
                              [a, -0.01, z + width / 2]])
            builder.add(verts, quad, CLASS_ID["Road"], Material.ROAD, asphalt)


def _signal_head(builder: MeshBuilder, center: list[float], facing: int, lit: int, size: float = 1.0) -> None:
    """A three-lamp signal head with its backplate, lamps towards ``-z`` (``facing = -1``) or ``+z``.

    The texture draws lamps on faces looking towards ``-z`` (the driving camera); a head turned to ``+z``
    shows the camera its dark back (its texture centre is moved away so that no lamp is drawn).
    """
    light = CLASS_ID["TrafficLight"]
    lamp_centre = list(center) if facing < 0 else [center[0] + 100.0, center[1], center[2]]
    # param: which lamp is lit (0 red, 1 amber, 2 green), housing centre
    builder.add_box(center, [0.34 * size, 0.95 * size, 0.28], light, Material.LIGHT, np.array([0.04, 0.04, 0.03]),
                    (float(lit), 0.0, *lamp_centre))
    plate = [center[0], center[1], center[2] - facing * 0.16]
    builder.add_box(plate, [0.6 * size, 1.25 * size, 0.03], light, Material.PLAIN, np.array([0.05, 0.05, 0.05]))


def _traffic_signals(
    builder: MeshBuilder, rng: np.random.Generator, style: WorldStyle, road: RoadGeometry, z: float, width: float
) -> None:
    """Signals of an intersection at ``z``: a pole on every corner with heads for both directions, pedestrian
    heads, and on roads of two or more lanes per direction a mast arm with one head over every lane."""
    metal = _POLE_COLORS[rng.integers(len(_POLE_COLORS))]
    lit = int(rng.integers(3))
    pole, light = CLASS_ID["Pole"], CLASS_ID["TrafficLight"]
    for side in (-1, 1):
        x = (road.kerb_left if side < 0 else road.kerb_right) + side * 0.6
        for zc in (z - width / 2 - 1.0, z + width / 2 + 1.0):
            mast = style.fwd_lanes >= 2 and ((side > 0) == (zc < z))
            h = rng.uniform(5.8, 6.4) if mast else rng.uniform(2.9, 3.4)
            builder.add_box([x, -h / 2, zc], [0.16, h, 0.16], pole, Material.METAL, metal)
            top = -min(h, 3.4) - 0.55
            _signal_head(builder, [x, top, zc - 0.2], -1, lit)
            _signal_head(builder, [x, top, zc + 0.2], 1, lit)
            builder.add_box([x - side * 0.25, -2.3, zc], [0.22, 0.55, 0.25], light, Material.PLAIN,
                            np.array([0.05, 0.05, 0.05]))  # pedestrian head, turned across the road
            if mast:  # arm over the lanes of the direction facing this pole
                lanes = road.forward_lanes if side > 0 else [c for c, d in zip(road.lane_centers,
                                                                               road.lane_directions, strict=True)
                                                             if d < 0]
                far = min(lanes, key=lambda c: side * c)
                builder.add_box([(x + far) / 2, -h + 0.3, zc], [abs(x - far) + 0.6, 0.14, 0.14], pole,
                                Material.METAL, metal)
                for lane_x in lanes:
                    _signal_head(builder, [lane_x, -h - 0.3 + 1.05, zc - side * 0.2], -side, lit)


def _sign_plate(builder: MeshBuilder, rng: np.random.Generator, x: float, top: float, z: float, scale: float) -> float:
    """One sign plate facing along z, its top edge at height ``top`` (y, negative up); returns its height.

    Kinds: round (red ring on white, or a blue disc), warning triangle, give-way triangle, stop octagon,
    priority diamond, rectangular information board (blue, green or white, with a panel).
    """
    sign, white = CLASS_ID["TrafficSign"], np.full(3, 0.75)
    kind = int(rng.choice(7, p=[0.22, 0.14, 0.2, 0.08, 0.06, 0.1, 0.2]))
    r = rng.uniform(0.3, 0.42) * scale
    w, h = rng.uniform(0.5, 1.3) * scale, rng.uniform(0.35, 0.8) * scale
    heights = {0: 2 * r, 1: 2 * r, 2: 2.25 * r, 3: 2.25 * r, 4: 2.2 * r * np.cos(np.pi / 8), 5: 1.5 * r * 2**0.5}
    height = heights.get(kind, h)
    center = [x, top + height / 2, z]
    front = [x, top + height / 2, z - 0.03]
    # Texture param (appearance._sign): kind (0 ring, 1 disc, 2 diamond), plate size, plate centre; a size
    # of 100 paints the whole plate in its colour.
    if kind <= 1:  # round: prohibition (red ring on white) or mandatory (blue disc)
        builder.add_prism(regular_polygon(12, r), 0.04, center, sign, Material.SIGN, _SIGN_COLORS[kind],
                          (float(kind), 2 * r, *center))
    elif kind <= 3:  # warning (point up) or give way (point down): red triangle with a white inside
        # Polygon y is world y (down): a corner at -pi/2 points up. The centroid lies a quarter of the
        # circumradius (1.5 r) off the middle of the height, towards the base.
        turn, c = (-np.pi / 2, 0.375 * r) if kind == 2 else (np.pi / 2, -0.375 * r)
        center[1] += c
        front[1] += c
        builder.add_prism(regular_polygon(3, 1.5 * r, turn), 0.04, center, sign, Material.SIGN, _SIGN_COLORS[0],
                          (1.0, 100.0, *center))
        builder.add_prism(regular_polygon(3, 0.9 * r, turn), 0.02, front, sign, Material.SIGN, white,
                          (1.0, 100.0, *front))
    elif kind == 4:  # stop
        builder.add_prism(regular_polygon(8, 1.1 * r, np.pi / 8), 0.04, center, sign, Material.SIGN,
                          _SIGN_COLORS[0], (1.0, 100.0, *center))
    elif kind == 5:  # priority road: a yellow square on its corner, white border
        builder.add_prism(regular_polygon(4, 0.75 * r * 2**0.5), 0.04, center, sign, Material.SIGN, white,
                          (1.0, 100.0, *center))
        builder.add_prism(regular_polygon(4, 0.5 * r * 2**0.5), 0.02, front, sign, Material.SIGN, _SIGN_COLORS[2],
                          (1.0, 100.0, *front))
    else:  # information board
        color = (_SIGN_COLORS[1], _SIGN_COLORS[3], white)[int(rng.integers(3))]
        builder.add_box(center, [w, h, 0.04], sign, Material.SIGN, color, (1.0, 100.0, *center))
        panel = _SIGN_COLORS[int(rng.integers(len(_SIGN_COLORS)))] if color is white else white
        builder.add_box(front, [0.45 * w, 0.5 * h, 0.02], sign, Material.SIGN, panel, (1.0, 100.0, *front))
    return height


def _sign_post(builder: MeshBuilder, rng: np.random.Generator, x: float, z: float, scale: float) -> None:
    """A post with one or two sign plates at its top."""
    h = rng.uniform(2.1, 2.6) * max(scale, 1.0)
    builder.add_box([x, -h / 2, z], [0.07, h, 0.07], CLASS_ID["Pole"], Material.METAL, _POLE_COLORS[0])
    top = -h - 0.1
    for _ in range(1 + int(rng.uniform() < 0.3)):
        top += _sign_plate(builder, rng, x, top, z - 0.06, scale) + 0.08


def _gantry(builder: MeshBuilder, rng: np.random.Generator, road: RoadGeometry, z: float) -> None:
    """A sign gantry across a motorway: two posts beyond the shoulders, a beam, direction boards over both
    carriageways (the ones for the other direction show their backs)."""
    pole, sign = CLASS_ID["Pole"], CLASS_ID["TrafficSign"]
    metal = np.array([0.42, 0.43, 0.45])
    h = rng.uniform(6.5, 7.2)
    x0, x1 = road.kerb_left - 1.2, road.kerb_right + 1.2
    for x in (x0, x1):
        builder.add_box([x, -h / 2, z], [0.35, h, 0.35], pole, Material.METAL, metal)
    builder.add_box([(x0 + x1) / 2, -h + 0.3, z], [x1 - x0, 0.6, 0.4], pole, Material.METAL, metal)
    color = _SIGN_COLORS[1] if rng.uniform() < 0.5 else _SIGN_COLORS[3]
    for direction in (-1, 1):
        lanes = [c for c, d in zip(road.lane_centers, road.lane_directions, strict=True) if d == -direction]
        for lane_x in lanes:
            w, bh = rng.uniform(3.0, 3.6), rng.uniform(1.8, 2.4)
            center = [lane_x, -h + 0.6 + bh / 2, z + direction * 0.3]
            builder.add_box(center, [w, bh, 0.08], sign, Material.SIGN, color, (1.0, 100.0, *center))
            panel = [lane_x, center[1] - 0.2 * bh, z + direction * 0.36]
            builder.add_box(panel, [0.4 * w, 0.3 * bh, 0.02], sign, Material.SIGN, np.full(3, 0.75),
                            (1.0, 100.0, *panel))


def _lamp(builder: MeshBuilder, rng: np.random.Generator, x: float, z: float, side: int, color: np.ndarray) -> None:
    """A street lamp: post, arm over the road, luminaire."""
    pole = CLASS_ID["Pole"]
    h = rng.uniform(6.0, 8.0)
    builder.add_box([x, -h / 2, z], [0.18, h, 0.18], pole, Material.METAL, color)
    builder.add_box([x - side * 0.9, -h + 0.05, z], [1.8, 0.1, 0.12], pole, Material.METAL, color)
    builder.add_box([x - side * 1.7, -h + 0.05, z], [0.6, 0.15, 0.3], pole, Material.METAL, np.array([0.5, 0.5, 0.45]))


def _utility_pole(builder: MeshBuilder, rng: np.random.Generator, x: float, z: float) -> None:
    """A wooden utility pole with a cross arm and insulators."""
    pole, wood = CLASS_ID["Pole"], np.array([0.22, 0.15, 0.09]) * rng.uniform(0.8, 1.2)
    h = rng.uniform(7.5, 9.0)
    builder.add_box([x, -h / 2, z], [0.26, h, 0.26], pole, Material.TRUNK, wood)
    builder.add_box([x, -h + 0.6, z], [2.0, 0.12, 0.12], pole, Material.TRUNK, wood)
    for dx in (-0.85, 0.0, 0.85):
        builder.add_box([x + dx, -h + 0.42, z], [0.08, 0.22, 0.08], pole, Material.PLAIN, np.full(3, 0.6))


def _guard_rail(builder: MeshBuilder, x: float, side: int, spans: list[tuple[float, float]],
                width: float = 0.08) -> None:
    """A steel guard rail at ``x`` along ``spans`` (z intervals), posts every 4 m on its ``side`` (0: under it,
    a median rail with beams on both faces is ``width`` wide)."""
    rail = CLASS_ID["GuardRail"]
    for z_lo, z_hi in spans:
        for z0, z1 in _split(z_lo, z_hi, 8.0):
            builder.add_box([x, -0.62, (z0 + z1) / 2], [width, 0.32, z1 - z0], rail, Material.METAL,
                            np.array([0.45, 0.46, 0.47]))
            for zp in np.arange(z0 + 0.5, z1, 4.0):
                builder.add_box([x + side * 0.1, -0.38, zp], [0.12, 0.76, 0.12], rail, Material.METAL,
                                np.array([0.3, 0.3, 0.3]))


def _rail_spans(rng: np.random.Generator, share: float, z_lo: float, z_hi: float) -> list[tuple[float, float]]:
    """Stretches with a guard rail: everywhere for ``share >= 1``, else 30-90 m pieces covering about ``share``."""
    if share >= 1.0:
        return [(z_lo, z_hi)]
    spans, z = [], z_lo
    while share > 0 and z < z_hi:
        length = rng.uniform(30.0, 90.0)
        if rng.uniform() < share:
            spans.append((z, min(z + length, z_hi)))
        z += length
    return spans


#: Misc objects: (name, size x y z, colour); fences get a random length.
_MISC = (
    ("bin", (0.6, 1.0, 0.6), (0.10, 0.16, 0.10)),
    ("bench", (0.6, 0.9, 1.8), (0.22, 0.14, 0.08)),
    ("bollard", (0.15, 0.9, 0.15), (0.20, 0.20, 0.20)),
    ("utility box", (0.5, 1.3, 0.9), (0.35, 0.36, 0.32)),
    ("fence", (0.1, 1.2, 0.0), (0.18, 0.14, 0.10)),
    ("advertising column", (1.2, 3.0, 1.2), (0.40, 0.30, 0.18)),
    ("bus shelter", (1.4, 2.5, 3.5), (0.25, 0.30, 0.32)),
)


def _misc(builder: MeshBuilder, rng: np.random.Generator, style: WorldStyle, road: RoadGeometry, side: int,
          z_lo: float, z_hi: float) -> None:
    """Bins, benches, bollards, utility boxes, fences, advertising columns and bus shelters."""
    kerb = road.kerb_left if side < 0 else road.kerb_right
    verge = road.verge_left if side < 0 else road.verge_right
    urban = abs(verge - kerb) > 1e-6
    weights = np.array([3, 2, 2, 2, 3, 1, 1] if urban else [1, 0, 1, 2, 6, 0, 0], dtype=np.float64)
    for _ in range(int(rng.poisson(style.misc_density * (z_hi - z_lo) / 100.0))):
        name, size, color = _MISC[int(rng.choice(len(_MISC), p=weights / weights.sum()))]
        size = (size[0], size[1], rng.uniform(3.0, 10.0)) if name == "fence" else size
        at_verge = name in ("fence", "bus shelter", "advertising column") or not urban
        x = verge + side * rng.uniform(0.3, 1.5) if at_verge else kerb + side * rng.uniform(0.6, 1.4)
        x = x + side * size[0] / 2 if name in ("bus shelter", "advertising column") else x
        z = rng.uniform(z_lo, z_hi)
        colour = np.array(color) * rng.uniform(0.7, 1.4)
        if name == "advertising column":
            builder.add(*_column(x, z, size), CLASS_ID["Misc"], Material.PLAIN, colour)
        elif name == "bus shelter":  # roof and back wall
            builder.add_box([x, -size[1], z], [size[0], 0.12, size[2]], CLASS_ID["Misc"], Material.PLAIN, colour)
            builder.add_box([x + side * size[0] / 2, -size[1] / 2, z], [0.06, size[1], size[2]], CLASS_ID["Misc"],
                            Material.PLAIN, colour * 1.5)
        else:
            builder.add_box([x, -size[1] / 2, z], size, CLASS_ID["Misc"], Material.PLAIN, colour)


def _column(x: float, z: float, size: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """An upright octagonal column (``size``: diameter, height, diameter) standing on the ground at (x, z)."""
    verts, faces = prism_mesh(regular_polygon(8, size[0] / 2, np.pi / 8), size[1], np.zeros(3))
    verts = verts[:, [0, 2, 1]] * np.array([1.0, -1.0, 1.0])  # a rotation: extrusion axis z -> up (-y)
    return verts + np.array([x, -size[1] / 2, z]), faces


def _street_furniture(
    builder: MeshBuilder,
    rng: np.random.Generator,
    style: WorldStyle,
    road: RoadGeometry,
    side: int,
    z_range: tuple[float, float],
    gaps: list[tuple[float, float]],
) -> None:
    """Lamps, utility poles, sign posts, guard rails and misc objects along one side of the road."""
    z_lo, z_hi = z_range
    kerb = road.kerb_left if side < 0 else road.kerb_right
    verge = road.verge_left if side < 0 else road.verge_right
    lamp_color = _POLE_COLORS[int(rng.integers(len(_POLE_COLORS)))]
    for z in _positions(rng, style.lamp_spacing, z_lo, z_hi, jitter=0.1):
        _lamp(builder, rng, kerb + side * 0.5, z, side, lamp_color)
    if side < 0 and style.utility_pole_spacing > 0:  # utility poles on one side (left)
        for z in _positions(rng, style.utility_pole_spacing, z_lo, z_hi, jitter=0.1):
            _utility_pole(builder, rng, verge + side * rng.uniform(1.5, 3.0), z)
    scale = 1.6 if style.gantry_spacing > 0 else 1.0  # larger signs along motorways
    for z in _positions(rng, style.sign_spacing, z_lo, z_hi, jitter=0.6):
        if not _in_gaps(z, gaps, 1.0):
            _sign_post(builder, rng, kerb + side * rng.uniform(0.4, 1.0) * max(scale, 1.0), z, scale)
    spans = _minus(_rail_spans(rng, style.guard_rail, z_lo, z_hi), gaps)
    if spans:
        _guard_rail(builder, (kerb + side * 0.4) if abs(verge - kerb) < 1e-6 else verge + side * 0.3, side, spans)
    _misc(builder, rng, style, road, side, z_lo, z_hi)


def _trees(builder: MeshBuilder, rng: np.random.Generator, style: WorldStyle, road: RoadGeometry, side: int,
           z_range: tuple[float, float], gaps: list[tuple[float, float]]) -> None:
    """Roadside trees (a row along the verge) and forest behind the lots; none on a side street."""
    z_lo, z_hi = z_range
    verge = road.verge_left if side < 0 else road.verge_right
    kerb = road.kerb_left if side < 0 else road.kerb_right
    if style.tree_spacing > 0:
        z = z_lo + rng.uniform(0, style.tree_spacing)
        while z < z_hi:
            if rng.uniform() < 0.85 and not _in_gaps(z, gaps, 2.0):
                _tree(builder, rng, verge - side * 0.7 if abs(verge - kerb) > 1.5 else verge + side * 1.0, z)
            z += style.tree_spacing * rng.uniform(0.6, 1.4)
    forest = rng.poisson(style.forest * (z_hi - z_lo) / 100.0)
    # Behind the building lots (at most 20 m deep) where there are buildings.
    start = 4.0 if style.building_prob < 0.3 else 21.0
    for _ in range(int(forest)):
        x, z, scale = verge + side * (start + rng.exponential(12.0)), rng.uniform(z_lo, z_hi), rng.uniform(0.9, 1.5)
        if not (_in_gaps(z, gaps, 4.0) and abs(x - verge) < 40.0):
            _tree(builder, rng, x, z, scale=scale)


def build_static_scene(
    rng: np.random.Generator, style: WorldStyle, road: RoadGeometry, z_range: tuple[float, float]
) -> StaticMesh:
    """The static mesh of a world: ground, intersections with their signals, sign gantries, roadside lots,
    trees and street furniture.

    Args:
        rng: the world's scenery generator.
        style: street style.
        road: cross-section.
        z_range: world z span with detailed scenery (the ground continues 600 m beyond); the camera starts
            at z = 0 and drives along +z.
    """
    z_lo, z_hi = z_range
    builder = MeshBuilder()
    _ground(builder, road, z_lo, z_hi, rng)
    crossings = _staged_positions(rng, style.crossing_spacing, z_lo, z_hi, first=(15.0, 60.0))
    gaps = []
    for z in crossings:
        width = rng.uniform(8.0, 12.0)
        gaps.append((z - width / 2 - 1.5, z + width / 2 + 1.5))
        _cross_street(builder, rng, road, z, width)
        _traffic_signals(builder, rng, style, road, z, width)
    for z in _staged_positions(rng, style.gantry_spacing, z_lo, z_hi, first=(40.0, 120.0)):
        _gantry(builder, rng, road, z)
    if style.median_rail and road.lane_directions.count(-1):
        _guard_rail(builder, 0.0, 0, _minus([(z_lo, z_hi)], gaps), width=0.3)
    for side in (-1, 1):
        _lots(builder, rng, style, road, side, (z_lo, z_hi), gaps)
        _street_furniture(builder, rng, style, road, side, (z_lo, z_hi), gaps)
        _trees(builder, rng, style, road, side, (z_lo, z_hi), gaps)
    return builder.build()
