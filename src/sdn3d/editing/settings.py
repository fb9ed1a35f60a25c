"""The one translation of an edit configuration (``conf/edit.yaml``, or ``conf/app.yaml``, which holds the same keys,
both typed by :mod:`sdn3d.cli._schemas`) into typed settings: :func:`session_settings` gives the
:class:`~sdn3d.editing.session.SessionSettings` of an :class:`~sdn3d.editing.session.EditSession`, its modes as
enums (:class:`~sdn3d.proposals.Proposals`, :class:`~sdn3d.editing.appearance.Appearance`) and its parts as their
settings (:class:`~sdn3d.editing.photo.settings.PhotoSettings`, :class:`~sdn3d.editing.compose.ComposeSettings`,
:class:`~sdn3d.geometric.fit.FitSettings`, :class:`~sdn3d.geometric.refine.RefineSettings`).

``sdn3d-edit`` and ``sdn3d-app`` both call it (the app once, at start-up), so a setting means the same in both and
the app's ``sdn3d-edit`` command line reproduces its picture. ``cfg`` is any mapping with attribute access of those
keys (an OmegaConf ``DictConfig``); nothing here imports Hydra.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from sdn3d.editing.appearance import APPEARANCES, Appearance
from sdn3d.errors import InputError
from sdn3d.runs import from_trained_data, quality_warnings, semantic_summary, trained_data

__all__ = ["session_settings", "appearance_settings", "compose_settings", "refine_settings", "box_settings",
           "semantic_metrics"]


def session_settings(cfg: Any, checkpoints: dict[str, dict | None], compose: Any = None,
                     appearance: Appearance | None = None, photo: Any = None) -> Any:
    """The :class:`~sdn3d.editing.session.SessionSettings` of an edit configuration: proposals, geometric.min_pixels,
    refine, fit_proposals, box_objects.*, pick_radius, strict, seed, appearance, photo.*, compose*, diagnostics.
    ``checkpoints``: per branch ``{'path', ...}`` or None (``box_objects.prior: auto`` reads the semantic run's
    recorded quality).
    ``compose`` / ``appearance`` / ``photo``: already checked ones.

    Raises:
        InputError (and the photo / compose settings' errors): naming the setting.
    """
    from sdn3d.editing.session import SessionSettings
    from sdn3d.proposals import Proposals

    if appearance is None or photo is None:
        appearance, photo = appearance_settings(cfg)
    fit, prior, iterations, refine_masks = box_settings(cfg, checkpoints)
    return SessionSettings(proposals=Proposals.parse(cfg.proposals, InputError),
                           min_pixels=int(cfg.geometric.min_pixels),
                           refine=refine_settings(cfg), fit_proposals=bool(cfg.get("fit_proposals", True)),
                           box_fit=fit, box_prior=prior, box_iterations=iterations,
                           box_refine_masks=refine_masks,
                           pick_radius=cfg.pick_radius, strict=bool(cfg.strict), seed=int(cfg.seed),
                           appearance=appearance, photo=photo, compose=compose or compose_settings(cfg),
                           diagnostics=bool(cfg.diagnostics))


def appearance_settings(cfg: Any) -> tuple[Appearance, Any]:
    """``(Appearance, PhotoSettings)`` of ``appearance`` and ``photo.*`` (checked before anything is loaded)."""
    from sdn3d.editing.photo.settings import PhotoSettings

    appearance = str(cfg.get("appearance", "photo"))
    if appearance not in APPEARANCES:
        raise InputError(f"appearance must be one of {list(APPEARANCES)} (photo: each edited car drawn with its own "
                         f"pixels through its 3D shape; generator: the paper's textural generator), got {appearance!r}")
    return Appearance(appearance), PhotoSettings.from_mapping(cfg.get("photo"))


def compose_settings(cfg: Any) -> Any:
    """:class:`~sdn3d.editing.compose.ComposeSettings` of ``compose``, ``compose_dilate_px``, ``compose_feather_px``."""
    from sdn3d.editing.compose import ComposeSettings

    return ComposeSettings(str(cfg.compose), cfg.compose_dilate_px, cfg.compose_feather_px)


def refine_settings(cfg: Any) -> Any:
    """The :class:`~sdn3d.geometric.refine.RefineSettings` of ``cfg.refine`` (``conf/refine/paper.yaml``), or
    None when it is off: ``enabled: auto`` turns it on for Cityscapes (``data=cityscapes``, or an image file
    with ``input.camera``), as the paper does, and off for Virtual KITTI."""
    from sdn3d.geometric.refine import RefineSettings

    node = cfg.get("refine")
    enabled = None if node is None else node.get("enabled")
    if enabled == "auto":
        data = cfg.get("data")
        enabled = (data is not None and data.get("kind") == "cityscapes") or (
            data is None and cfg.input.get("camera") is not None)
    if not isinstance(enabled, bool):
        raise InputError(f"refine.enabled must be auto, true or false, got {enabled!r}")
    if not enabled:
        return None
    try:
        return RefineSettings(iterations=int(node.iterations), lr=float(node.lr), params=tuple(node.params),
                              ffd_reg=float(node.ffd_reg), sigma=float(node.sigma))
    except (TypeError, ValueError) as exc:
        raise InputError(f"refine: {exc}") from exc


def box_settings(cfg: Any, checkpoints: dict[str, dict | None]) -> tuple[Any, bool, int, bool]:
    """``(FitSettings, prior, iterations, refine_masks)`` of ``box_objects.*`` for objects named by a box: the fit's
    settings, whether the semantic branch seeds GrabCut (``prior: auto``: when its recorded quality raises no warning
    and the input comes from the data it trained on: a synthetic-trained branch's vehicle probability on a photo is no
    seed; an input not known, e.g. the editor's uploads, is not from it), the GrabCut iterations and whether GrabCut
    runs again seeded by the fitted shapes (the last two typed by the schema, sdn3d.cli._schemas)."""
    from sdn3d.geometric.fit import FitSettings

    node = cfg.get("box_objects") or {}
    prior = node.get("prior", "auto")
    if prior not in ("auto", True, False):
        raise InputError(f"box_objects.prior must be auto, true or false, got {prior!r}")
    if prior == "auto":
        path, metrics = semantic_metrics(checkpoints) if checkpoints.get("semantic") else (None, None)
        frame_input = cfg.get("data") is not None and (cfg.get("input") or {}).get("frame") is not None
        source = cfg.data.root if frame_input else (cfg.get("input") or {}).get("image")
        prior = (metrics is not None and not quality_warnings(metrics, None, str(path))
                 and from_trained_data(trained_data(path), source) is True)
    iterations = node.get("iterations", 5)
    if iterations < 1:
        raise InputError(f"box_objects.iterations must be a positive integer (GrabCut iterations), got {iterations!r}")
    refine_masks = node.get("refine_masks", True)
    try:
        fit = FitSettings(**dict(node.get("fit") or {}))
    except (TypeError, ValueError) as exc:
        raise InputError(f"box_objects.fit: {exc}") from exc
    return fit, bool(prior) and checkpoints.get("semantic") is not None, iterations, refine_masks


def semantic_metrics(checkpoints: dict[str, dict | None]) -> tuple[Path | None, dict | None]:
    """The semantic run's summary file and its recorded ``metrics`` (None where unknown or unreadable)."""
    path = semantic_summary(checkpoints.get("semantic"))
    if path is None:
        return None, None
    try:
        metrics = json.loads(path.read_text(encoding="utf-8")).get("metrics")
    except (OSError, UnicodeDecodeError, ValueError, AttributeError):
        metrics = None
    return path, metrics if isinstance(metrics, dict) else None
