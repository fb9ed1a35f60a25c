"""Texture codes: one code per region of an image, and the ways to edit them.

A *region* is one id of the instance label map ``L`` of one image: an object (instance id
``class_id * 1000 + k`` >= 1000) or a background class (its semantic class id < 1000). The
texture encoder E gives every region one code (dim 5 in the paper), its mean feature
(instance-wise average pooling). Codes are kept as flat :class:`TextureCodes` rows
``(batch, id, code)``; :func:`code_map` broadcasts them back into the generator's
``(B, code_dim, H, W)`` input. Editing appearance = changing rows: :func:`set_code`,
:func:`swap_codes`, or :func:`sample_code` from a :class:`CodeBank` of codes seen in training.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.labels import INSTANCE_DIVISOR, region_class

__all__ = ["CodeBank", "TextureCodes", "code_map", "sample_code", "set_code", "swap_codes"]


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
    """Codes seen in training, grouped by semantic class: ``{class_id: (M, C)}``.

    Build with :meth:`from_codes` over the training set's :class:`TextureCodes` (see
    :meth:`TexturalRenderer.encode`); save with ``torch.save(bank.state_dict(), path)``.
    """

    def __init__(self, codes: Mapping[int, Tensor]) -> None:
        self.codes = {int(k): v for k, v in codes.items() if v.numel()}
        dims = {v.shape[1] for v in self.codes.values()}
        if len(dims) > 1 or any(v.dim() != 2 for v in self.codes.values()):
            raise ValueError(f"CodeBank codes must all be (M, C) with one C, got C in {sorted(dims)}")

    @classmethod
    def from_codes(cls, batches: Iterable[TextureCodes], objects_only: bool = False) -> CodeBank:
        """Group the rows of ``batches`` by class (``objects_only``: keep instance regions only)."""
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

    def __len__(self) -> int:
        return sum(v.shape[0] for v in self.codes.values())

    def sample(self, class_id: int, n: int = 1, generator: torch.Generator | None = None) -> Tensor:
        """``(n, C)`` codes drawn uniformly (with replacement) among the class's training codes."""
        if class_id not in self.codes:
            raise KeyError(f"no training codes for class {class_id}; the bank has classes {self.classes}")
        bank = self.codes[class_id]
        idx = torch.randint(bank.shape[0], (n,), generator=generator)
        return bank[idx]

    def mean(self, class_id: int) -> Tensor:
        """``(C,)`` mean training code of a class."""
        if class_id not in self.codes:
            raise KeyError(f"no training codes for class {class_id}; the bank has classes {self.classes}")
        return self.codes[class_id].mean(0)

    def state_dict(self) -> dict[str, Tensor]:
        return {str(k): v for k, v in self.codes.items()}

    @classmethod
    def from_state_dict(cls, state: Mapping[str, Tensor]) -> CodeBank:
        return cls({int(k): v for k, v in state.items()})


def sample_code(codes: TextureCodes, bank: CodeBank, image: int, region_id: int,
                generator: torch.Generator | None = None) -> TextureCodes:
    """Give region ``region_id`` of ``image`` a random training code of its class (new appearance).

    Objects: ``region_id`` is the instance id; a background class: its class id.
    """
    cls_id = int(region_class(torch.tensor(region_id)))
    return set_code(codes, image, region_id, bank.sample(cls_id, 1, generator)[0])
