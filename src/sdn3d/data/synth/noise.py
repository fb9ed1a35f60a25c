"""Deterministic procedural noise for the synthetic scenes' textures (vectorised, seedable)."""

from __future__ import annotations

import functools

import torch
from torch import Tensor

__all__ = ["hash_cells", "value_noise", "fbm"]

_MASK = 0xFFFFFFFF


def hash_cells(cells: Tensor, seed: int) -> Tensor:
    """``(P, D)`` int64 lattice cells -> ``(P,)`` floats in [0, 1), a fixed integer hash."""
    primes = (73856093, 19349663, 83492791)
    h = torch.full(cells.shape[:1], (seed * 2654435761) & _MASK, dtype=torch.long, device=cells.device)
    for d in range(cells.shape[1]):
        h = h ^ ((cells[:, d] * primes[d]) & _MASK)
    h = (((h >> 16) ^ h) * 0x45D9F3B) & _MASK
    h = (((h >> 16) ^ h) * 0x45D9F3B) & _MASK
    h = (h >> 16) ^ h
    return h.to(torch.float32) * (1.0 / 4294967296.0)


#: Lattice size of the noise tables (the noise repeats every ``_PERIOD`` features).
_PERIOD = {2: 256, 3: 32}


@functools.lru_cache(maxsize=512)
def _noise_table(dims: int, seed: int) -> Tensor:
    """Random lattice values in [0, 1) with a wrap-around border, ``(1, 1, N+1, N+1[, N+1])``."""
    n = _PERIOD[dims]
    gen = torch.Generator().manual_seed(int(seed) & 0x7FFFFFFFFFFFFFFF)
    table = torch.rand((n,) * dims, generator=gen)
    for d in range(dims):  # periodic border so interpolation across the seam wraps
        table = torch.cat([table, table.narrow(d, 0, 1)], dim=d)
    return table.reshape(1, 1, *table.shape)


def value_noise(coords: Tensor, scale: float, seed: int) -> Tensor:
    """Value noise in [0, 1) of ``(P, D)`` coordinates (D = 2 or 3) with feature size ``scale``.

    Random values on a periodic lattice (256^2 or 32^3 cells), interpolated (bi/trilinear,
    ``grid_sample``): one fused lookup per octave instead of hashing every lattice corner.
    """
    dims = coords.shape[1]
    if dims not in _PERIOD:
        raise ValueError(f"coords must be (P, 2) or (P, 3), got {tuple(coords.shape)}")
    n = _PERIOD[dims]
    table = _noise_table(dims, seed).to(coords.device)
    # grid_sample's last grid axis is x = the table's last dimension: reverse the coordinates.
    grid = torch.remainder(coords.flip(1) / scale, n) * (2.0 / n) - 1.0
    grid = grid.view(1, *([1] * (dims - 1)), -1, dims).to(table.dtype)
    out = torch.nn.functional.grid_sample(table, grid, mode="bilinear", padding_mode="border", align_corners=True)
    return out.reshape(-1)


def fbm(coords: Tensor, scales: tuple[float, ...], seed: int) -> Tensor:
    """Sum of value-noise octaves with halving weights, normalised to [0, 1)."""
    total = torch.zeros(coords.shape[0], dtype=torch.float32, device=coords.device)
    norm = 0.0
    for i, scale in enumerate(scales):
        w = 0.5**i
        total = total + w * value_noise(coords, scale, seed + 101 * i)
        norm += w
    return total / norm
