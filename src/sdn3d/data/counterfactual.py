"""Reader of the counterfactual pairs ``sdn3d-synth`` writes (``counterfactual_pairs.json``, docs/DATA.md,
"Counterfactual pairs"): the index as :class:`CounterfactualPair` records and their masks as bool arrays.

The writer is :mod:`sdn3d.data.synth.counterfactual`; this module only reads (the benchmark's side,
:mod:`sdn3d.evaluation.counterfactual`).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.data.errors import DataFormatError, MissingDataError

__all__ = ["CounterfactualPair", "CounterfactualIndex", "load_pairs", "load_pair_mask", "load_pair_rgb",
           "PAIR_MASKS", "PAIRS_NAME", "PAIRS_FORMAT"]

#: The index file at the dataset root and its ``format`` (the writer's
#: :data:`sdn3d.data.synth.counterfactual.PAIRS_NAME` / ``PAIRS_FORMAT``; repeated here so that reading does not
#: import the generator; a test checks they agree).
PAIRS_NAME = "counterfactual_pairs.json"
PAIRS_FORMAT = "sdn3d-counterfactual-pairs"

#: The mask files of a pair (keys of :attr:`CounterfactualPair.paths`).
PAIR_MASKS = ("source_mask", "target_mask", "vacated", "shadow")


@dataclass(frozen=True)
class CounterfactualPair:
    """One pair of the index (docs/DATA.md): ``kind`` ``'turn'`` (by ``angle_deg``) or ``'delete'`` of the car
    ``instance_id`` of frame ``frame`` of ``world/variation``; ``from_uv`` its projected centre in 1242x375 pixels;
    ``paths``: ``source``, ``target`` and :data:`PAIR_MASKS`, relative to the dataset root."""

    world: str
    variation: str
    frame: int
    instance_id: int
    kind: str
    angle_deg: float | None
    from_uv: tuple[float, float]
    paths: dict[str, str]
    ry_source: float = 0.0
    overlaps: tuple[int, ...] = ()
    model: str = ""
    pixels: dict[str, int] = field(default_factory=dict)

    @property
    def key(self) -> str:
        """``world/variation/frame_instance turn_<angle> | delete``."""
        what = "delete" if self.kind == "delete" else f"turn_{self.angle_deg:g}"
        return f"{self.world}/{self.variation}/{self.frame:05d}_{self.instance_id} {what}"

    @property
    def car(self) -> str:
        """The physical car, ``world/instance_id``: one track of the world, the same car in every frame and
        variation (its pairs are one piece of evidence: the benchmark's intervals resample whole cars)."""
        return f"{self.world}/{self.instance_id}"

    @property
    def target_key(self) -> tuple[str, str, int, int]:
        """The target car: ``(world, variation, frame, instance_id)`` (shared by its turns and its delete)."""
        return self.world, self.variation, self.frame, self.instance_id


@dataclass(frozen=True)
class CounterfactualIndex:
    """The index: ``root``, ``image_size (W, H)`` the renders and frames are written at, ``shadow_threshold`` and
    the pairs in the file's order."""

    root: Path
    image_size: tuple[int, int]
    shadow_threshold: int
    pairs: tuple[CounterfactualPair, ...]


def load_pairs(root: str | os.PathLike) -> CounterfactualIndex:
    """Read ``<root>/counterfactual_pairs.json``.

    Raises:
        MissingDataError: no index (a tree written without ``counterfactual_cars``).
        DataFormatError: not the format (naming the file and what is wrong).
    """
    root = Path(root).expanduser()
    path = root / PAIRS_NAME
    if not path.is_file():
        raise MissingDataError(f"{path}: not found: the dataset has no counterfactual pairs (sdn3d-synth "
                               "counterfactual_cars=N writes them)", path=path)
    try:
        data = json.loads(path.read_text())
        if data.get("format") != PAIRS_FORMAT or data.get("version") != 1:
            raise ValueError(f"format {data.get('format')!r} version {data.get('version')!r}, expected "
                             f"{PAIRS_FORMAT!r} version 1")
        width, height = (int(v) for v in data["image_size"])
        pairs = []
        for p in data["pairs"]:
            if p["kind"] not in ("turn", "delete"):
                raise ValueError(f"pair kind {p['kind']!r} (turn or delete)")
            pairs.append(CounterfactualPair(
                world=str(p["world"]), variation=str(p["variation"]), frame=int(p["frame"]),
                instance_id=int(p["instance_id"]), kind=p["kind"],
                angle_deg=None if p.get("angle_deg") is None else float(p["angle_deg"]),
                from_uv=(float(p["from"][0]), float(p["from"][1])),
                paths={k: str(p[k]) for k in ("source", "target", *PAIR_MASKS)},
                ry_source=float(p.get("ry_source", 0.0)), overlaps=tuple(int(i) for i in p.get("overlaps", ())),
                model=str(p.get("model", "")), pixels={str(k): int(v) for k, v in (p.get("pixels") or {}).items()}))
    except (KeyError, TypeError, ValueError) as exc:
        raise DataFormatError(f"{path}: not a counterfactual-pairs index: {exc}", path=path) from None
    return CounterfactualIndex(root, (width, height), int(data.get("shadow_threshold", 0)), tuple(pairs))


def load_pair_mask(root: str | os.PathLike, pair: CounterfactualPair, which: str) -> np.ndarray:
    """``(H, W)`` bool mask ``which`` (:data:`PAIR_MASKS`) of ``pair`` (255 in the PNG = True)."""
    if which not in PAIR_MASKS:
        raise ValueError(f"which must be one of {PAIR_MASKS}, got {which!r}")
    return np.array(Image.open(Path(root) / pair.paths[which])) > 127


def load_pair_rgb(root: str | os.PathLike, pair: CounterfactualPair, which: str = "target") -> np.ndarray:
    """``(H, W, 3)`` uint8 ``'target'`` (the counterfactual render) or ``'source'`` image of ``pair``."""
    if which not in ("source", "target"):
        raise ValueError(f"which must be 'source' or 'target', got {which!r}")
    return np.array(Image.open(Path(root) / pair.paths[which]).convert("RGB"))
