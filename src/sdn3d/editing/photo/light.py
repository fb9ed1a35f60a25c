"""One directional light and an ambient term fitted to the input's car pixels (the photo appearance's step 4:
:mod:`sdn3d.editing.photo`), and the view-dependent reflection of a car's glass and paint (:func:`fit_reflection`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.image_ops import luminance

__all__ = ["LightEstimate", "fit_light", "grazing", "fit_reflection", "REFLECTION_POWER",
           "REFLECTION_MIN_EXPLAINED"]


@dataclass(frozen=True)
class LightEstimate:
    """One directional light: ``shade(n) = ambient + (1 - ambient) max(0, n . direction)``.

    Attributes:
        direction: ``(3,)`` unit vector towards the light (camera frame); ambient: in (0, 1];
        gain: the fit's residual cut against constant shading (0: no better, 1: perfect); pixels: used.
    """

    direction: Tensor
    ambient: float
    gain: float
    pixels: int

    def shade(self, normals: Tensor) -> Tensor:
        """``(...,)`` shading of unit ``normals (..., 3)``."""
        lam = (normals * self.direction.to(normals)).sum(-1).clamp(min=0)
        return self.ambient + (1 - self.ambient) * lam

    def to_dict(self) -> dict:
        return {"direction": [round(float(x), 4) for x in self.direction], "ambient": round(self.ambient, 4),
                "gain": round(self.gain, 4), "pixels": self.pixels}


# -- fit ---------------------------------------------------------------------------------------------


def _sphere(n: int) -> Tensor:
    """``(n, 3)`` float64 unit vectors spread evenly (Fibonacci sphere)."""
    k = torch.arange(n, dtype=torch.float64) + 0.5
    y = 1 - 2 * k / n
    r = (1 - y * y).sqrt()
    phi = math.pi * (3 - math.sqrt(5)) * k
    return torch.stack([r * phi.cos(), y, r * phi.sin()], 1)


def fit_light(colors: Tensor, normals: Tensor, groups: Tensor, directions: int = 256,
              ambients: tuple[float, ...] = (0.15, 0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85),
              max_pixels: int = 12000) -> LightEstimate | None:
    """Fit one directional light and an ambient term to object pixels (module doc, step 4).

    Each pixel's luminance is modelled as ``albedo[group] * shade(normal)``; per light the albedos are solved in
    closed form on log luminance, and the light with the least squared residual wins. Very dark and saturated
    pixels are left out, and so are lights below the horizon. Give body pixels only (:func:`body_pixels`): dark
    windows on top of a car would otherwise read as light from below.

    Args:
        colors: ``(P, 3)`` sRGB in [0, 1]; normals: ``(P, 3)`` unit camera-frame normals; groups: ``(P,)`` object
            index of each pixel (one albedo each).
        max_pixels: at most this many usable pixels, evenly spaced in their order, enter the fit: the
            ``(P, directions x ambients)`` table of a 1242x375 frame's cars took most of a second, and 12,000
            pixels pin a light of 3 + groups numbers as well as 50,000 do.

    Returns:
        The best light, or None with fewer than 50 usable pixels.

    Example:
        >>> import torch
        >>> n = torch.nn.functional.normalize(torch.randn(2000, 3, generator=torch.Generator().manual_seed(0)), dim=1)
        >>> light = torch.tensor([0.0, -0.8, -0.6])
        >>> y = 0.6 * (0.3 + 0.7 * (n @ light).clamp(min=0))
        >>> fit = fit_light(y[:, None].expand(-1, 3), n, torch.zeros(2000, dtype=torch.long))
        >>> bool((fit.direction @ light) > 0.98), round(fit.ambient, 2)
        (True, 0.35)
    """
    y = luminance(colors.double())
    keep = (y > 0.04) & (y < 0.97) & torch.isfinite(normals).all(1)
    if int(keep.sum()) < 50:
        return None
    y, n, g = y[keep], normals[keep].double(), groups[keep]
    if len(y) > max_pixels:
        pick = torch.linspace(0, len(y) - 1, max_pixels, dtype=torch.float64).round().long()
        y, n, g = y[pick], n[pick], g[pick]
    _, g = torch.unique(g, return_inverse=True)
    groups_n = int(g.max()) + 1
    count = torch.bincount(g, minlength=groups_n).double()
    log_y = y.log()
    dirs = _sphere(directions)
    dirs = dirs[dirs[:, 1] <= 0.1]  # street scenes: the light comes from above the horizon (camera y points down)
    amb = torch.tensor(ambients, dtype=torch.float64)
    lam = (n @ dirs.T).clamp(min=0)  # (P, D)
    log_s = (amb[None, None, :] + (1 - amb[None, None, :]) * lam[..., None]).log().flatten(1)  # (P, D*A)
    resid = log_y[:, None] - log_s
    total = torch.zeros(groups_n, resid.shape[1], dtype=torch.float64).index_add_(0, g, resid)
    # sum over pixels of (resid - group mean)^2 = sum resid^2 - sum over groups of total^2 / count
    err = (resid * resid).sum(0) - (total * total / count[:, None]).sum(0)
    flat = log_y - (torch.zeros(groups_n, dtype=torch.float64).index_add_(0, g, log_y) / count)[g]
    base = float((flat**2).sum())
    best = int(err.argmin())
    d, a = divmod(best, len(ambients))
    gain = 1 - float(err[best]) / base if base > 0 else 0.0
    return LightEstimate(dirs[d].float(), float(amb[a]), gain, len(y))


# -- view-dependent reflection -------------------------------------------------------------------------------------

#: Exponent of :func:`grazing`: Schlick's approximation of the Fresnel factor of glass and clear-coated paint,
#: ``F0 + (1 - F0) (1 - cos)^5``.
REFLECTION_POWER = 5.0
#: :func:`fit_reflection`'s least share of a part's colour variance the reflection must explain.
REFLECTION_MIN_EXPLAINED = 0.2


def grazing(cos: Tensor) -> Tensor:
    """``(...,)`` the view-dependent part of a glossy surface's reflection (Schlick: ``(1 - cos)^5``) seen at
    ``|cos|`` ``(...,)`` between its normal and the line of sight: 0 seen squarely, 1 edge-on. A window seen at a
    grazing angle mirrors the sky; turned to face the camera it shows its dark inside."""
    return (1 - cos).clamp(0, 1) ** REFLECTION_POWER


def fit_reflection(colors: Tensor, cos: Tensor, min_pixels: int = 30, min_spread: float = 0.02,
                   min_explained: float = REFLECTION_MIN_EXPLAINED) -> Tensor | None:
    """``(3,)`` per-channel strength ``r >= 0`` of the reflection in one part of one car: ``colors (Q, 3)`` (sRGB)
    seen at view cosines ``cos (Q,)`` fitted as ``a + r * grazing(cos)`` by least squares. The colour a point of
    that part shows at a new view is then its old colour plus ``r`` times the change of :func:`grazing`. None with
    fewer than ``min_pixels`` pixels, a standard deviation of :func:`grazing` under ``min_spread`` (the part was
    seen from one angle only: the strength is not observable), or a fit that explains less than ``min_explained``
    of the colours' variance (the colours change over the part for another reason: paint, shading, dirt).

    Example:
        >>> cos = torch.linspace(0.2, 1.0, 100, dtype=torch.float64)
        >>> colors = 0.05 + torch.tensor([0.6, 0.7, 0.8], dtype=torch.float64) * grazing(cos)[:, None]
        >>> [round(v, 3) for v in fit_reflection(colors, cos).tolist()]
        [0.6, 0.7, 0.8]
        >>> fit_reflection(colors, torch.full((100,), 0.9, dtype=torch.float64)) is None
        True
    """
    if len(colors) < min_pixels:
        return None
    g = grazing(cos.double())
    centred = g - g.mean()
    var = float((centred * centred).mean())
    if var < min_spread**2:
        return None
    c = colors.double() - colors.double().mean(0)
    strength = ((centred[:, None] * c).mean(0) / var).clamp(min=0)
    explained = float((strength * strength).sum()) * var / max(float((c * c).mean(0).sum()), 1e-12)
    return strength if explained >= min_explained else None
