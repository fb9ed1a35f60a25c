"""Texture codes: one code per region of an image, and the ways to edit them.

A *region* is one id of the instance label map ``L`` of one image: an object (instance id
``class_id * 1000 + k`` >= 1000) or a background class (its semantic class id < 1000). The
texture encoder E gives every region one code (dim 5 in the paper), its mean feature
(instance-wise average pooling). Codes are kept as flat :class:`TextureCodes` rows
``(batch, id, code)``; :func:`code_map` broadcasts them back into the generator's
``(B, code_dim, H, W)`` input. Editing appearance = changing rows: :func:`set_code`,
:func:`swap_codes`, or :func:`sample_code` from a :class:`CodeBank` of codes seen in training
(:meth:`CodeBank.nearest` picks one by colour; the bank's file: :mod:`sdn3d.textural.code_bank`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.labels import INSTANCE_DIVISOR, region_class

__all__ = ["CodeBank", "TextureCodes", "code_donors", "code_map", "rgb_to_lab", "sample_code", "set_code", "swap_codes"]


@dataclass(frozen=True)
class TextureCodes:
    """Texture codes of the regions of a batch, one row per ``(image, region id)``.

    Attributes:
        batch: ``(N,)`` long image index; ids: ``(N,)`` long region id (values of ``L``).
        codes: ``(N, C)`` float codes.
    """

    batch: Tensor
    ids: Tensor
    codes: Tensor

    def __post_init__(self) -> None:
        n = self.codes.shape[0]
        if self.codes.dim() != 2 or self.batch.shape != (n,) or self.ids.shape != (n,):
            raise ValueError(f"TextureCodes needs batch (N,), ids (N,), codes (N, C); got {tuple(self.batch.shape)}, "
                             f"{tuple(self.ids.shape)}, {tuple(self.codes.shape)}")

    def __len__(self) -> int:
        return self.codes.shape[0]

    @property
    def code_dim(self) -> int:
        return self.codes.shape[1]

    @property
    def classes(self) -> Tensor:
        """``(N,)`` semantic class of each region."""
        return region_class(self.ids)

    def rows(self, image: int, region_id: int) -> Tensor:
        """Indices of the rows of ``(image, region_id)`` (0 or 1 rows)."""
        return torch.nonzero((self.batch == image) & (self.ids == region_id)).view(-1)

    def get(self, image: int, region_id: int) -> Tensor:
        """The ``(C,)`` code of region ``region_id`` of image ``image``."""
        row = self.rows(image, region_id)
        if row.numel() == 0:
            raise KeyError(f"no texture code for region {region_id} of image {image}")
        return self.codes[row[0]]

    def image(self, image: int) -> dict[int, Tensor]:
        """``{region id: (C,) code}`` of one image."""
        sel = self.batch == image
        return dict(zip(self.ids[sel].tolist(), self.codes[sel], strict=True))

    def to(self, device: str | torch.device) -> TextureCodes:
        return TextureCodes(self.batch.to(device), self.ids.to(device), self.codes.to(device))

    def detach(self) -> TextureCodes:
        return TextureCodes(self.batch, self.ids, self.codes.detach())


def code_map(codes: TextureCodes, L: Tensor, missing: str = "zero") -> Tensor:
    """Broadcast per-region codes into a ``(B, C, H, W)`` map over ``L (B, H, W)`` (vectorised lookup).

    Args:
        missing: pixels whose ``(image, id)`` has no code get zeros (``'zero'``) or raise (``'error'``).
    """
    if L.dim() != 3:
        raise ValueError(f"L must be (B, H, W), got {tuple(L.shape)}")
    if missing not in ("zero", "error"):
        raise ValueError(f"missing must be 'zero' or 'error', got {missing!r}")
    L = L.long()
    dev = L.device
    b = L.shape[0]
    span = max(int(L.max()) if L.numel() else 0, int(codes.ids.max()) if len(codes) else 0) + 1
    keys = codes.batch.to(dev) * span + codes.ids.to(dev)
    order = torch.argsort(keys)
    sorted_keys = keys[order]
    pix = torch.arange(b, device=dev).view(-1, 1, 1) * span + L
    pos = torch.searchsorted(sorted_keys, pix.reshape(-1)).clamp(max=max(len(codes) - 1, 0))
    found = sorted_keys[pos] == pix.reshape(-1) if len(codes) else torch.zeros_like(pix.reshape(-1), dtype=torch.bool)
    if missing == "error" and not bool(found.all()):
        lost = torch.unique(pix.reshape(-1)[~found])
        raise ValueError(f"no texture code for {lost.numel()} region(s), e.g. image {int(lost[0]) // span} "
                         f"id {int(lost[0]) % span}")
    table = codes.codes.to(dev)[order] if len(codes) else L.new_zeros(1, codes.code_dim, dtype=codes.codes.dtype)
    values = table[pos] * found[:, None].to(table.dtype)
    return values.view(b, *L.shape[1:], -1).permute(0, 3, 1, 2)


def set_code(codes: TextureCodes, image: int, region_id: int, code: Tensor) -> TextureCodes:
    """A copy of ``codes`` where region ``region_id`` of ``image`` has ``code (C,)`` (row added if absent)."""
    code = code.reshape(1, -1).to(codes.codes)
    if code.shape[1] != codes.code_dim:
        raise ValueError(f"code must have {codes.code_dim} values, got {code.shape[1]}")
    row = codes.rows(image, region_id)
    if row.numel():
        new = codes.codes.clone()
        new[row] = code
        return TextureCodes(codes.batch, codes.ids, new)
    return TextureCodes(torch.cat([codes.batch, codes.batch.new_tensor([image])]),
                        torch.cat([codes.ids, codes.ids.new_tensor([region_id])]),
                        torch.cat([codes.codes, code]))


def swap_codes(codes: TextureCodes, a: tuple[int, int], b: tuple[int, int]) -> TextureCodes:
    """Exchange the codes of regions ``a = (image, id)`` and ``b = (image, id)`` (e.g. two cars' paint)."""
    code_a, code_b = codes.get(*a).clone(), codes.get(*b).clone()
    return set_code(set_code(codes, *a, code_b), *b, code_a)


class CodeBank:
    """Codes seen in training, grouped by semantic class: ``{class_id: (M, C)}``, optionally with the mean colour
    of each code's region ``{class_id: (M, 3)}`` (sRGB in [0, 1]).

    Build with :meth:`from_regions` (codes and colours, what ``sdn3d-train`` writes:
    :func:`sdn3d.textural.code_bank.build_code_bank`) or :meth:`from_codes` (codes only); files:
    :func:`sdn3d.textural.code_bank.save_code_bank` / ``load_code_bank``.
    """

    def __init__(self, codes: Mapping[int, Tensor], colors: Mapping[int, Tensor] | None = None) -> None:
        self.codes = {int(k): v for k, v in codes.items() if v.numel()}
        dims = {v.shape[1] for v in self.codes.values()}
        if len(dims) > 1 or any(v.dim() != 2 for v in self.codes.values()):
            raise ValueError(f"CodeBank codes must all be (M, C) with one C, got C in {sorted(dims)}")
        self.colors = None if colors is None else {int(k): v for k, v in colors.items() if int(k) in self.codes}
        if self.colors is not None and (set(self.colors) != set(self.codes) or any(
                self.colors[k].shape != (v.shape[0], 3) for k, v in self.codes.items())):
            raise ValueError("CodeBank colors must give one (M, 3) colour per code of every class")

    @classmethod
    def from_regions(cls, ids: Tensor, codes: Tensor, colors: Tensor) -> CodeBank:
        """From flat rows: region ids ``(N,)`` (instance ids or background classes), codes ``(N, C)``, their
        regions' mean colours ``(N, 3)``."""
        cls_ids = region_class(ids)
        groups = {int(c): cls_ids == c for c in torch.unique(cls_ids)}
        return cls({c: codes[sel] for c, sel in groups.items()}, {c: colors[sel] for c, sel in groups.items()})

    @classmethod
    def from_codes(cls, batches: Iterable[TextureCodes], objects_only: bool = False) -> CodeBank:
        """Group the rows of ``batches`` by class (``objects_only``: keep instance regions only); no colours."""
        batches = list(batches)
        if not batches:
            return cls({})
        ids = torch.cat([b.ids.cpu() for b in batches])
        codes = torch.cat([b.codes.detach().cpu() for b in batches])
        if objects_only:
            keep = ids >= INSTANCE_DIVISOR
            ids, codes = ids[keep], codes[keep]
        cls_ids = region_class(ids)
        return cls({int(c): codes[cls_ids == c] for c in torch.unique(cls_ids)})  # one entry per class

    @property
    def classes(self) -> list[int]:
        return sorted(self.codes)

    @property
    def code_dim(self) -> int:
        return next(iter(self.codes.values())).shape[1] if self.codes else 0

    def __len__(self) -> int:
        return sum(v.shape[0] for v in self.codes.values())

    def _class_codes(self, class_id: int) -> Tensor:
        if class_id not in self.codes:
            raise KeyError(f"no training codes for class {class_id}; the bank has classes {self.classes}")
        return self.codes[class_id]

    def sample(self, class_id: int, n: int = 1, generator: torch.Generator | None = None) -> Tensor:
        """``(n, C)`` codes drawn uniformly (with replacement) among the class's training codes."""
        bank = self._class_codes(class_id)
        idx = torch.randint(bank.shape[0], (n,), generator=generator)
        return bank[idx]

    def mean(self, class_id: int) -> Tensor:
        """``(C,)`` mean training code of a class."""
        return self._class_codes(class_id).mean(0)

    def nearest(self, class_id: int, rgb: Tensor) -> tuple[Tensor, Tensor]:
        """``(code (C,), its region's colour (3,))``: the class's training code whose region's mean colour is
        nearest ``rgb (3,)`` (sRGB in [0, 1]) in CIE Lab (Euclidean, CIE76)."""
        codes = self._class_codes(class_id)
        if self.colors is None:
            raise ValueError("this code bank has no colours (build it with CodeBank.from_regions)")
        colors = self.colors[class_id]
        best = int((rgb_to_lab(colors) - rgb_to_lab(rgb.reshape(1, 3))).norm(dim=1).argmin())
        return codes[best], colors[best]

def rgb_to_lab(rgb: Tensor) -> Tensor:
    """sRGB ``(..., 3)`` in [0, 1] -> CIE Lab ``(..., 3)`` (D65 white; L in [0, 100])."""
    rgb = rgb.float().clamp(0, 1)
    linear = torch.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    m = rgb.new_tensor([[0.4124564, 0.3575761, 0.1804375],
                        [0.2126729, 0.7151522, 0.0721750],
                        [0.0193339, 0.1191920, 0.9503041]])
    xyz = linear @ m.T / rgb.new_tensor([0.95047, 1.0, 1.08883])
    eps, kappa = 216 / 24389, 24389 / 27
    f = torch.where(xyz > eps, xyz.clamp_min(eps) ** (1 / 3), (kappa * xyz + 16) / 116)
    return torch.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def code_donors(ids: Tensor, generator: torch.Generator | None = None) -> Tensor:
    """For code swapping in training: ``(N,)`` index of the region whose code each region of ``ids (N,)`` gets.

    Objects (ids >= 1000) get the code of another object of their class, a random cyclic shift within the class
    (a derangement: nobody keeps their own code when the class has two objects or more); a class's only object
    and background regions keep their own (index = itself).
    """
    n = ids.numel()
    own = torch.arange(n, device=ids.device)
    group = torch.where(ids >= INSTANCE_DIVISOR, region_class(ids), torch.full_like(ids, -1))
    perm = torch.randperm(n, generator=generator).to(ids.device)
    order = perm[torch.argsort(group[perm], stable=True)]  # grouped by class, random order within a class
    _, counts = torch.unique_consecutive(group[order], return_counts=True)
    start = torch.repeat_interleave(torch.cumsum(counts, 0) - counts, counts)
    size = torch.repeat_interleave(counts, counts)
    nxt = start + (torch.arange(n, device=ids.device) - start + 1) % size
    donors = torch.empty_like(own)
    donors[order] = order[nxt]
    return torch.where(group >= 0, donors, own)


def sample_code(codes: TextureCodes, bank: CodeBank, image: int, region_id: int,
                generator: torch.Generator | None = None) -> TextureCodes:
    """Give region ``region_id`` of ``image`` a random training code of its class (new appearance).

    Objects: ``region_id`` is the instance id; a background class: its class id.
    """
    cls_id = int(region_class(torch.tensor(region_id)))
    return set_code(codes, image, region_id, bank.sample(cls_id, 1, generator)[0])
