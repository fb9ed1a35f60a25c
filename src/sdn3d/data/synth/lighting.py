"""Lighting and weather of the Virtual KITTI variations: ``Look`` presets, shading, sky, fog, rain.

Colours are linear RGB; :func:`tonemap` maps them to 8-bit sRGB-like values. The angle
variations keep the clone's look (only the camera turns).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.data.synth.noise import fbm, hash_cells

__all__ = ["Surface", "Look", "LOOKS", "look_for", "shade", "sky_color", "apply_weather", "tonemap"]


@dataclass
class Surface:
    """Flat per-pixel surface attributes of the foreground pixels (P of them).

    Attributes:
        material: ``(P,)`` material ids; color ``(P, 3)`` base albedo; param ``(P, 8)``.
        world: ``(P, 3)`` world-frame position; normal: ``(P, 3)`` world-frame unit normal facing
            the camera; view: ``(P, 3)`` unit world direction from the surface to the camera.
        footprint: ``(P,)`` metres covered by one pixel at that depth (for anti-aliasing).
        local: ``(P, 3)`` canonical car coordinates (car pixels only, else 0).
        template: ``(P,)`` vehicle shape id of car pixels (``vehicle_family.VEHICLE_SHAPE_NAMES``), -1 elsewhere;
            wheel: ``(P,)`` bool, wheel faces.
    """

    material: Tensor
    color: Tensor
    param: Tensor
    world: Tensor
    normal: Tensor
    view: Tensor
    footprint: Tensor
    local: Tensor
    template: Tensor
    wheel: Tensor


def _sun(elevation_deg: float, azimuth_deg: float) -> tuple[float, float, float]:
    """Unit world direction towards the sun; azimuth 0 is straight ahead (+z), 90 to the right (+x)."""
    el, az = math.radians(elevation_deg), math.radians(azimuth_deg)
    return (math.cos(el) * math.sin(az), -math.sin(el), math.cos(el) * math.cos(az))


@dataclass(frozen=True)
class Look:
    """Lighting and weather of a variation.

    Attributes:
        sun_dir: world direction towards the sun (y down, so elevation makes y negative).
        sun, ambient: light colours (linear RGB, already scaled by intensity).
        zenith, horizon: sky gradient colours.
        exposure: multiplies the radiance before tone mapping.
        fog_distance: metres at which fog hides 63% of a surface (0: no fog).
        fog_color: colour surfaces fade to.
        rain: draw rain streaks and darken / gloss the ground.
        clouds: cloud cover of the sky in [0, 1].
    """

    sun_dir: tuple[float, float, float]
    sun: tuple[float, float, float]
    ambient: tuple[float, float, float]
    zenith: tuple[float, float, float]
    horizon: tuple[float, float, float]
    exposure: float = 1.0
    fog_distance: float = 0.0
    fog_color: tuple[float, float, float] = (0.6, 0.62, 0.65)
    rain: bool = False
    clouds: float = 0.2


_CLONE = Look(_sun(48.0, 35.0), (2.3, 2.2, 2.0), (0.42, 0.47, 0.58), (0.10, 0.28, 0.75), (0.55, 0.70, 0.90))

#: The look of every Virtual KITTI variation; the angle variations keep the clone's lighting.
LOOKS: dict[str, Look] = {
    "clone": _CLONE,
    "morning": Look(
        _sun(14.0, -60.0),
        (2.3, 1.9, 1.3),
        (0.40, 0.40, 0.46),
        (0.22, 0.40, 0.78),
        (0.90, 0.82, 0.70),
        exposure=1.05,
        clouds=0.1,
    ),
    "sunset": Look(
        _sun(4.0, 20.0),
        (1.9, 0.95, 0.40),
        (0.30, 0.24, 0.30),
        (0.16, 0.20, 0.45),
        (1.00, 0.50, 0.22),
        exposure=1.0,
        clouds=0.3,
    ),
    "overcast": Look(
        _sun(40.0, 30.0),
        (0.35, 0.35, 0.36),
        (0.95, 0.97, 1.0),
        (0.50, 0.52, 0.56),
        (0.70, 0.71, 0.73),
        exposure=1.0,
        clouds=0.9,
    ),
    "fog": Look(
        _sun(40.0, 30.0),
        (0.30, 0.30, 0.30),
        (0.90, 0.92, 0.95),
        (0.62, 0.64, 0.67),
        (0.72, 0.73, 0.75),
        exposure=1.0,
        fog_distance=55.0,
        fog_color=(0.66, 0.68, 0.70),
        clouds=1.0,
    ),
    "rain": Look(
        _sun(40.0, 30.0),
        (0.20, 0.20, 0.21),
        (0.70, 0.73, 0.78),
        (0.35, 0.37, 0.41),
        (0.50, 0.52, 0.55),
        exposure=1.0,
        fog_distance=160.0,
        fog_color=(0.45, 0.47, 0.50),
        rain=True,
        clouds=1.0,
    ),
}
for _angle in ("15-deg-left", "15-deg-right", "30-deg-left", "30-deg-right"):
    LOOKS[_angle] = _CLONE


def look_for(variation: str) -> Look:
    if variation not in LOOKS:
        raise ValueError(f"variation must be one of {sorted(LOOKS)}, got {variation!r}")
    return LOOKS[variation]


def shade(s: Surface, albedo: Tensor, emissive: Tensor, gloss: Tensor, look: Look, shadow: Tensor) -> Tensor:
    """Lambert + ambient (brighter for up-facing surfaces) + Blinn-Phong highlight, linear RGB ``(P, 3)``.

    ``shadow`` ``(P,)`` in [0, 1] scales the direct sun (1 = fully lit).
    """
    dev = albedo.device
    sun_dir = torch.tensor(look.sun_dir, device=dev)
    sun = torch.tensor(look.sun, device=dev)
    ambient = torch.tensor(look.ambient, device=dev)
    n_dot_l = (s.normal @ sun_dir).clamp(min=0.0)
    sky_fac = 0.65 + 0.35 * (-s.normal[:, 1])  # y is down: up-facing surfaces see more sky
    half = torch.nn.functional.normalize(s.view + sun_dir, dim=1)
    spec = (s.normal * half).sum(1).clamp(min=0.0) ** 40 * gloss
    direct = (n_dot_l * shadow).unsqueeze(1) * sun
    color = albedo * (ambient * sky_fac.unsqueeze(1) + direct) + (spec * shadow).unsqueeze(1) * sun * 0.35
    fresnel = (1 - (s.normal * s.view).sum(1).abs()).clamp(0, 1) ** 3 * gloss
    return color + fresnel.unsqueeze(1) * torch.tensor(look.horizon, device=dev) * 0.3 + emissive


def sky_color(dirs: Tensor, look: Look, seed: int) -> Tensor:
    """``(Q, 3)`` sky radiance for unit world view directions ``(Q, 3)``: gradient, sun glow, clouds."""
    dev = dirs.device
    elevation = (-dirs[:, 1]).clamp(min=0.0)
    t = (1 - elevation).pow(4).unsqueeze(1)
    color = torch.tensor(look.zenith, device=dev) * (1 - t) + torch.tensor(look.horizon, device=dev) * t
    sun_dir = torch.tensor(look.sun_dir, device=dev)
    glow = (dirs @ sun_dir).clamp(min=0.0) ** 200 * 3 + (dirs @ sun_dir).clamp(min=0.0) ** 8 * 0.25
    color = color + glow.unsqueeze(1) * torch.tensor(look.sun, device=dev) * (1 - look.clouds * 0.8)
    plane = dirs[:, [0, 2]] / (elevation.unsqueeze(1) + 0.08)  # clouds on a plane above the camera
    cloud = (fbm(plane, (1.2, 0.4), seed + 71) - (1 - look.clouds)).clamp(0, 1) / max(look.clouds, 1e-3)
    cloud_col = torch.tensor(look.horizon, device=dev) * 1.1
    cover = (cloud * min(1.0, look.clouds * 1.5)).unsqueeze(1)
    return color * (1 - cover) + cloud_col * cover


def apply_weather(image: Tensor, depth: Tensor, look: Look, rng_seed: int) -> Tensor:
    """Fog by depth and rain streaks on a linear ``(H, W, 3)`` image; ``depth`` ``(H, W)`` (inf = sky)."""
    out = image
    if look.fog_distance > 0:
        keep = torch.exp(-depth.clamp(max=1e4) / look.fog_distance).unsqueeze(-1)
        fog = torch.tensor(look.fog_color, device=image.device)
        out = out * keep + fog * (1 - keep)
    if look.rain:
        h, w = depth.shape
        rows = torch.arange(h, device=image.device).view(-1, 1).float()
        cols = torch.arange(w, device=image.device).view(1, -1).float()
        scale = w / 624.0
        slanted = torch.floor((cols + 0.25 * rows) / max(1.0, 1.5 * scale))  # streak columns, slanted
        length = 14.0 * scale
        offset = hash_cells(slanted.reshape(-1, 1).long(), rng_seed).view(1, -1) * length
        segment = torch.floor((rows + offset.view_as(slanted)) / length)
        ids = torch.stack([slanted.expand(h, w).reshape(-1), segment.reshape(-1)], 1).long()
        streak = (hash_cells(ids, rng_seed + 1) < 0.025).view(h, w).float()
        out = out * (1 - 0.35 * streak.unsqueeze(-1)) + 0.35 * streak.unsqueeze(-1) * 0.8
    return out


def tonemap(image: Tensor, exposure: float) -> Tensor:
    """Linear radiance ``(H, W, 3)`` -> uint8: soft exposure curve ``1 - exp(-x)``, then gamma 1/2.2."""
    mapped = 1.0 - torch.exp(-image.clamp(min=0.0) * exposure * 1.6)
    return (mapped.pow(1 / 2.2) * 255.0 + 0.5).clamp(0, 255).to(torch.uint8)
