"""Front from back at the fitted axis (issue 40): what the appearance believes of any yaw, for the box fit.

A silhouette fixes a car's axis well (the test-time fit, :mod:`sdn3d.geometric.fit`, within a few degrees) but
hardly its end; the geometric branch at a CPU budget gets the end wrong for one car in seven, and the red-lamp cue
(:mod:`sdn3d.geometric.lamps`) is right for nearly every car it can read. The branch's own yaw sits near its bins'
centres (``alpha`` near +-90 degrees), so the lamps' side cue (which end lies left, ``cos(alpha)``) is only
readable at the fitted axis. :func:`facing_belief` scores each hypothesis yaw of the fit::

    score(ry) = lamps(alpha) + net_weight * net(ry),      alpha = ry - ray

with ``lamps`` the lamps' evidence at that ``alpha`` (:func:`~sdn3d.geometric.lamps.evidence_of`) and ``net`` the
net's say: ``2 p - 1``
of its MultiBin bins (:func:`~sdn3d.geometric.model.yaw_distribution`) where ``bins`` and the net has them, else
``cos(ry - net_ry)``. ``net_weight`` is the lamp cue's ``-flip_below``: lamps whose evidence is beyond it decide
the end, as :func:`~sdn3d.geometric.lamps.face_by_lamps` does for the branch's own yaw. The score of a yaw and of its
reverse are opposite, so the fit's ``belief >= reverse`` is ``score >= 0``.

Measured on a seed-13 tuning tree (442 cars and vans, ground-truth masks and boxes: an oracle), the box fit with
this belief made as many flips as with the plain one (the yaw nearest its start, itself turned by the lamps): 16
either way (3.6 %), template accuracy 35.7 % against 36.2 %; so the box objects use it only where
``FitSettings.appearance`` asks (``docs/results/2026-11-28_cpu/session3/flips``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import torch
from torch import Tensor

from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution

__all__ = ["APPEARANCE_KEYS", "BIN_KEYS", "BORDER_KEYS", "FRONT_KEYS", "Appearance", "facing_belief"]

#: What :func:`facing_belief` reads per object: the predictor's outputs (``net_ry``, ``ray``, the lamps' reading).
APPEARANCE_KEYS = ("net_ry", "ray", "lamp_present", "lamp_usable", "lamp_offset")
#: A red body's headlights (:func:`~sdn3d.geometric.lamps.white_lamps`), read where present.
FRONT_KEYS = ("front_present", "front_usable", "front_offset")
#: The image border that cuts each object's box (:func:`~sdn3d.geometric.lamps.border_side`), read where present.
BORDER_KEYS = ("border_side",)
#: A MultiBin net's outputs, read where present.
BIN_KEYS = ("yaw_bins", "yaw_residual", "yaw_ray")


def facing_belief(appearance: Mapping[str, Tensor], cue: LampCue | None = None, bins: bool = True
                  ) -> Callable[[Tensor], Tensor]:
    """``ry (N, K) -> (N, K)`` the score of each yaw (module doc) of the ``N`` objects of ``appearance``
    (:data:`APPEARANCE_KEYS`, each ``(N,)``, and optionally :data:`BIN_KEYS`, :data:`FRONT_KEYS` and
    :data:`BORDER_KEYS`).

    >>> appearance = {"net_ry": torch.tensor([1.6]), "ray": torch.zeros(1), "lamp_present": torch.tensor([False]),
    ...               "lamp_usable": torch.tensor([True]), "lamp_offset": torch.zeros(1)}
    >>> back, front = -1.6, 1.6  # no red lamps on a readable crop: the front is seen
    >>> [round(v, 2) for v in facing_belief(appearance)(torch.tensor([[back, front]]))[0].tolist()]
    [-0.8, 0.8]
    """
    cue = cue or LampCue()
    net_weight = -cue.flip_below
    a = {k: appearance[k] for k in APPEARANCE_KEYS}
    raw = {k: appearance[k] for k in BIN_KEYS} if bins and all(k in appearance for k in BIN_KEYS) else None
    front = (appearance["front_present"].bool(), appearance["front_usable"].bool(), appearance["front_offset"]) \
        if all(k in appearance for k in FRONT_KEYS) else None
    border = appearance["border_side"] if "border_side" in appearance else None

    def score(ry: Tensor) -> Tensor:
        ry = ry.to(a["net_ry"].dtype)
        lamps = evidence_of(a["lamp_present"].bool(), a["lamp_usable"].bool(), a["lamp_offset"],
                            ry - a["ray"][:, None], cue, front=front, border=border)
        net = 2 * yaw_distribution(raw, ry) - 1 if raw is not None else torch.cos(ry - a["net_ry"][:, None])
        return lamps + net_weight * net

    return score


@dataclass(frozen=True)
class Appearance:
    """What the geometric branch saw of ``N`` objects (:data:`APPEARANCE_KEYS`, :data:`FRONT_KEYS` and
    :data:`BORDER_KEYS` where read and, of a MultiBin net, :data:`BIN_KEYS`, each with ``N`` rows) and the lamp cue
    it read them with: the box fit's yaw belief.

    Attributes:
        values: the tensors by key (rows without a prediction: zeros; ``has`` says which rows have one).
        has: ``(N,)`` bool, the rows with a prediction.
        cue: the lamp cue's thresholds.
    """

    values: dict[str, Tensor]
    has: Tensor
    cue: LampCue = field(default_factory=LampCue)

    def rows(self, index: Tensor) -> Appearance:
        """The appearance of the objects ``index``."""
        return Appearance({k: v[index] for k, v in self.values.items()}, self.has[index], self.cue)

    def belief(self, bins: bool = True) -> Callable[[Tensor], Tensor]:
        """:func:`facing_belief` of these objects."""
        return facing_belief(self.values, self.cue, bins)
