"""Eight procedural vehicle templates in the canonical mesh frame.

Canonical frame (see ``docs/ARCHITECTURE.md``): unit box ``[-0.5, 0.5]^3``, ``+x`` = vehicle
front (length), ``+y`` = down (height: wheels touch ``y = +0.5``, the roof is at ``y = -0.5``),
``z`` = width. Every template's axis-aligned bounds are exactly that box (anisotropic scale; the
real size comes from the predicted ``(l, h, w)``), so e.g. a pickup's low bed sits below
``y = -0.5`` while its cabin roof touches it.

Construction (no shapely / boolean ops needed): a *lofted body*. At stations along the length a
convex cross-section ring in the ``(z, height)`` plane is built from the template's profiles:
roof line (hood, windscreen, roof, rear window, trunk or pickup bed), underbody (ground
clearance, bumper lift, wheel arches), belt line (where the narrower greenhouse starts:
tumblehome) and plan-view corner rounding. Consecutive rings are joined by quads and both ends
are closed by a slightly inset ring plus a fan, so the body is watertight by construction. Four
wheels are separate closed cylinders (disjoint components that overlap the body: every edge is
still shared by exactly two faces, so ``is_watertight`` holds and the renderers, which only need
a closed surface, are unaffected). The ``-z`` half of every ring and the right wheels are exact
mirror images of the ``+z`` half, so the vertex set is mirror-symmetric across ``z = 0`` to the
last bit (the FFD is mirror-symmetric too).

Simplification, documented: a pickup bed is a solid at rail height (no open box), and wheels are
12-sided prisms.

Categories (Virtual KITTI has ``Car`` and ``Van``): sedan, hatchback, wagon, suv, pickup and van
(a minivan / MPV, car-sized) are ``Car``; minibus and bus are ``Van`` (Virtual KITTI has no bus
class; its ``Van`` is the closest box-shaped category).

The lofting machinery is public (:class:`VehicleSpec`, :func:`loft_vehicle`) so that other vehicle
shapes can be built the same way (``vehicle_family.py``: the synthetic generator's held-out shapes).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from sdn3d.meshes.parts import MIN_GLASS_SLOPE, MIN_GREENHOUSE, Part

if TYPE_CHECKING:  # trimesh is imported where a Trimesh is built: the edit path never needs it
    import trimesh

__all__ = [
    "TEMPLATE_NAMES",
    "TEMPLATE_DIMENSIONS",
    "CLASS_TEMPLATES",
    "TEMPLATE_CATEGORY",
    "TEMPLATE_SPECS",
    "VehicleSpec",
    "loft_vehicle",
    "loft_vehicle_parts",
    "build_template",
    "template_arrays",
    "template_parts",
    "all_templates",
    "normalize_to_unit_box",
]

#: Template names, in mesh-id order.
TEMPLATE_NAMES: tuple[str, ...] = ("sedan", "hatchback", "wagon", "suv", "pickup", "van", "minibus", "bus")

_WHEEL_SECTIONS = 12


@dataclass(frozen=True)
class VehicleSpec:
    """One lofted vehicle shape (a template or a family shape), in metres, height up from the ground.

    ``top`` is the roof line as ``(u, height)`` keypoints, ``u`` in ``[0, 1]`` from the rear
    (``u = 0``) to the front (``u = 1``); it is piecewise linear and every keypoint is a station,
    so kinks (windscreen base, cab back wall) stay sharp.
    """

    length: float
    height: float
    width: float
    top: tuple[tuple[float, float], ...]
    belt: float  # belt line height: the greenhouse above it is narrower (tumblehome)
    clearance: float
    wheel_radius: float
    axles: tuple[float, float]  # (rear, front) axle positions as u
    bumper_lift: tuple[float, float] = (0.18, 0.15)  # (rear, front) underbody rise at the ends
    tumble: float = 0.22  # inward run of the greenhouse side per metre of rise
    plan_round: float = 0.10  # relative width loss at the very ends (plan-view corner rounding)
    round: float = 0.05  # edge rounding radius
    crown: float = 0.03  # roof crown: centre higher than the roof edges
    wheel_width: float = 0.22
    category: str = "Car"


_SPECS: dict[str, VehicleSpec] = {
    # Three-box: long hood, steep windscreen base, sloped rear window, trunk deck.
    "sedan": VehicleSpec(
        4.6, 1.45, 1.8,
        top=((0.0, 0.72), (0.02, 0.90), (0.06, 0.99), (0.20, 1.03), (0.26, 1.07), (0.38, 1.38),
             (0.44, 1.45), (0.62, 1.45), (0.68, 1.37), (0.78, 1.00), (0.95, 0.86), (0.99, 0.74),
             (1.0, 0.62)),
        belt=0.98, clearance=0.15, wheel_radius=0.32, axles=(0.20, 0.80)),
    # Two-box, short: fast-sloping rear hatch from the roof, short hood.
    "hatchback": VehicleSpec(
        4.1, 1.48, 1.76,
        top=((0.0, 0.80), (0.02, 1.02), (0.10, 1.28), (0.18, 1.44), (0.24, 1.48), (0.56, 1.48),
             (0.62, 1.40), (0.74, 0.98), (0.94, 0.85), (0.99, 0.74), (1.0, 0.62)),
        belt=0.98, clearance=0.15, wheel_radius=0.31, axles=(0.17, 0.81)),
    # Long roof to an upright tailgate, long low hood.
    "wagon": VehicleSpec(
        4.8, 1.50, 1.8,
        top=((0.0, 0.78), (0.01, 1.02), (0.025, 1.38), (0.05, 1.48), (0.08, 1.50), (0.60, 1.50),
             (0.67, 1.41), (0.79, 0.96), (0.96, 0.84), (0.99, 0.73), (1.0, 0.60)),
        belt=0.96, clearance=0.14, wheel_radius=0.32, axles=(0.20, 0.81)),
    # Tall ground clearance, big wheels, high flat hood, upright windscreen and tailgate.
    "suv": VehicleSpec(
        4.7, 1.78, 1.9,
        top=((0.0, 1.00), (0.01, 1.40), (0.03, 1.68), (0.06, 1.78), (0.70, 1.78), (0.76, 1.66),
             (0.82, 1.24), (0.97, 1.18), (0.995, 1.05), (1.0, 0.90)),
        belt=1.22, clearance=0.24, wheel_radius=0.38, axles=(0.19, 0.82),
        bumper_lift=(0.15, 0.12), tumble=0.15),
    # Hood, high cab, then a long bed at rail height behind a near-vertical cab back wall.
    "pickup": VehicleSpec(
        5.3, 1.80, 1.9,
        top=((0.0, 0.95), (0.01, 1.08), (0.42, 1.10), (0.43, 1.66), (0.45, 1.80), (0.62, 1.80),
             (0.66, 1.70), (0.74, 1.25), (0.96, 1.17), (0.99, 1.05), (1.0, 0.88)),
        belt=1.15, clearance=0.22, wheel_radius=0.38, axles=(0.16, 0.78),
        bumper_lift=(0.12, 0.12), tumble=0.12),
    # One-box minivan / MPV: raked windscreen running into a short sloped nose.
    "van": VehicleSpec(
        4.9, 1.85, 1.9,
        top=((0.0, 0.80), (0.01, 1.50), (0.025, 1.78), (0.05, 1.85), (0.62, 1.85), (0.70, 1.72),
             (0.86, 1.12), (0.97, 0.95), (0.995, 0.82), (1.0, 0.66)),
        belt=1.05, clearance=0.16, wheel_radius=0.33, axles=(0.19, 0.82), tumble=0.15),
    # High-roof delivery van (Sprinter-like): box body, steep windscreen, short high hood.
    "minibus": VehicleSpec(
        6.0, 2.55, 2.0,
        top=((0.0, 0.70), (0.005, 2.40), (0.02, 2.55), (0.76, 2.55), (0.79, 2.40), (0.85, 1.40),
             (0.97, 1.22), (0.995, 1.05), (1.0, 0.82)),
        belt=1.30, clearance=0.20, wheel_radius=0.36, axles=(0.22, 0.80),
        bumper_lift=(0.10, 0.12), tumble=0.05, plan_round=0.06, category="Van"),
    # City bus: a long box with flat ends, large overhangs and big wheels.
    "bus": VehicleSpec(
        12.0, 3.2, 2.55,
        top=((0.0, 2.85), (0.005, 3.12), (0.012, 3.2), (0.988, 3.2), (0.995, 3.10), (1.0, 2.70)),
        belt=1.20, clearance=0.32, wheel_radius=0.50, axles=(0.27, 0.78),
        bumper_lift=(0.05, 0.05), tumble=0.02, plan_round=0.04, round=0.08, crown=0.04,
        wheel_width=0.30, category="Van"),
}

#: The lofting spec of each template (read-only use: the family shapes compare against them).
TEMPLATE_SPECS: Mapping[str, VehicleSpec] = MappingProxyType(_SPECS)
#: Typical real dimensions ``(l, h, w)`` in metres of each template.
TEMPLATE_DIMENSIONS: dict[str, tuple[float, float, float]] = {
    name: (spec.length, spec.height, spec.width) for name, spec in _SPECS.items()
}
#: Virtual KITTI category of each template (``Car`` or ``Van``, see the module doc).
TEMPLATE_CATEGORY: dict[str, str] = {name: spec.category for name, spec in _SPECS.items()}
#: The templates an object of a semantic class (its lower-case name) may be drawn with; a class not listed: every
#: template. A car is none of the ``Van`` category's (a minibus, a bus); a van (Virtual KITTI's ``Van``: panel and
#: high-roof vans, minibuses, box trucks) is box-shaped: the one-box van, the minibus or the bus, no sedan, hatchback,
#: wagon, SUV or pickup.
CLASS_TEMPLATES: dict[str, tuple[str, ...]] = {
    "car": tuple(name for name, category in TEMPLATE_CATEGORY.items() if category == "Car"),
    "van": ("van",) + tuple(name for name, category in TEMPLATE_CATEGORY.items() if category == "Van"),
}


def _bottom(spec: VehicleSpec, u: np.ndarray) -> np.ndarray:
    """Underbody height at ``u``: clearance, bumper lift ramps at the ends, wheel arches."""
    ramp = 0.08
    hb = (spec.clearance + spec.bumper_lift[0] * np.clip(1 - u / ramp, 0, 1) ** 2
          + spec.bumper_lift[1] * np.clip(1 - (1 - u) / ramp, 0, 1) ** 2)
    r_arch = spec.wheel_radius + 0.05
    for axle in spec.axles:
        dx = (u - axle) * spec.length
        inside = np.abs(dx) <= r_arch + 1e-9
        arch = spec.wheel_radius + np.sqrt(np.clip(r_arch**2 - dx**2, 0, None))
        hb = np.where(inside, np.maximum(hb, arch), hb)
    return hb


def _half_width(spec: VehicleSpec, u: np.ndarray) -> np.ndarray:
    """Lower-body half width at ``u``, narrowed towards the ends (plan-view corner rounding)."""
    d = np.minimum(u, 1 - u)
    return 0.5 * spec.width * (1 - spec.plan_round * np.clip(1 - d / 0.08, 0, 1) ** 2)


def _stations(spec: VehicleSpec) -> np.ndarray:
    """Sorted station positions ``u``: roof keypoints, wheel-arch samples, and a coarse fill."""
    r_arch = spec.wheel_radius + 0.05
    # +-1.04: the arch edge is a near-vertical step from the clearance up to the wheel centre.
    arch_t = np.array([-1.04, -1.0, -0.8, -0.45, 0.0, 0.45, 0.8, 1.0, 1.04])
    required = [u for u, _ in spec.top]
    for axle in spec.axles:
        required.extend(axle + arch_t * r_arch / spec.length)
    required = np.unique(np.clip(np.asarray(required), 0.0, 1.0))
    fill = np.linspace(0.0, 1.0, 13)
    gaps = np.abs(fill[:, None] - required[None, :]).min(axis=1)
    return np.unique(np.concatenate([required, fill[gaps > 0.025]]))


def _half_rings(spec: VehicleSpec, u: np.ndarray) -> np.ndarray:
    """``(S, 8, 2)`` half cross-sections ``(z >= 0, height)`` from the bottom centre to the roof centre."""
    ht = np.interp(u, *np.asarray(spec.top).T)
    hb = _bottom(spec, u)
    if np.any(ht - hb < 0.2):
        raise ValueError("template spec leaves less than 0.2 m between underbody and roof at "
                         f"u={u[ht - hb < 0.2]}")
    rb = np.minimum(spec.round, 0.25 * (ht - hb))
    rt = rb
    crown = np.minimum(spec.crown, 0.1 * (ht - hb))
    hs = np.clip(spec.belt, hb + rb + 0.02, ht - crown - rt - 0.02)  # shoulder / belt line
    wl = _half_width(spec, u)
    greenhouse = ht - crown - rt - hs
    wu = np.maximum(wl - spec.tumble * greenhouse - 0.5 * rt, 0.3 * wl)
    zero = np.zeros_like(u)
    pts = [
        (zero, hb),
        (wl - rb, hb),
        (wl, hb + rb),
        (wl, hs),
        (wu, ht - crown - rt),
        (wu - rt, ht - crown),
        (0.5 * (wu - rt), ht - 0.25 * crown),
        (zero, ht),
    ]
    return np.stack([np.stack(p, axis=-1) for p in pts], axis=1)


def _full_rings(half: np.ndarray) -> np.ndarray:
    """``(S, 8, 2)`` half rings -> ``(S, 14, 2)`` closed rings; the ``-z`` side is an exact mirror."""
    mirrored = half[:, -2:0:-1] * np.array([-1.0, 1.0])
    return np.concatenate([half, mirrored], axis=1)


def _loft(x: np.ndarray, rings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Join ``(S, K, 2)`` rings at stations ``x (S,)`` into a closed surface ``(x, height, z)``."""
    s, k = rings.shape[:2]
    verts = np.concatenate([np.repeat(x, k)[:, None], rings.reshape(-1, 2)[:, [1, 0]]], axis=1)
    ring_i = np.arange(s - 1)[:, None] * k
    a = ring_i + np.arange(k)[None, :]
    b = ring_i + (np.arange(k)[None, :] + 1) % k
    c, dd = b + k, a + k
    side = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, dd], -1)], axis=1).reshape(-1, 3)
    # Fan caps: the edge orientation on the last ring is opposite to that on the first one.
    centres = np.stack([[x[0], rings[0, :, 1].mean(), 0.0], [x[-1], rings[-1, :, 1].mean(), 0.0]])
    c0, c1 = s * k, s * k + 1
    ring = np.arange(k)
    nxt = (ring + 1) % k
    cap0 = np.stack([np.full(k, c0), nxt, ring], -1)
    cap1 = np.stack([np.full(k, c1), (s - 1) * k + ring, (s - 1) * k + nxt], -1)
    return np.concatenate([verts, centres]), np.concatenate([side, cap0, cap1])


def _wheel(center: np.ndarray, radius: float, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed ``_WHEEL_SECTIONS``-sided prism along z in ``(x, height, z)``; outward winding."""
    n = _WHEEL_SECTIONS
    t = 2 * np.pi * np.arange(n) / n
    ring = np.stack([radius * np.cos(t), radius * np.sin(t)], -1)
    zs = np.array([-0.5 * width, 0.5 * width])
    verts = np.concatenate([
        np.concatenate([ring, np.full((n, 1), zs[0])], 1),
        np.concatenate([ring, np.full((n, 1), zs[1])], 1),
        [[0.0, 0.0, zs[0]], [0.0, 0.0, zs[1]]],
    ]) + center
    i = np.arange(n)
    j = (i + 1) % n
    faces = np.concatenate([
        np.stack([i, j, j + n], -1), np.stack([i, j + n, i + n], -1),
        np.stack([np.full(n, 2 * n), j, i], -1), np.stack([np.full(n, 2 * n + 1), i + n, j + n], -1),
    ])
    return verts, faces


def normalize_to_unit_box(vertices: np.ndarray) -> np.ndarray:
    """Scale and translate ``(V, 3)`` vertices per axis so their bounds are exactly ``[-0.5, 0.5]^3``."""
    vertices = np.asarray(vertices, dtype=np.float64)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    extent = hi - lo
    if np.any(extent <= 0) or not np.all(np.isfinite(extent)):
        raise ValueError(f"vertices must span a positive finite extent on every axis, got extent {extent}")
    return (vertices - lo) / extent - 0.5


def loft_vehicle(spec: VehicleSpec) -> tuple[np.ndarray, np.ndarray]:
    """Canonical-frame mesh of ``spec``: ``verts (V, 3)`` float64 with bounds exactly ``[-0.5, 0.5]^3``,
    ``faces (F, 3)`` int64 wound outward (lofted body, then the wheels: rear-left, rear-right,
    front-left, front-right). Watertight and mirror-symmetric across ``z = 0`` (see the module doc).
    :func:`loft_vehicle_parts` gives the same mesh with each face's :class:`~sdn3d.meshes.parts.Part`.

    Raises:
        ValueError: the spec leaves less than 0.2 m between underbody and roof somewhere.
    """
    verts, faces, _ = loft_vehicle_parts(spec)
    return verts, faces


# Segments of the 14-point ring (segment k joins points k and k + 1; see _half_rings for the points).
_SEG_BOTTOM_CENTRE = [0, 13]  # bottom centre to the bottom corners
_SEG_BOTTOM_CORNER = [1, 12]  # lower edge rounding
_SEG_LOWER_SIDE = [2, 11]  # body side from the underbody to the belt line
_SEG_WINDOW = [3, 10]  # greenhouse side: belt line to the roof edge
_SEG_TOP = list(range(4, 10))  # roof edge rounding and roof


def _face_parts(spec: VehicleSpec, x: np.ndarray, rings: np.ndarray) -> np.ndarray:
    """``(F_body,)`` :class:`Part` labels of the lofted body of :func:`_loft` (side quads, then both fans) from the
    rings ``(S, 14, 2)`` (``(z, height)``; ring 0 and ``S - 1`` are the inset end rings) at ``x (S,)``."""
    s, k = rings.shape[:2]
    height = rings[..., 1]
    top = height[:, 7]
    greenhouse = height[:, 4] - height[:, 3]  # belt (shoulder) to the roof edge
    side = np.full((s - 1, 2, k), int(Part.BODY), dtype=np.int64)  # (interval, triangle, segment)
    lo, hi = np.arange(1, s - 2), np.arange(2, s - 1)  # the quads between real stations
    windows = np.minimum(greenhouse[lo], greenhouse[hi]) >= MIN_GREENHOUSE
    slope = np.abs(top[hi] - top[lo]) / np.maximum(x[hi] - x[lo], 1e-9)
    edge = height[:, 4]  # the roof edge: the lowest point of the roof's segments
    screens = (np.minimum(edge[lo], edge[hi]) >= spec.belt) & (slope >= MIN_GLASS_SLOPE)
    inner = side[1:-1]  # a view
    inner[:, :, _SEG_WINDOW] = np.where(windows[:, None, None], int(Part.GLASS), int(Part.BODY))
    inner[:, :, _SEG_TOP] = np.where(screens[:, None, None], int(Part.GLASS), int(Part.BODY))
    caps = []
    seg = np.arange(k)
    for end, interval, station, light in ((0, 0, 1, Part.TAIL_LIGHTS), (s - 1, s - 2, s - 2, Part.FRONT_LIGHTS)):
        # A flat end with glass (a bus): its faces above the belt (every corner) are glass.
        tall = greenhouse[station] >= MIN_GREENHOUSE
        ring_low = np.minimum(height[end, seg], height[end, (seg + 1) % k])
        cap_above = tall & (np.minimum(ring_low, height[end].mean()) >= spec.belt)  # the fan's centre, as _loft's
        bevel_above = tall & (np.minimum(ring_low, np.minimum(height[station, seg], height[station, (seg + 1) % k]))
                              >= spec.belt)
        upper = np.zeros(k, dtype=bool)
        upper[_SEG_WINDOW + _SEG_TOP] = True
        cap = np.full(k, int(Part.FRONT_LIGHTS if light == Part.FRONT_LIGHTS else Part.BODY), dtype=np.int64)
        cap[_SEG_BOTTOM_CENTRE] = int(Part.PLATE)
        cap[_SEG_BOTTOM_CORNER] = int(Part.BODY)
        cap[_SEG_LOWER_SIDE] = int(light)
        cap[upper & cap_above] = int(Part.GLASS)
        caps.append(cap)
        bevel = side[interval]
        bevel[:, _SEG_LOWER_SIDE] = int(light)
        bevel[:, upper & bevel_above] = int(Part.GLASS)
    return np.concatenate([side.reshape(-1), caps[0], caps[1]])


def loft_vehicle_parts(spec: VehicleSpec) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`loft_vehicle`'s ``verts (V, 3)`` and ``faces (F, 3)``, and ``parts (F,)`` int64: each face's
    :class:`~sdn3d.meshes.parts.Part` (the rules are in :mod:`sdn3d.meshes.parts`).

    Raises:
        ValueError: the spec leaves less than 0.2 m between underbody and roof somewhere.
    """
    u = _stations(spec)
    rings = _full_rings(_half_rings(spec, u))
    x = (u - 0.5) * spec.length
    # Rounded ends: one extra ring inset by the edge radius on every side, one radius further out.
    ends = []
    for idx, sign in ((0, -1.0), (-1, 1.0)):
        ring = rings[idx]
        lo, hi = ring[:, 1].min(), ring[:, 1].max()
        mid = 0.5 * (lo + hi)
        r = spec.round
        half_w, half_h = ring[:, 0].max(), 0.5 * (hi - lo)
        scale = np.array([(half_w - r) / half_w, (half_h - r) / half_h])
        ends.append((x[idx] + sign * r, (ring - [0.0, mid]) * scale + [0.0, mid]))
    x = np.concatenate([[ends[0][0]], x, [ends[1][0]]])
    rings = np.concatenate([ends[0][1][None], rings, ends[1][1][None]])
    verts, faces = _loft(x, rings)
    parts = [_face_parts(spec, x, rings)]
    # Wheels: the +z (left) ones are built, the -z ones are their exact mirror images.
    parts_v, parts_f = [verts], [faces]
    offset = len(verts)
    for axle in spec.axles:
        # Outer wheel face 2 cm inside the body side, so the body defines the width.
        zc = float(_half_width(spec, np.array(axle))) - 0.02 - 0.5 * spec.wheel_width
        center = np.array([(axle - 0.5) * spec.length, spec.wheel_radius, zc])
        wv, wf = _wheel(center, spec.wheel_radius, spec.wheel_width)
        for v, f in ((wv, wf), (wv * [1.0, 1.0, -1.0], wf[:, ::-1])):
            parts_v.append(v)
            parts_f.append(f + offset)
            parts.append(np.full(len(f), int(Part.TYRE), dtype=np.int64))
            offset += len(v)
    verts = np.concatenate(parts_v)
    faces = np.concatenate(parts_f)
    # (x, height, z) -> canonical (x, y = down, z), then exact unit box bounds.
    canon = normalize_to_unit_box(verts * [1.0, -1.0, 1.0])
    # The loft is symmetric about z = 0, so the normalisation's z shift is zero up to rounding;
    # re-mirror the -z half exactly so that the vertex set is symmetric to the last bit.
    canon[:, 2] = verts[:, 2] * (0.5 / np.abs(verts[:, 2]).max())
    # Flipping the height axis reversed the orientation: make the winding outward.
    if _signed_volume(canon, faces) < 0:
        faces = faces[:, ::-1]
    return canon.astype(np.float64), np.ascontiguousarray(faces, dtype=np.int64), np.concatenate(parts)


def _signed_volume(verts: np.ndarray, faces: np.ndarray) -> float:
    """Volume enclosed by a closed mesh ``verts (V, 3)``, ``faces (F, 3)``: positive when wound outward."""
    a, b, c = (verts[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


@cache
def _build_arrays(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return loft_vehicle_parts(_SPECS[name])


def template_arrays(name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(verts (V, 3) float64, faces (F, 3) int64)`` of template ``name`` (fresh copies; no trimesh needed)."""
    if name not in _SPECS:
        raise ValueError(f"name must be one of {TEMPLATE_NAMES}, got {name!r}")
    verts, faces, _ = _build_arrays(name)
    return verts.copy(), faces.copy()


def template_parts(name: str) -> np.ndarray:
    """``(F,)`` int64 :class:`~sdn3d.meshes.parts.Part` of each face of :func:`template_arrays` ``(name)`` (a copy)."""
    if name not in _SPECS:
        raise ValueError(f"name must be one of {TEMPLATE_NAMES}, got {name!r}")
    return _build_arrays(name)[2].copy()


def build_template(name: str) -> trimesh.Trimesh:
    """The procedural template ``name`` (one of :data:`TEMPLATE_NAMES`) in the canonical frame.

    Deterministic; the geometry is cached and a fresh :class:`trimesh.Trimesh` (``process=False``,
    so vertex order is stable) is returned on every call, safe to modify.
    """
    import trimesh

    verts, faces = template_arrays(name)
    return trimesh.Trimesh(verts, faces, process=False)


def all_templates() -> list[trimesh.Trimesh]:
    """All templates in :data:`TEMPLATE_NAMES` order."""
    return [build_template(name) for name in TEMPLATE_NAMES]
