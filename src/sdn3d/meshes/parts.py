"""Vehicle parts: the label every face of a lofted vehicle mesh carries.

The labels come from the procedural loft (:func:`sdn3d.meshes.templates.loft_vehicle_parts`), which knows
its stations, belt line and wheels; :class:`~sdn3d.meshes.bank.MeshBank` keeps them next to the faces
(``face_parts``), the FFD moves vertices only (faces keep their labels) and the glTF export writes them
(``sdn3d.export``: each object mesh's ``extras``).

How a face of the loft is labelled (``docs/ARCHITECTURE.md``, "Vehicle parts"):

- ``TYRE``: the four wheels (tyre and rim: each wheel is one closed 12-sided prism).
- ``GLASS``: the greenhouse above the belt line: the side band between the belt and the roof edge
  wherever the greenhouse is at least :data:`MIN_GREENHOUSE` tall at both stations of a quad (the
  windows; the narrow pillar ends at the windscreen's base stay body), and the roof where the roof line
  slopes by at least :data:`MIN_GLASS_SLOPE` above the belt (windscreen and rear window). A flat end taller
  than :data:`MIN_GREENHOUSE` above the belt (a bus) has glass on its end panel's upper triangles.
- ``FRONT_LIGHTS`` (head lights and grille): the front end panel (``+x``, the fan closing the loft) but
  its two bottom-centre triangles and two bottom corners, and the rounded edge around it at the lower sides.
- ``TAIL_LIGHTS``: the rear end panel's (``-x``) two lateral triangles and the rounded edge beside them.
- ``PLATE``: the two bottom-centre triangles of either end panel (the number plates, front and rear).
- ``BODY``: everything else (paint: sides below the belt, roof, hood, trunk, bumpers, underbody).

The end panels are fans of 14 triangles around the end ring (the mesh is not re-cut, so that the
geometry stays what it was): a plate or a lamp is one or two of those triangles, coarser than the real
part but at its place.

Per point, a drawn picture's part map (the photo appearance's, ``editing.photo.transfer``) adds the greenhouse's
glass the faces cannot carry (:func:`greenhouse_glass`): a ``BODY`` point above the belt line facing sideways or
along the car is glass, as vehicles have their windows all round the greenhouse (the end panels' fans reach below
the belt at their centre, so a van's upright rear window was body up to its roof; the side quads' diagonals make
a per-face rule lopsided).
"""

from __future__ import annotations

from enum import IntEnum

from torch import Tensor

__all__ = ["Part", "PART_NAMES", "MIN_GREENHOUSE", "MIN_GLASS_SLOPE", "MAX_GLASS_RISE", "greenhouse_glass"]


class Part(IntEnum):
    """Part of a vehicle a face belongs to (the value is the label stored per face)."""

    BODY = 0
    GLASS = 1
    TYRE = 2  # tyres and rims
    FRONT_LIGHTS = 3  # head lights and grille
    TAIL_LIGHTS = 4
    PLATE = 5


#: Lower-case part names by label: ``PART_NAMES[label]``.
PART_NAMES: tuple[str, ...] = tuple(p.name.lower() for p in Part)
#: Metres of greenhouse (belt line to roof edge) a station needs for its side band to be glass.
MIN_GREENHOUSE = 0.12
#: Height change per metre of length from which the roof above the belt is glass (windscreen, rear window).
MIN_GLASS_SLOPE = 0.3
#: The most upward component of the outward unit normal of a point above the belt line that is glass (the
#: roof, facing up, is paint): the synthetic generator's rule for its vehicles' windows (``data.synth.appearance``).
MAX_GLASS_RISE = 0.93


def greenhouse_glass(parts: Tensor, height: Tensor, rise: Tensor, belt: Tensor | float) -> Tensor:
    """``(...)`` bool: where ``parts (...)`` should read ``GLASS``: a ``BODY`` point whose canonical
    ``height`` (``y``, down) is above the canonical ``belt`` line and whose outward unit normal's upward component
    ``rise`` is under :data:`MAX_GLASS_RISE` (the greenhouse but its roof: a van's or a hatchback's upright rear
    window, the end panels above the belt, the strips between the side windows and the roof). Vehicles have their
    windows all round the greenhouse, as the synthetic generator draws them (``data.synth.appearance``); the loft's
    station rules leave those faces body. ``height``, ``rise`` and ``belt`` broadcast against ``parts``."""
    return (parts == int(Part.BODY)) & (height <= belt) & (rise < MAX_GLASS_RISE)
