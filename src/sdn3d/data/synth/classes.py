"""Virtual KITTI 1.3.1 semantic classes, their colours and the synthetic generator's materials.

Class colours are the ones of the Virtual KITTI 1.3.1 ``scenegt`` encoding. ``Car`` and ``Van``
have no class colour: every instance gets its own colour (``Car:<tid> r g b`` lines).
Virtual KITTI has no sidewalk class; the generator labels its sidewalks ``Road`` (paved
surface) and gives them a paving texture, and labels tree trunks ``Tree``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CLASS_NAMES",
    "CLASS_COLORS",
    "CLASS_ID",
    "STATIC_CLASS_NAMES",
    "Material",
    "CAR_COLORS",
    "instance_colors",
]

#: Internal class ids are indices into this tuple (Car and Van last: instance classes).
CLASS_NAMES: tuple[str, ...] = (
    "Terrain",
    "Sky",
    "Tree",
    "Vegetation",
    "Building",
    "Road",
    "GuardRail",
    "TrafficSign",
    "TrafficLight",
    "Pole",
    "Misc",
    "Truck",
    "Car",
    "Van",
)
CLASS_ID: dict[str, int] = {name: i for i, name in enumerate(CLASS_NAMES)}

#: Virtual KITTI 1.3.1 class colours (classes with one colour; Car and Van are per instance).
CLASS_COLORS: dict[str, tuple[int, int, int]] = {
    "Terrain": (210, 0, 200),
    "Sky": (90, 200, 255),
    "Tree": (0, 199, 0),
    "Vegetation": (90, 240, 0),
    "Building": (140, 140, 140),
    "Road": (100, 60, 100),
    "GuardRail": (255, 100, 255),
    "TrafficSign": (255, 255, 0),
    "TrafficLight": (200, 200, 0),
    "Pole": (255, 130, 0),
    "Misc": (80, 80, 80),
    "Truck": (160, 60, 60),
}
STATIC_CLASS_NAMES: tuple[str, ...] = tuple(CLASS_COLORS)


class Material:
    """Integer material ids: which procedural texture a face gets (see ``appearance.py``)."""

    ROAD = 0
    SIDEWALK = 1
    TERRAIN = 2
    FACADE = 3
    ROOF = 4
    CROWN = 5
    TRUNK = 6
    BUSH = 7
    METAL = 8
    SIGN = 9
    LIGHT = 10
    PLAIN = 11
    CAR = 12
    COUNT = 13


#: Named car body colours (Virtual KITTI's motgt ``color`` field uses such names), linear RGB.
CAR_COLORS: dict[str, tuple[float, float, float]] = {
    "Black": (0.03, 0.03, 0.035),
    "White": (0.80, 0.80, 0.78),
    "Silver": (0.55, 0.56, 0.58),
    "Grey": (0.25, 0.26, 0.27),
    "Red": (0.60, 0.04, 0.03),
    "Blue": (0.04, 0.12, 0.50),
    "Green": (0.06, 0.30, 0.08),
    "Brown": (0.28, 0.15, 0.06),
    "Yellow": (0.80, 0.62, 0.05),
    "Orange": (0.80, 0.30, 0.03),
    "Beige": (0.62, 0.52, 0.36),
    "DarkBlue": (0.02, 0.04, 0.18),
}


def instance_colors(tids: np.ndarray, seed: int) -> np.ndarray:
    """Unique scenegt colours for track ids, none equal to a class colour.

    Colours come from a fixed pseudo-random permutation of the 24-bit colour cube seeded by
    ``seed`` (so one sequence keeps them across frames); a colour is skipped when it equals
    a class colour or black.

    Args:
        tids: ``(N,)`` distinct non-negative track ids.
        seed: colour seed (the generator uses one per world).

    Returns:
        ``(N, 3)`` uint8 colours, row ``i`` for ``tids[i]``.
    """
    tids = np.asarray(tids, dtype=np.int64)
    if tids.ndim != 1 or (tids < 0).any() or len(np.unique(tids)) != len(tids):
        raise ValueError(f"tids must be distinct non-negative integers, got {tids.tolist()}")
    if len(tids) == 0:
        return np.zeros((0, 3), dtype=np.uint8)
    rng = np.random.default_rng([int(seed), 0xC010])
    reserved = {tuple(c) for c in CLASS_COLORS.values()} | {(0, 0, 0)}
    count = int(tids.max()) + 1
    chosen: list[tuple[int, int, int]] = []
    seen: set[tuple[int, int, int]] = set()
    # Draw in batches; duplicates and reserved colours are rare in 2^24, so one batch usually does.
    while len(chosen) < count:
        batch = rng.integers(0, 256, size=(2 * (count - len(chosen)) + 8, 3))
        for row in batch:
            key = (int(row[0]), int(row[1]), int(row[2]))
            if key in reserved or key in seen:
                continue
            seen.add(key)
            chosen.append(key)
            if len(chosen) == count:
                break
    return np.asarray(chosen, dtype=np.uint8)[tids]
