"""The trained branches of a de-render (:class:`Models`), loaded from files: Lightning checkpoints or inference
exports, and what their predictors need beyond the weights, read from the export or else the run's ``config.yaml``:
the geometric branch's crop settings (:func:`geometric_crop_settings`) and the semantic branch's training frame size
(:func:`semantic_trained_size`).

:func:`sdn3d.derender.derender` takes a :class:`Models`; this module is where they come from (floor 5, beside
:mod:`sdn3d.derender` and :mod:`sdn3d.runs`).
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import torch

from sdn3d.errors import UserInputError

if TYPE_CHECKING:
    from sdn3d.geometric.predict import GeometricPredictor
    from sdn3d.io import TorchFiles
    from sdn3d.semantic.predict import SemanticPredictor
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["DEFAULT_CROP_SIZE", "DEFAULT_MARGIN", "Models", "geometric_crop_settings", "semantic_trained_size"]

log = logging.getLogger("sdn3d.derender")  # the logger these messages always had

#: Paper crop side of the geometric branch (released 3D-SDN code), used when a run does not say.
DEFAULT_CROP_SIZE = 256
DEFAULT_MARGIN = 0.1


def _run_config(checkpoint: str | os.PathLike, branch: str, purpose: str) -> tuple[dict, Path] | None:
    """The saved config of ``checkpoint``'s run (``<run>/config.yaml`` beside ``<run>/checkpoints/*.ckpt``, or
    beside the file), as plain data, and its path; None where there is none. The file is only read (nothing in it
    is instantiated or resolved).

    Raises:
        UserInputError: naming the config file and ``purpose``, when it is not readable YAML.
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
            raise UserInputError(f"the {branch} run's config {str(config)!r} (read for its {purpose}) is not "
                                 f"readable YAML ({reason}); fix it or {_GIVE[branch]}") from exc
        return (tree if isinstance(tree, dict) else {}), config
    return None


_GIVE = {"geometric": "give the crop size and margin", "semantic": "export the checkpoint with a run config beside it"}


def geometric_crop_settings(checkpoint: str | os.PathLike) -> tuple[int, float] | None:
    """``(crop_size, margin)`` the geometric run of ``checkpoint`` trained with, or None if unknown.

    Read from the run's saved config (``<run>/config.yaml`` beside ``<run>/checkpoints/*.ckpt``, written by
    ``sdn3d-train``): the crop size is a datamodule setting, not in the checkpoint.

    Raises:
        UserInputError: naming the config file, when it is not readable YAML or its ``datamodule.crop_size``
            / ``margin`` are not numbers (pass ``crop_size`` and ``margin`` explicitly to skip it).
    """
    found = _run_config(checkpoint, "geometric", "crop size")
    if found is None:
        return None
    tree, config = found
    dm = tree.get("datamodule") or {}
    if isinstance(dm, dict) and isinstance(dm.get("crop_size"), int):
        crop, margin = dm["crop_size"], dm.get("margin", DEFAULT_MARGIN)
        if isinstance(crop, bool) or isinstance(margin, bool) or not isinstance(margin, (int, float)):
            raise UserInputError(f"the geometric run's config {str(config)!r}: datamodule.crop_size and margin "
                                 f"must be numbers, got {crop!r} and {margin!r}; fix it or give the crop size "
                                 "and margin")
        return int(crop), float(margin)
    return None


def semantic_trained_size(checkpoint: str | os.PathLike) -> tuple[int, int] | None:
    """``(W, H)`` of the frames the semantic run of ``checkpoint`` trained on, or None if unknown: its saved
    config's ``datamodule.image_size``, else its ``data.image_size`` (the datamodule's null means the data's).

    The network learnt objects at that scale: run at another (the demo's branch, trained at 312x96, on a
    624x192 working image) it found a quarter of the cars (docs/results/2026-11-30_cpu/session19/inst), so
    :class:`~sdn3d.semantic.predict.SemanticPredictor` resizes its input to about this size.

    Raises:
        UserInputError: naming the config file, when it is not readable YAML or the size is not two positive
            integers.
    """
    found = _run_config(checkpoint, "semantic", "training frame size")
    if found is None:
        return None
    tree, config = found
    for section in ("datamodule", "data"):
        part = tree.get(section) or {}
        value = part.get("image_size") if isinstance(part, dict) else None
        if value is not None and not (isinstance(value, str) and value.startswith("${")):
            return _image_size(value, f"the semantic run's config {str(config)!r}: {section}.image_size")
    return None


def _image_size(value: object, where: str) -> tuple[int, int]:
    """``(W, H)`` from ``value``, two positive integers; else UserInputError naming ``where``."""
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or any(isinstance(v, bool) or not isinstance(v, int) or v <= 0 for v in value)):
        raise UserInputError(f"{where} must be [W, H], two positive integers, got {value!r}")
    return int(value[0]), int(value[1])


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
                         crop_size: int | None = None, margin: float | None = None,
                         semantic_size: tuple[int, int] | None = None, traffic: str = "right",
                         files: TorchFiles | None = None) -> Models:
        """Load the branches from their Lightning checkpoints or inference exports (None: branch absent;
        :func:`sdn3d.inference_export.load_branch_weights` tells the two apart by content). ``files``: what reads
        them (:class:`~sdn3d.io.TorchFiles`: a file it read before is not read again, tensors mapped with its
        ``mmap``); None: each is read whole.

        ``crop_size`` / ``margin`` None: the geometric export's settings, else the geometric run's
        (:func:`geometric_crop_settings`), else :data:`DEFAULT_CROP_SIZE` / :data:`DEFAULT_MARGIN`. The semantic
        predictor runs at ``semantic_size`` ``(W, H)``, else at about the size its branch trained at: the export's
        ``image_size``, else the run's (:func:`semantic_trained_size`), else the image's own size. ``traffic``: the
        side of the road the input's traffic keeps to (:class:`~sdn3d.geometric.lamps.Traffic`: ``right``, ``left`` or
        ``none``), which end the geometric branch's lamp cue takes a car cut by the image's left or right border to
        show (:attr:`~sdn3d.geometric.lamps.LampCue.traffic`).

        Raises:
            UserInputError: ``semantic_size`` is not two positive integers; ``traffic`` is not a side; a file or a
                run's setting is unreadable.
        """
        from sdn3d.geometric.lamps import Traffic

        side = Traffic.parse(traffic, "geometric.traffic", UserInputError)
        if semantic_size is not None:
            semantic_size = _image_size(list(semantic_size), "semantic.size")
        for name, path in (("semantic", semantic), ("geometric", geometric), ("textural", textural)):
            if path is not None and not Path(path).expanduser().is_file():
                raise FileNotFoundError(f"{name} checkpoint {os.fspath(path)!r} does not exist")
        sem = geo = tex = None
        if semantic is not None:
            from sdn3d.inference_export import load_branch_weights
            from sdn3d.semantic.predict import SemanticPredictor

            weights = load_branch_weights(Path(semantic).expanduser(), "semantic", map_location, files)
            trained = None
            if semantic_size is None:  # the export's or the run's size is only read when needed
                trained = _export_image_size(weights.settings, weights.path) or semantic_trained_size(semantic)
            sem = SemanticPredictor.from_weights(weights, map_location=map_location, image_size=semantic_size,
                                                 trained_size=trained)
        found = None
        if geometric is not None:
            from sdn3d.geometric.predict import GeometricPredictor
            from sdn3d.inference_export import load_branch_weights

            weights = load_branch_weights(geometric, "geometric", map_location, files)
            geo = GeometricPredictor.from_weights(weights, map_location=map_location)
            if geo.lamp_cue is not None:
                geo.lamp_cue = replace(geo.lamp_cue, traffic=side)
            if crop_size is None or margin is None:  # the run's config is only read when needed
                found = _export_crop_settings(weights.settings, weights.path) or geometric_crop_settings(geometric)
        if textural is not None:
            from sdn3d.textural.renderer import TexturalRenderer

            tex = TexturalRenderer.from_checkpoint(Path(textural).expanduser(), map_location=map_location,
                                                  files=files)
            tex.to(map_location)
        if geometric is not None and found is None and crop_size is None:
            log.warning("geometric crop size unknown (no run config.yaml beside %s): using %d", geometric,
                        DEFAULT_CROP_SIZE)
        size = crop_size if crop_size is not None else (found[0] if found else DEFAULT_CROP_SIZE)
        grow = margin if margin is not None else (found[1] if found else DEFAULT_MARGIN)
        return cls(sem, geo, tex, int(size), float(grow))


def _export_image_size(settings: Mapping[str, object], path: Path) -> tuple[int, int] | None:
    """``(W, H)`` of the training frames a semantic inference export records (None: it records none)."""
    if "image_size" not in settings:
        return None
    return _image_size(settings["image_size"], f"inference export {str(path)!r}: settings image_size")


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
