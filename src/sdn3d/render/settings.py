"""Renderer settings: small frozen dataclasses.

Units: image sizes are ``(H, W)`` in pixels; ``near`` / ``far`` are camera-frame z in metres;
the soft silhouette's ``sigma`` is in **pixels squared** (see :class:`SoftSilhouetteSettings`).

Hydra config group ``conf/renderer`` (``default.yaml``, in ``sdn3d-train``'s and ``sdn3d-render-demo``'s
configs) holds one ``_target_`` node per dataclass, field for field: ``renderer.soft`` is
:class:`SoftSilhouetteSettings` (``sigma``, ``cull_eps``, ``near``, ``max_pairs_per_chunk``,
``cull_backfaces``) and
``renderer.hard`` is :class:`RasterSettings` (``near``, ``far``, ``cull_backfaces``,
``max_pairs_per_chunk``). ``image_size`` is left out: it is the crop or frame at hand, given when
building one, ``hydra.utils.instantiate(cfg.renderer.soft, image_size=(64, 64))``. Configs that
need the softness interpolate ``${renderer.soft.sigma}`` (the geometric branch's ``model.sigma``,
``refine.sigma`` of ``conf/refine/paper.yaml``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["RasterSettings", "SoftSilhouetteSettings", "sigma_from_ndc"]


def _check_image_size(image_size: tuple[int, int], owner: str) -> tuple[int, int]:
    if len(tuple(image_size)) != 2:
        raise ValueError(f"{owner}.image_size must be (H, W), got {image_size!r}")
    height, width = (int(s) for s in image_size)
    if height <= 0 or width <= 0 or (height, width) != tuple(image_size):
        raise ValueError(f"{owner}.image_size must be two positive integers (H, W), got {image_size!r}")
    return height, width


def _check_near(near: float, owner: str) -> None:
    if not math.isfinite(near) or near <= 0:
        raise ValueError(f"{owner}.near must be a positive finite camera-frame z, got {near}")


@dataclass(frozen=True)
class RasterSettings:
    """Settings of the hard z-buffer rasterizer (:func:`sdn3d.render.rasterize_meshes`).

    Args:
        image_size: ``(H, W)`` in pixels.
        near: faces with **any** vertex at ``z < near`` are culled (no clipping: scenes put
            objects in front of the camera; a ground plane must start beyond ``near``).
        far: faces with all vertices beyond ``far`` are culled, and pixels deeper than ``far``
            are left empty.
        cull_backfaces: drop faces whose right-hand-rule normal ``(v1 - v0) x (v2 - v0)``
            points away from the camera (trimesh's outward winding). Off by default: the
            procedural templates and ground planes need not be consistently wound.
        max_pairs_per_chunk: bound on the (face, pixel) pairs processed at once; memory use is
            about 60 bytes per pair.
    """

    image_size: tuple[int, int]
    near: float = 0.1
    far: float = 1000.0
    cull_backfaces: bool = False
    max_pairs_per_chunk: int = 4_000_000

    def __post_init__(self) -> None:
        object.__setattr__(self, "image_size", _check_image_size(self.image_size, "RasterSettings"))
        _check_near(self.near, "RasterSettings")
        if not self.far > self.near:
            raise ValueError(f"RasterSettings.far must exceed near={self.near}, got {self.far}")
        if self.max_pairs_per_chunk <= 0:
            raise ValueError(
                f"RasterSettings.max_pairs_per_chunk must be positive, got {self.max_pairs_per_chunk}"
            )


def sigma_from_ndc(sigma_ndc: float, image_size: tuple[int, int]) -> float:
    """Convert a SoftRas ``sigma`` (NDC units squared) to pixels squared.

    SoftRas measures distances in NDC, where the image width ``S`` spans ``[-1, 1]``, i.e. one
    NDC unit is ``S / 2`` pixels; hence ``sigma_px2 = sigma_ndc * (S / 2) ** 2``. For non-square
    images the width is used (SoftRas renders square images). SoftRas' ``sigma_val = 1e-4`` at
    64x64 is about ``0.1`` px^2.
    """
    _, width = _check_image_size(image_size, "sigma_from_ndc")
    return float(sigma_ndc) * (width / 2.0) ** 2


@dataclass(frozen=True)
class SoftSilhouetteSettings:
    """Settings of the SoftRas-style soft silhouette (:func:`sdn3d.render.soft_silhouette`).

    ``D_j(p) = sigmoid(delta * d^2(p, j) / sigma)`` with ``d`` in **pixels**, so ``sigma`` is in
    pixels squared: the width of the soft edge is the same in pixels whatever the crop size.
    Equivalence with SoftRas (distances in NDC, image width ``S`` spanning 2 units):
    ``sigma_px2 = sigma_ndc * (S / 2) ** 2`` (see :func:`sigma_from_ndc`).

    The default ``sigma = 0.25`` px^2 gives a soft edge about 1.5 px wide (``D = 0.27`` half a
    pixel outside a face, ``0.018`` one pixel outside), a little softer than SoftRas'
    ``sigma_val = 1e-4`` at 64x64 (about ``0.1`` px^2); pose fitting from a perturbed start
    converges with it (tests). Softer edges (``1.0`` px^2: ``D = 0.27`` one pixel out) widen the
    basin but cost time: the culling radius grows with ``sqrt(sigma)`` and the work roughly
    with its square (small faces).

    Args:
        image_size: ``(H, W)`` of each per-mesh crop.
        sigma: softness in pixels squared.
        cull_eps: a face is ignored at pixels outside it farther than ``r`` with
            ``sigmoid(-r^2 / sigma) = cull_eps``, i.e. ``r^2 = sigma * log(1 / cull_eps - 1)``
            (``r = 1.52`` px for the defaults). Each dropped term is below ``cull_eps``; the
            silhouette differs from the exact (dense) one by a few ``cull_eps`` (below 1e-3 for
            the defaults; lower ``cull_eps`` for very soft edges on finely tessellated meshes).
        near: faces with any vertex at ``z < near`` are culled.
        max_pairs_per_chunk: (face, pixel) pairs processed at once. Each chunk costs ~50 tensor
            ops of overhead; ~1e5 pairs balances that against cache use on CPU (GPUs like more).
            Temporaries are ~100 bytes per pair; the backward keeps 32 bytes per pair.
        cull_backfaces: drop faces whose right-hand-rule normal ``(v1 - v0) x (v2 - v0)`` points away from
            the camera (as :class:`RasterSettings`). For a closed, consistently wound mesh the front faces
            alone cover its silhouette, so this halves the (face, pixel) pairs; each outline edge then has
            one soft side instead of two (its front face's), so the silhouette is a little sharper outside
            the outline, and pixels on an edge two front faces share reach only about 0.75 inside it (the
            back faces behind filled them to 1). Off by default: meshes need not be closed or consistently
            wound.
        native_kernel: on CPU tensors, draw with the fused C++ kernel (``render/soft_kernel.cpp``, built with g++ on
            first use and cached; :mod:`sdn3d.render._native`). It evaluates the same pairs' terms as the PyTorch
            path, one pair at a time, so results agree up to float summation order (and the window padding's
            terms below ``cull_eps ** 9``); about 10x less time. ``False``, on other devices, or without a compiler:
            the pure-PyTorch path.
    """

    image_size: tuple[int, int]
    sigma: float = 0.25
    cull_eps: float = 1e-4
    near: float = 0.1
    max_pairs_per_chunk: int = 131_072
    cull_backfaces: bool = False
    native_kernel: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "image_size", _check_image_size(self.image_size, "SoftSilhouetteSettings"))
        if not math.isfinite(self.sigma) or self.sigma <= 0:
            raise ValueError(f"SoftSilhouetteSettings.sigma must be positive (pixels^2), got {self.sigma}")
        if not 0 < self.cull_eps < 0.5:
            raise ValueError(f"SoftSilhouetteSettings.cull_eps must lie in (0, 0.5), got {self.cull_eps}")
        _check_near(self.near, "SoftSilhouetteSettings")
        if self.max_pairs_per_chunk <= 0:
            raise ValueError(
                f"SoftSilhouetteSettings.max_pairs_per_chunk must be positive, got {self.max_pairs_per_chunk}"
            )

    @property
    def cull_radius_sq(self) -> float:
        """Squared culling radius in pixels^2: ``sigma * log(1 / cull_eps - 1)``."""
        return self.sigma * math.log(1.0 / self.cull_eps - 1.0)

    @property
    def cull_radius(self) -> float:
        """Culling radius in pixels."""
        return math.sqrt(self.cull_radius_sq)
