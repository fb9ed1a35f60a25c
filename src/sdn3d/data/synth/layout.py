"""World layouts of the synthetic Virtual KITTI generator: road, static scenery, cars, camera path.

A *world* (named like Virtual KITTI's ``0001`` ... ``0020``) is a straight street sampled from
``(seed, world)``: its cross-section (lanes, parking strips, sidewalks), the static scenery
along it (buildings, trees, bushes, poles, signs, traffic lights, guard rails, misc objects,
parked trucks), the car tracks (parked along the kerb or driving in lanes at a constant speed)
and the camera path (driving forward in one lane). Car bodies come from the held-out vehicle family
(``vehicles='heldout'``, :mod:`sdn3d.meshes.vehicle_family`: shapes the 8 bank templates only approximate)
or, as before, from the 8 templates themselves (``vehicles='bank'``); each with a small random FFD.
Every variation of a world renders this same scene; variations only change the camera yaw or the
lighting (see ``appearance.py``).

World frame: x right, y down, z forward along the road, metres; the ground is ``y = 0``. By default the
camera has no pitch or roll, so the ground is at camera-frame height ``y = camera_height`` in
every frame and every variation: that is each car's ``y3d``. A pitched camera (``build_world(camera_pitch=)``,
issue 40) looks down by that angle: the cars (:class:`FrameObjects`) stay in its *level* camera frame (the same
camera without the pitch, where the road is ``y = camera_height``) and only the rendering and the written
extrinsics and motgt locations see the pitch (:meth:`CameraPath.tilt`).
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

import numpy as np
import torch

from sdn3d.data.synth.classes import CAR_COLORS
from sdn3d.data.synth.primitives import StaticMesh
from sdn3d.data.synth.scenery import WORLD_STYLES, RoadGeometry, WorldStyle, build_static_scene
from sdn3d.math3d.ffd import expand_half_ffd
from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS, TEMPLATE_NAMES
from sdn3d.meshes.vehicle_family import FAMILY, VEHICLE_SHAPE_CATEGORY, VEHICLE_SHAPE_NAMES

__all__ = [
    "VARIATIONS",
    "CAMERA_YAW_DEG",
    "VEHICLE_SOURCES",
    "WorldStyle",
    "WORLD_STYLES",
    "CarTracks",
    "CameraPath",
    "World",
    "FrameObjects",
    "rng_for",
    "build_world",
    "frame_objects",
]

#: Virtual KITTI 1.3.1 variations; the four angle variations rotate the camera yaw.
VARIATIONS: tuple[str, ...] = (
    "clone",
    "morning",
    "sunset",
    "overcast",
    "fog",
    "rain",
    "15-deg-left",
    "15-deg-right",
    "30-deg-left",
    "30-deg-right",
)
#: Camera yaw of each variation in degrees (negative turns the camera to the left).
CAMERA_YAW_DEG: dict[str, float] = {
    "15-deg-left": -15.0,
    "15-deg-right": 15.0,
    "30-deg-left": -30.0,
    "30-deg-right": 30.0,
}

#: Where car bodies come from: the held-out family (default) or the 8 bank templates (the old data).
VEHICLE_SOURCES: tuple[str, ...] = ("heldout", "bank")
#: Cars are placed and counted over this stretch of road ahead of the camera (metres).
VIEW_DEPTH = 100.0
#: Track ids must stay below this (the readers' instance ids are class * 1000 + tid + 1).
MAX_TRACKS = 999
#: Cars more than this far behind the camera (camera-frame z) are not rendered at all.
BEHIND_LIMIT = 15.0


# Template frequencies (sedan ... bus; vehicles='bank'), family frequencies (vehicles='heldout': Van-category
# shapes about 24 % of the traffic, 11 % with the templates) and named-colour frequencies.
_TEMPLATE_WEIGHTS = np.array([0.22, 0.19, 0.14, 0.15, 0.08, 0.11, 0.07, 0.04])
_FAMILY_WEIGHTS = np.array([shape.weight for shape in FAMILY])
_FAMILY_LANE_ONLY = np.array([shape.lane_only for shape in FAMILY])
_FAMILY_DIMENSIONS = np.array([(s.spec.length, s.spec.height, s.spec.width) for s in FAMILY])
_COLOR_NAMES = tuple(CAR_COLORS)
_COLOR_WEIGHTS = np.array([0.16, 0.16, 0.16, 0.12, 0.09, 0.08, 0.04, 0.04, 0.03, 0.03, 0.04, 0.05])


def rng_for(seed: int, *keys: str | int) -> np.random.Generator:
    """A numpy Generator seeded from ``seed`` and a path of keys (world, variation, frame, ...).

    String keys are hashed with CRC32 (stable across processes, unlike ``hash``).
    """
    words = [int(seed) & 0xFFFFFFFF]
    for key in keys:
        words.append(zlib.crc32(key.encode()) if isinstance(key, str) else int(key) & 0xFFFFFFFF)
    return np.random.default_rng(words)


@dataclass
class CarTracks:
    """All cars of a world, one row per track (world frame; positions at frame 0).

    Attributes:
        tid: ``(N,)`` track ids ``0..N-1``.
        shape: ``(N,)`` vehicle shape ids (index into ``vehicle_family.VEHICLE_SHAPE_NAMES``: the 8 template
            ids, then the held-out family shapes).
        dims: ``(N, 3)`` ``(l, h, w)`` metres.
        phi: ``(N, 64, 3)`` float32 mirror-symmetric FFD displacements.
        color_name: N colour names; ``color_rgb`` ``(N, 3)`` linear albedo.
        x, z0: ``(N,)`` world position of the bottom-face centre at frame 0.
        yaw: ``(N,)`` world yaw (``-pi/2`` drives along +z).
        speed: ``(N,)`` metres per frame along +z (0: parked).
    """

    tid: np.ndarray
    shape: np.ndarray
    dims: np.ndarray
    phi: np.ndarray
    color_name: list[str]
    color_rgb: np.ndarray
    x: np.ndarray
    z0: np.ndarray
    yaw: np.ndarray
    speed: np.ndarray

    def __len__(self) -> int:
        return int(len(self.tid))

    @property
    def model(self) -> list[str]:
        """Vehicle shape name of each track (the motgt ``model`` column)."""
        return [VEHICLE_SHAPE_NAMES[s] for s in self.shape]

    @property
    def category(self) -> list[str]:
        """Virtual KITTI category (``Car`` or ``Van``) of each track."""
        return [VEHICLE_SHAPE_CATEGORY[VEHICLE_SHAPE_NAMES[s]] for s in self.shape]


@dataclass(frozen=True)
class CameraPath:
    """The camera drives along +z at ``x``, ``height`` metres above the road, with constant ``speed``
    (m/frame); no roll, and no pitch unless ``pitch`` (radians, positive looking down: Cityscapes' convention,
    :class:`sdn3d.math3d.camera.CameraPose`)."""

    x: float
    height: float
    speed: float
    pitch: float = 0.0

    def tilt(self) -> np.ndarray | None:
        """``(3, 3)`` level camera frame -> camera frame rotation (``p_cam = tilt @ p_level``), None without
        pitch."""
        if self.pitch == 0.0:
            return None
        from sdn3d.math3d.camera import CameraPose

        return CameraPose(self.height, self.pitch).tilt()

    def pose(self, frame: int, yaw_deg: float, level: bool = False) -> np.ndarray:
        """World->camera ``(4, 4)`` float64 matrix of ``frame`` with the camera turned by ``yaw_deg``.

        The camera-to-world rotation is ``roty(psi)``, ``psi = radians(yaw_deg)``: its optical
        axis points along ``(sin psi, 0, cos psi)``, so a negative yaw looks left; then, for a pitched camera,
        the pitch (:meth:`tilt`) unless ``level``.
        """
        psi = math.radians(yaw_deg)
        c, s = math.cos(psi), math.sin(psi)
        rot_cw = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        center = np.array([self.x, -self.height, self.speed * frame])
        out = np.eye(4)
        out[:3, :3] = rot_cw.T
        out[:3, 3] = -rot_cw.T @ center
        tilt = None if level else self.tilt()
        if tilt is not None:
            out[:3] = tilt @ out[:3]
        return out


@dataclass
class World:
    """One sampled world: scenery mesh, road geometry, car tracks and camera path."""

    name: str
    seed: int
    style: WorldStyle
    road: RoadGeometry
    static: StaticMesh
    cars: CarTracks
    camera: CameraPath
    num_frames: int


@dataclass
class FrameObjects:
    """The cars of one rendered frame in the (level, :class:`CameraPath`) camera frame (what motgt describes).

    Attributes:
        track: ``(N,)`` row in the world's :class:`CarTracks`.
        center: ``(N, 3)`` box centres ``(x3d, y3d - h/2, z3d)``.
        ry: ``(N,)`` camera-frame yaw.
        moving: ``(N,)`` bool.
    """

    track: np.ndarray
    center: np.ndarray
    ry: np.ndarray
    moving: np.ndarray

    def __len__(self) -> int:
        return int(len(self.track))

    def subset(self, keep: np.ndarray) -> FrameObjects:
        return FrameObjects(self.track[keep], self.center[keep], self.ry[keep], self.moving[keep])


def _style_for(world: str, rng: np.random.Generator) -> WorldStyle:
    if world in WORLD_STYLES:
        return WORLD_STYLES[world]
    base = WORLD_STYLES[("0001", "0002", "0006", "0018", "0020")[int(rng.integers(5))]]
    return base.varied(rng)


def _sample_shape(rng: np.random.Generator, allow_bus: bool, vehicles: str) -> tuple[int, np.ndarray]:
    """Vehicle shape id and its real dims ``(l, h, w)``; buses only where ``allow_bus`` (driving lanes)."""
    if vehicles == "bank":
        weights = _TEMPLATE_WEIGHTS.copy()
        if not allow_bus:
            weights[TEMPLATE_NAMES.index("bus")] = 0.0
        template = int(rng.choice(len(TEMPLATE_NAMES), p=weights / weights.sum()))
        return template, np.array(TEMPLATE_DIMENSIONS[TEMPLATE_NAMES[template]])
    weights = np.where(_FAMILY_LANE_ONLY & (not allow_bus), 0.0, _FAMILY_WEIGHTS)
    member = int(rng.choice(len(FAMILY), p=weights / weights.sum()))
    return len(TEMPLATE_NAMES) + member, _FAMILY_DIMENSIONS[member].copy()


def _sample_car(rng: np.random.Generator, allow_bus: bool, vehicles: str) -> tuple[int, np.ndarray, np.ndarray, int]:
    """Vehicle shape id, jittered dims ``(l, h, w)``, FFD ``(64, 3)`` and colour index of one car."""
    shape, base = _sample_shape(rng, allow_bus, vehicles)
    dims = base * (1.0 + rng.uniform(-0.05, 0.05)) * (1.0 + rng.uniform(-0.04, 0.04, size=3))
    # Small symmetric FFD; the bottom lattice layer (j = 3, y = +0.5) keeps its height so the
    # wheels stay exactly on the ground (y3d is the ground height).
    half = rng.normal(0.0, 0.02, size=(4, 4, 2, 3)).clip(-0.05, 0.05)
    half[:, 3, :, 1] = 0.0
    phi = expand_half_ffd(torch.from_numpy(half.reshape(32, 3))).numpy()
    color = int(rng.choice(len(_COLOR_NAMES), p=_COLOR_WEIGHTS / _COLOR_WEIGHTS.sum()))
    return shape, dims, phi, color


def _place_row(
    rng: np.random.Generator, z_lo: float, z_hi: float, spacing: float, allow_bus: bool, vehicles: str
) -> list[tuple[float, int, np.ndarray, np.ndarray, int]]:
    """Cars along one row (lane or parking strip) between ``z_lo`` and ``z_hi``, no overlaps.

    Gaps are ``0.8 m`` plus an exponential with the mean that makes the mean centre spacing
    ``spacing``. Returns ``(z_centre, shape, dims, phi, colour)`` per car.
    """
    out = []
    z = z_lo + rng.uniform(0.0, spacing)
    while True:
        shape, dims, phi, color = _sample_car(rng, allow_bus, vehicles)
        if z + dims[0] > z_hi:
            return out
        out.append((z + dims[0] / 2, shape, dims, phi, color))
        z += dims[0] + 0.8 + rng.exponential(max(spacing - 5.3, 0.5))


def _sample_cars(
    rng: np.random.Generator,
    style: WorldStyle,
    road: RoadGeometry,
    camera: CameraPath,
    num_frames: int,
    cars_per_frame: tuple[int, int],
    vehicles: str,
) -> CarTracks:
    """Car tracks along every lane and parking strip (see :func:`build_world`)."""
    rows = []  # (x, yaw (None: parked), speed in m/frame, same lane as the camera)
    travel = camera.speed * max(num_frames - 1, 0)
    for lane_x, direction in zip(road.lane_centers, road.lane_directions, strict=True):
        same_lane = abs(lane_x - camera.x) < 0.1
        if same_lane:
            speed = camera.speed
        elif direction > 0:
            speed = camera.speed * rng.uniform(0.6, 1.4)
        else:
            speed = -camera.speed * rng.uniform(0.7, 1.3)
        yaw = -math.pi / 2 if direction > 0 else math.pi / 2
        rows.append((lane_x, yaw, speed, same_lane))
    for x in road.parking_centers:
        rows.append((x, None, 0.0, False))
    n_target = int(rng.integers(cars_per_frame[0], cars_per_frame[1] + 1))
    if n_target <= 0 or not rows:
        empty = np.zeros(0)
        return CarTracks(
            empty.astype(np.int64),
            empty.astype(np.int64),
            np.zeros((0, 3)),
            np.zeros((0, 64, 3), np.float32),
            [],
            np.zeros((0, 3)),
            empty,
            empty,
            empty,
            empty,
        )
    spacing = VIEW_DEPTH * len(rows) / n_target
    cars = []
    for x, yaw, speed, same_lane in rows:
        rel = (camera.speed - speed) * travel / max(camera.speed, 1e-6)
        if same_lane:  # ahead of the camera only, driving at its speed: never reached
            z_lo, z_hi = 8.0, VIEW_DEPTH
        else:  # every car that is in view at some frame
            z_lo = -BEHIND_LIMIT + min(0.0, rel)
            z_hi = VIEW_DEPTH + max(0.0, rel)
        for z, shape, dims, phi, color in _place_row(rng, z_lo, z_hi, spacing, yaw is not None, vehicles):
            if yaw is None:  # parked: mostly facing the traffic of its side, slightly askew
                forward = x > 0
                if rng.uniform() < 0.15:
                    forward = not forward
                car_yaw = (-math.pi / 2 if forward else math.pi / 2) + rng.normal(0.0, 0.04)
                car_x = x + rng.normal(0.0, 0.12)
            else:
                car_yaw, car_x = yaw + rng.normal(0.0, 0.01), x + rng.normal(0.0, 0.1)
            cars.append((car_x, z, car_yaw, speed, shape, dims, phi, color))
    cars.sort(key=lambda c: (c[1], c[0]))
    n = len(cars)
    return CarTracks(
        tid=np.arange(n, dtype=np.int64),
        shape=np.array([c[4] for c in cars], dtype=np.int64),
        dims=np.array([c[5] for c in cars], dtype=np.float64).reshape(n, 3),
        phi=np.array([c[6] for c in cars], dtype=np.float32).reshape(n, 64, 3),
        color_name=[_COLOR_NAMES[c[7]] for c in cars],
        color_rgb=np.array([CAR_COLORS[_COLOR_NAMES[c[7]]] for c in cars], dtype=np.float64).reshape(n, 3),
        x=np.array([c[0] for c in cars], dtype=np.float64),
        z0=np.array([c[1] for c in cars], dtype=np.float64),
        yaw=np.array([c[2] for c in cars], dtype=np.float64),
        speed=np.array([c[3] for c in cars], dtype=np.float64),
    )


def build_world(seed: int, world: str, num_frames: int, cars_per_frame: tuple[int, int] = (4, 12),
                vehicles: str = "heldout", camera_height: float | None = None, camera_pitch: float = 0.0) -> World:
    """Sample world ``world`` of dataset seed ``seed``.

    Args:
        seed: dataset seed.
        world: 4-digit world name; the five Virtual KITTI names have fixed street styles.
        num_frames: frames of the sequence (sets how far the camera drives, hence how long
            the scenery and car rows are).
        cars_per_frame: ``[min, max]``: the number of cars placed along the first
            ``VIEW_DEPTH`` = 100 m of road ahead of the camera, drawn once per world; the same
            density continues along the sequence. How many are visible in a frame varies with
            occlusion and the frame's field of view.
        vehicles: ``'heldout'`` (car bodies from the held-out vehicle family) or ``'bank'`` (from the 8
            templates; the same world as before the family existed, bit for bit).
        camera_height: the camera's height above the road (metres); None: drawn per world in [1.50, 1.65]
            (the same draw either way, so the rest of the world does not change).
        camera_pitch: the camera's pitch (radians, positive looking down; 0: level, as before).
    """
    if not (len(world) == 4 and world.isdigit()):
        raise ValueError(f"world must be a 4-digit name like '0001', got {world!r}")
    if num_frames < 1:
        raise ValueError(f"num_frames must be >= 1, got {num_frames}")
    if vehicles not in VEHICLE_SOURCES:
        raise ValueError(f"vehicles must be one of {list(VEHICLE_SOURCES)}, got {vehicles!r}")
    lo, hi = (int(v) for v in cars_per_frame)
    if lo < 0 or hi < lo:
        raise ValueError(f"cars_per_frame must be [min, max] with 0 <= min <= max, got {cars_per_frame}")
    rng = rng_for(seed, "world", world)
    style = _style_for(world, rng)
    road = RoadGeometry.from_style(style, rng)
    lane = int(rng.integers(len(road.forward_lanes)))
    camera = CameraPath(
        x=float(road.forward_lanes[lane]),
        height=float(rng.uniform(1.5, 1.65)),
        speed=float(rng.uniform(0.7, 1.3)),
    )
    if camera_height is not None or camera_pitch != 0.0:
        camera = CameraPath(camera.x, camera.height if camera_height is None else float(camera_height), camera.speed,
                            float(camera_pitch))
    travel = camera.speed * (num_frames - 1)
    static = build_static_scene(rng_for(seed, "scenery", world), style, road, z_range=(-40.0, travel + 220.0))
    cars = _sample_cars(rng_for(seed, "cars", world), style, road, camera, num_frames, (lo, hi), vehicles)
    if len(cars) > MAX_TRACKS:
        raise ValueError(
            f"world {world} has {len(cars)} car tracks but Virtual KITTI readers accept track ids up to "
            f"{MAX_TRACKS - 1} (instance ids are class * 1000 + tid + 1); lower frames_per_sequence or "
            "cars_per_frame"
        )
    return World(world, int(seed), style, road, static, cars, camera, int(num_frames))


def frame_objects(world: World, frame: int, yaw_deg: float) -> FrameObjects:
    """Cars of ``frame`` in the level camera frame (variation yaw ``yaw_deg``), far-behind ones dropped.

    Moving cars advance ``speed`` metres per frame; ``moving`` is their motgt flag.
    """
    cars = world.cars
    world_to_cam = world.camera.pose(frame, yaw_deg, level=True)
    h = cars.dims[:, 1]
    bottom = np.stack([cars.x, np.zeros(len(cars)), cars.z0 + cars.speed * frame], axis=1)
    center_w = bottom - np.stack([np.zeros(len(cars)), h / 2, np.zeros(len(cars))], axis=1)
    center = center_w @ world_to_cam[:3, :3].T + world_to_cam[:3, 3]
    ry = cars.yaw - math.radians(yaw_deg)
    ry = np.remainder(ry + math.pi, 2 * math.pi) - math.pi
    objects = FrameObjects(np.arange(len(cars)), center, ry, cars.speed != 0)
    radius = 0.5 * np.linalg.norm(cars.dims[:, [0, 2]], axis=1)
    keep = (center[:, 2] + radius > -BEHIND_LIMIT) & (center[:, 2] - radius < VIEW_DEPTH + 60.0)
    return objects.subset(keep)
