"""Procedural textures of the synthetic street scenes (albedo, emission, gloss per pixel).

All functions work on flat tensors of pixels (no per-pixel Python loops). Textures are functions
of world (or object-canonical) coordinates and a per-world seed, so a surface looks the same in
every frame and every variation of a world; only the lighting, fog and rain change (see
``lighting.py``, whose names are re-exported here).
"""

from __future__ import annotations

import torch
from torch import Tensor

from sdn3d.data.synth.classes import Material
from sdn3d.data.synth.lighting import LOOKS, Look, Surface, apply_weather, look_for, shade, sky_color, tonemap
from sdn3d.data.synth.noise import fbm, hash_cells, value_noise
from sdn3d.meshes.parts import MAX_GLASS_RISE
from sdn3d.meshes.vehicle_family import FAMILY, canonical_belt

__all__ = [
    "Look",
    "LOOKS",
    "look_for",
    "value_noise",
    "fbm",
    "Surface",
    "surface_albedo",
    "shade",
    "sky_color",
    "apply_weather",
    "tonemap",
    "TEMPLATE_BELT",
    "VEHICLE_BELT",
]

#: Approximate belt line (bottom of the side windows) of each template as canonical y (down is
#: +0.5); the car texture makes the surface above it glass where it is not roof-like.
TEMPLATE_BELT: tuple[float, ...] = (-0.18, -0.16, -0.14, -0.19, -0.14, -0.07, -0.01, 0.12)
#: Belt line of every vehicle shape by shape id (``vehicle_family.VEHICLE_SHAPE_NAMES``): the templates',
#: then each held-out family shape's (its spec's belt height, :func:`~sdn3d.meshes.vehicle_family.canonical_belt`).
VEHICLE_BELT: tuple[float, ...] = TEMPLATE_BELT + tuple(canonical_belt(shape.spec) for shape in FAMILY)


def _smooth_band(dist: Tensor, half_width: float | Tensor, footprint: Tensor) -> Tensor:
    """Coverage in [0, 1] of a band ``|d| < half_width`` over a pixel of size ``footprint`` (anti-aliased)."""
    return ((half_width - dist.abs()) / footprint.clamp(min=1e-4) + 0.5).clamp(0.0, 1.0)


# --- textures -----------------------------------------------------------------------------------


def _road(s: Surface, idx: Tensor, seed: int, markings: tuple[Tensor, Tensor, float]) -> Tensor:
    xz = s.world[idx][:, [0, 2]]
    base = s.color[idx]
    grain = fbm(xz, (0.35, 1.4, 6.0), seed + 11)
    patches = (value_noise(xz, 9.0, seed + 12) > 0.72).float() * 0.25
    albedo = base * (0.75 + 0.5 * grain - patches).unsqueeze(1)
    mark_x, dashed, width = markings
    if mark_x.numel():
        dist = xz[:, :1] - mark_x.unsqueeze(0)  # (p, K)
        cover = _smooth_band(dist, width / 2, s.footprint[idx].unsqueeze(1))
        on_dash = (torch.remainder(xz[:, 1:2], 9.0) < 3.0).float()
        cover = cover * torch.where(dashed.unsqueeze(0), on_dash, torch.ones_like(on_dash))
        paint = cover.amax(1, keepdim=True) * (0.8 + 0.2 * grain.unsqueeze(1))
        albedo = albedo * (1 - paint) + 0.6 * paint
    return albedo


def _sidewalk(s: Surface, idx: Tensor, seed: int) -> Tensor:
    xz = s.world[idx][:, [0, 2]]
    fp = s.footprint[idx].unsqueeze(1)
    tile = torch.remainder(xz + 0.25, 0.5) - 0.25  # distance to the nearest groove, per axis
    groove = 1 - _smooth_band(tile.abs() - 0.25, 0.02, fp).amax(1, keepdim=True)  # 0 in grooves
    groove = 1 - (1 - groove) * (0.04 / fp).clamp(max=1.0)  # grooves fade with distance
    shade = 0.8 + 0.3 * value_noise(torch.floor(xz / 0.5), 1.0, seed + 21).unsqueeze(1)
    return s.color[idx] * shade * (0.7 + 0.3 * groove)


def _terrain(s: Surface, idx: Tensor, seed: int) -> Tensor:
    xz = s.world[idx][:, [0, 2]]
    mix = fbm(xz, (2.0, 7.0), seed + 31).unsqueeze(1)
    dirt = torch.tensor([0.20, 0.15, 0.08], device=xz.device)
    fine = 0.75 + 0.5 * value_noise(xz, 0.3, seed + 32).unsqueeze(1)
    return (s.color[idx] * (1 - mix) + dirt * mix * 0.8) * fine


def _facade(s: Surface, idx: Tensor) -> Tensor:
    p, n, base, prm = s.world[idx], s.normal[idx], s.color[idx], s.param[idx]
    horiz = torch.where(n[:, 0].abs() > n[:, 2].abs(), p[:, 2], p[:, 0])
    height = -p[:, 1]
    col_f = torch.remainder(horiz / prm[:, 0], 1.0)
    floor_f = torch.remainder(height / prm[:, 1], 1.0)
    half = prm[:, 2] / 2
    window = ((col_f - 0.5).abs() < half) & (floor_f > 0.3) & (floor_f < 0.82) & (height > 1.0)
    shop = (prm[:, 3] > 0.5) & (height < 3.2)
    window = torch.where(shop, (height > 0.4) & (height < 2.8) & ((col_f - 0.5).abs() < 0.45), window)
    vertical = n[:, 1].abs() < 0.5
    window = window & vertical
    glass = torch.tensor([0.05, 0.07, 0.09], device=p.device) * (
        0.6
        + 0.8
        * hash_cells(
            torch.stack([torch.floor(horiz / prm[:, 0]), torch.floor(height / prm[:, 1])], 1).long(), 7
        ).unsqueeze(1)
    )
    return torch.where(window.unsqueeze(1), glass, base)


def _foliage(s: Surface, idx: Tensor, seed: int) -> Tensor:
    p = s.world[idx]
    leaf = fbm(p + s.param[idx][:, :1], (0.25, 0.8), seed + 41).unsqueeze(1)
    return s.color[idx] * (0.45 + 1.1 * leaf)


def _trunk(s: Surface, idx: Tensor, seed: int) -> Tensor:
    p = s.world[idx]
    bark = value_noise(torch.stack([p[:, 0] * 8 + p[:, 2] * 8, p[:, 1]], 1), 0.7, seed + 51)
    return s.color[idx] * (0.7 + 0.6 * bark).unsqueeze(1)


def _plain(s: Surface, idx: Tensor, seed: int) -> Tensor:
    return s.color[idx] * (0.88 + 0.24 * value_noise(s.world[idx], 0.8, seed + 61)).unsqueeze(1)


def _sign(s: Surface, idx: Tensor) -> Tensor:
    """Round signs (kind 0: coloured ring on white, kind 1: coloured disc) on a dark square plate,
    kind 2: a coloured diamond on a white plate; drawn in plate coordinates (param: kind, size, centre)."""
    prm = s.param[idx]
    local = s.world[idx] - prm[:, 2:5]
    half = prm[:, 1] / 2
    r = torch.linalg.vector_norm(local[:, :2], dim=1) / half
    kind = prm[:, 0].unsqueeze(1)
    color = s.color[idx]
    white = torch.full_like(color, 0.75)
    plate = torch.full_like(color, 0.12)
    round_sign = torch.where((r < 0.7).unsqueeze(1) & (kind == 0), white, color)
    round_sign = torch.where((r > 1.0).unsqueeze(1), plate, round_sign)
    diamond = ((local[:, :2].abs().sum(1) / half) < 0.8).unsqueeze(1)
    return torch.where(kind == 2, torch.where(diamond, color, white), round_sign)


def _light(s: Surface, idx: Tensor) -> tuple[Tensor, Tensor]:
    prm = s.param[idx]
    local = s.world[idx] - prm[:, 2:5]
    lamp_y = torch.tensor([-0.3, 0.0, 0.3], device=local.device)
    d = torch.sqrt(local[:, :1] ** 2 + (local[:, 1:2] - lamp_y) ** 2)  # (p, 3)
    lamp = (d < 0.11) & (s.normal[idx][:, 2:3] < -0.5)
    colors = torch.tensor([[1.0, 0.05, 0.02], [1.0, 0.6, 0.02], [0.1, 1.0, 0.3]], device=local.device)
    lit = torch.nn.functional.one_hot(prm[:, 0].long().clamp(0, 2), 3).bool() & lamp
    emissive = (lit.float() @ colors) * 2.0
    albedo = torch.where(lamp.any(1, keepdim=True), torch.full_like(s.color[idx], 0.05), s.color[idx])
    return albedo, emissive


def _car(s: Surface, idx: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    loc, n, base = s.local[idx], s.normal[idx], s.color[idx]
    belt = torch.tensor(VEHICLE_BELT, device=loc.device)[s.template[idx].clamp(min=0)]
    up = -n[:, 1]
    glass = (loc[:, 1] < belt) & (up < MAX_GLASS_RISE) & (loc[:, 1] > -0.49)
    lower = loc[:, 1] > 0.36
    albedo = torch.where(lower.unsqueeze(1), base * 0.55 + 0.01, base)
    albedo = torch.where(glass.unsqueeze(1), torch.tensor([0.015, 0.02, 0.025], device=loc.device), albedo)
    light_band = (loc[:, 1] > belt + 0.04) & (loc[:, 1] < belt + 0.2) & (loc[:, 2].abs() > 0.28)
    head = light_band & (loc[:, 0] > 0.47)
    tail = light_band & (loc[:, 0] < -0.47)
    albedo = torch.where((head | tail).unsqueeze(1), torch.full_like(albedo, 0.1), albedo)
    emissive = head.unsqueeze(1) * torch.tensor([0.5, 0.5, 0.45], device=loc.device)
    emissive = emissive + tail.unsqueeze(1) * torch.tensor([0.5, 0.02, 0.02], device=loc.device)
    wheel = s.wheel[idx]
    rim = wheel & (loc[:, 2].abs() > 0.3)
    albedo = torch.where(wheel.unsqueeze(1), torch.full_like(albedo, 0.02), albedo)
    albedo = torch.where(rim.unsqueeze(1) & (up.abs() < 0.3).unsqueeze(1), torch.full_like(albedo, 0.12), albedo)
    gloss = torch.where(glass, 1.0, torch.where(wheel | lower, 0.05, 0.6))
    return albedo, emissive, gloss


def surface_albedo(s: Surface, seed: int, markings: tuple[Tensor, Tensor, float]) -> tuple[Tensor, Tensor, Tensor]:
    """Albedo ``(P, 3)``, emission ``(P, 3)`` and glossiness ``(P,)`` of every foreground pixel.

    Args:
        s: the pixels' surface attributes.
        seed: the world's texture seed.
        markings: lane marking world x ``(K,)``, dashed flags ``(K,)`` bool, line width (m).
    """
    num = s.material.shape[0]
    albedo = s.color.clone()
    emissive = torch.zeros_like(albedo)
    gloss = torch.zeros(num, dtype=albedo.dtype, device=albedo.device)
    simple = {
        Material.ROAD: lambda i: _road(s, i, seed, markings),
        Material.SIDEWALK: lambda i: _sidewalk(s, i, seed),
        Material.TERRAIN: lambda i: _terrain(s, i, seed),
        Material.FACADE: lambda i: _facade(s, i),
        Material.CROWN: lambda i: _foliage(s, i, seed),
        Material.BUSH: lambda i: _foliage(s, i, seed + 5),
        Material.TRUNK: lambda i: _trunk(s, i, seed),
        Material.PLAIN: lambda i: _plain(s, i, seed),
        Material.ROOF: lambda i: _plain(s, i, seed + 3),
        Material.METAL: lambda i: _plain(s, i, seed + 7),
        Material.SIGN: lambda i: _sign(s, i),
    }
    for material, fn in simple.items():
        idx = (s.material == material).nonzero().squeeze(1)
        if idx.numel():
            albedo[idx] = fn(idx)
    gloss[s.material == Material.METAL] = 0.3
    gloss[s.material == Material.ROAD] = 0.05
    idx = (s.material == Material.LIGHT).nonzero().squeeze(1)
    if idx.numel():
        albedo[idx], emissive[idx] = _light(s, idx)
    idx = (s.material == Material.CAR).nonzero().squeeze(1)
    if idx.numel():
        albedo[idx], emissive[idx], gloss[idx] = _car(s, idx)
    return albedo.clamp(0.0, 1.0), emissive, gloss
