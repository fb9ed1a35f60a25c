"""The trained branches of a de-render (:class:`Models`), loaded from files: Lightning checkpoints or inference
exports, and the geometric branch's crop settings read from its run's ``config.yaml`` (:func:`geometric_crop_settings`)
or its export.

:func:`sdn3d.derender.derender` takes a :class:`Models`; this module is where they come from (floor 5, beside
:mod:`sdn3d.derender` and :mod:`sdn3d.runs`).
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import torch

from sdn3d.errors import UserInputError

if TYPE_CHECKING:
    from sdn3d.geometric.predict import GeometricPredictor
    from sdn3d.semantic.predict import SemanticPredictor
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["DEFAULT_CROP_SIZE", "DEFAULT_MARGIN", "Models", "geometric_crop_settings"]

log = logging.getLogger("sdn3d.derender")  # the logger these messages always had

#: Paper crop side of the geometric branch (released 3D-SDN code), used when a run does not say.
DEFAULT_CROP_SIZE = 256
DEFAULT_MARGIN = 0.1


def geometric_crop_settings(checkpoint: str | os.PathLike) -> tuple[int, float] | None:
    """``(crop_size, margin)`` the geometric run of ``checkpoint`` trained with, or None if unknown.

    Read from the run's saved config (``<run>/config.yaml`` beside ``<run>/checkpoints/*.ckpt``,
    written by ``sdn3d-train``): the crop size is a datamodule setting, not in the checkpoint. The file
    is only read (nothing in it is instantiated or resolved).

    Raises:
        UserInputError: naming the config file, when it is not readable YAML or its ``datamodule.crop_size``
            / ``margin`` are not numbers (pass ``crop_size`` and ``margin`` explicitly to skip it).
    """
    import yaml
    from omegaconf import OmegaConf
    from omegaconf.errors import OmegaConfBaseException

    path = Path(checkpoint).expanduser().resolve()
    for run_dir in (path.parent.parent, path.parent):
        config = run_dir / "config.yaml"
        if not config.is_file():
            continue
        try:
            tree = OmegaConf.to_container(OmegaConf.load(config), resolve=False)
        except (yaml.YAMLError, OmegaConfBaseException, UnicodeDecodeError) as exc:
            reason = " ".join(str(exc).split())[:200]
            raise UserInputError(f"the geometric run's config {str(config)!r} (read for its crop size) is not "
                                 f"readable YAML ({reason}); fix it or give the crop size and margin") from exc
        dm = (tree.get("datamodule") if isinstance(tree, dict) else None) or {}
        if isinstance(dm, dict) and isinstance(dm.get("crop_size"), int):
            crop, margin = dm["crop_size"], dm.get("margin", DEFAULT_MARGIN)
            if isinstance(crop, bool) or isinstance(margin, bool) or not isinstance(margin, (int, float)):
                raise UserInputError(f"the geometric run's config {str(config)!r}: datamodule.crop_size and margin "
                                     f"must be numbers, got {crop!r} and {margin!r}; fix it or give the crop size "
                                     "and margin")
            return int(crop), float(margin)
    return None



@dataclass
class Models:
    """The trained branches (any may be None; rendering needs ``textural``).

    Attributes:
        semantic, geometric, textural: the branch predictors.
        crop_size, margin: object crops of the geometric branch (as it was trained).
    """

    semantic: SemanticPredictor | None = None
    geometric: GeometricPredictor | None = None
    textural: TexturalRenderer | None = None
    crop_size: int = DEFAULT_CROP_SIZE
    margin: float = DEFAULT_MARGIN

    def __post_init__(self) -> None:
        if int(self.crop_size) != self.crop_size or self.crop_size < 8:
            raise UserInputError(f"Models.crop_size must be an integer >= 8, got {self.crop_size!r}")
        if not (math.isfinite(self.margin) and self.margin >= 0):
            raise UserInputError(f"Models.margin must be finite and >= 0, got {self.margin!r}")

    @classmethod
    def from_checkpoints(cls, semantic: str | os.PathLike | None = None, geometric: str | os.PathLike | None = None,
                         textural: str | os.PathLike | None = None, map_location: str | torch.device = "cpu",
                         crop_size: int | None = None, margin: float | None = None) -> Models:
        """Load the branches from their Lightning checkpoints or inference exports (None: branch absent;
        :func:`sdn3d.inference_export.load_branch_weights` tells the two apart by content).

        ``crop_size`` / ``margin`` None: the geometric export's settings, else the geometric run's
        (:func:`geometric_crop_settings`), else :data:`DEFAULT_CROP_SIZE` / :data:`DEFAULT_MARGIN`.
        """
        for name, path in (("semantic", semantic), ("geometric", geometric), ("textural", textural)):
            if path is not None and not Path(path).expanduser().is_file():
                raise FileNotFoundError(f"{name} checkpoint {os.fspath(path)!r} does not exist")
        sem = geo = tex = None
        if semantic is not None:
            from sdn3d.semantic.predict import SemanticPredictor

            sem = SemanticPredictor.from_checkpoint(Path(semantic).expanduser(), map_location=map_location)
        found = None
        if geometric is not None:
            from sdn3d.geometric.predict import GeometricPredictor
            from sdn3d.inference_export import load_branch_weights

            weights = load_branch_weights(geometric, "geometric", map_location)
            geo = GeometricPredictor.from_weights(weights, map_location=map_location)
            if crop_size is None or margin is None:  # the run's config is only read when needed
                found = _export_crop_settings(weights.settings, weights.path) or geometric_crop_settings(geometric)
        if textural is not None:
            from sdn3d.textural.renderer import TexturalRenderer

            tex = TexturalRenderer.from_checkpoint(Path(textural).expanduser(), map_location=map_location)
            tex.to(map_location)
        if geometric is not None and found is None and crop_size is None:
            log.warning("geometric crop size unknown (no run config.yaml beside %s): using %d", geometric,
                        DEFAULT_CROP_SIZE)
        size = crop_size if crop_size is not None else (found[0] if found else DEFAULT_CROP_SIZE)
        grow = margin if margin is not None else (found[1] if found else DEFAULT_MARGIN)
        return cls(sem, geo, tex, int(size), float(grow))


def _export_crop_settings(settings: Mapping[str, object], path: Path) -> tuple[int, float] | None:
    """``(crop_size, margin)`` an inference export records (None: it records none)."""
    if "crop_size" not in settings:
        return None
    crop, margin = settings.get("crop_size"), settings.get("margin", DEFAULT_MARGIN)
    if (isinstance(crop, bool) or not isinstance(crop, int) or isinstance(margin, bool)
            or not isinstance(margin, (int, float))):
        raise UserInputError(f"inference export {str(path)!r}: settings crop_size and margin must be numbers, got "
                             f"{crop!r} and {margin!r}; export the checkpoint again")
    return int(crop), float(margin)
