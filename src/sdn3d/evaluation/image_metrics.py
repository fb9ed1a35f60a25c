"""Image-quality metrics on whole images, on region masks and on box crops (plain torch / torchmetrics).

Conventions (all functions):

- images ``(B, C, H, W)`` float in ``[0, data_range]`` (default 1); one value per image ``(B,)``.
- ``mask``: ``(B, H, W)`` or ``(B, 1, H, W)`` bool, True where the metric is taken; a masked metric
  averages over the masked pixels and all channels. An image whose mask is empty gets NaN
  (average with ``torch.nanmean``).
- ``boxes``: ``(B, 4)`` ``(x0, y0, x1, y1)`` half-open pixel ranges ``[x0, x1) x [y0, y1)``, clipped to
  the image; both images are cropped and the metric is computed on the crop. Empty crop: NaN.

Masked PSNR is ``10 log10(range^2 / masked MSE)``; masked SSIM is the mean of torchmetrics' SSIM map
(Gaussian window 11, sigma 1.5, reflect padding: the map has the image's size) over the mask, so
an all-True mask gives the whole-image SSIM. On crops with a side under 7 px the Gaussian window
shrinks (sigma = (side - 1) / 3.5) so that it fits; LPIPS upsamples images and crops with a side
under 32 px (bilinear, both images; :data:`sdn3d.nets.lpips.MIN_SIDE`) because AlexNet needs that much input.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import torch
from torch import Tensor
from torchmetrics.functional.image import peak_signal_noise_ratio, structural_similarity_index_measure

if TYPE_CHECKING:
    from sdn3d.nets.lpips import LPIPS

__all__ = [
    "crop_metrics",
    "image_metrics",
    "l1",
    "lpips",
    "mse",
    "psnr",
    "region_image_metrics",
    "ssim",
]



def _check(pred: Tensor, target: Tensor, mask: Tensor | None) -> Tensor | None:
    if pred.dim() != 4 or pred.shape != target.shape:
        raise ValueError(f"pred and target must both be (B, C, H, W), got {tuple(pred.shape)} and "
                         f"{tuple(target.shape)}")
    if mask is None:
        return None
    if mask.dim() == 4 and mask.shape[1] == 1:
        mask = mask[:, 0]
    b, _, h, w = pred.shape
    if mask.shape != (b, h, w):
        raise ValueError(f"mask must be (B, H, W) or (B, 1, H, W) with B, H, W = {(b, h, w)}, got {tuple(mask.shape)}")
    return mask.bool()


def _masked_mean(values: Tensor, mask: Tensor) -> Tensor:
    """Mean of ``values (B, C, H, W)`` over ``mask (B, H, W)`` and channels; NaN for empty masks."""
    m = mask[:, None].to(values.dtype)
    count = m.sum((1, 2, 3)) * values.shape[1]
    total = (values * m).sum((1, 2, 3))
    return torch.where(count > 0, total / count.clamp(min=1), torch.full_like(total, float("nan")))


def l1(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """Mean absolute error per image ``(B,)`` (over ``mask`` when given)."""
    mask = _check(pred, target, mask)
    diff = (pred - target).abs()
    return diff.mean((1, 2, 3)) if mask is None else _masked_mean(diff, mask)


def mse(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """Mean squared error per image ``(B,)`` (over ``mask`` when given)."""
    mask = _check(pred, target, mask)
    diff = (pred - target) ** 2
    return diff.mean((1, 2, 3)) if mask is None else _masked_mean(diff, mask)


def psnr(pred: Tensor, target: Tensor, mask: Tensor | None = None, data_range: float = 1.0) -> Tensor:
    """PSNR in dB per image ``(B,)`` (over ``mask`` when given; inf for identical images)."""
    if mask is None:
        _check(pred, target, None)
        return peak_signal_noise_ratio(pred, target, data_range=data_range, reduction="none", dim=(1, 2, 3))
    err = mse(pred, target, mask)
    return 10 * torch.log10(data_range**2 / err)


def ssim(pred: Tensor, target: Tensor, mask: Tensor | None = None, data_range: float = 1.0,
         sigma: float = 1.5) -> Tensor:
    """SSIM per image ``(B,)`` (torchmetrics, Gaussian window); mean of the SSIM map over ``mask`` when given."""
    mask = _check(pred, target, mask)
    if mask is None:
        return structural_similarity_index_measure(pred, target, data_range=data_range, sigma=sigma,
                                                   reduction="none")
    return _masked_mean(_ssim_maps(pred, target, data_range, sigma)[1], mask)


def _ssim_maps(pred: Tensor, target: Tensor, data_range: float = 1.0, sigma: float = 1.5) -> tuple[Tensor, Tensor]:
    """``(SSIM per image (B,), SSIM map (B, C, H', W'))`` of :func:`ssim`'s settings, one torchmetrics call."""
    return structural_similarity_index_measure(pred, target, data_range=data_range, sigma=sigma, reduction="none",
                                               return_full_image=True)


def lpips(pred: Tensor, target: Tensor, net: LPIPS, mask: Tensor | None = None) -> Tensor:
    """LPIPS per image ``(B,)`` with ``net`` (:class:`sdn3d.nets.lpips.LPIPS`); masked: mean of the spatial map."""
    mask = _check(pred, target, mask)
    with torch.no_grad():
        if mask is None:
            return net(pred, target)
        return _masked_mean(net(pred, target, spatial=True), mask)


def image_metrics(pred: Tensor, target: Tensor, mask: Tensor | None = None,
                  lpips_net: LPIPS | None = None) -> dict[str, Tensor]:
    """``{'l1', 'psnr', 'ssim'[, 'lpips']}`` per image ``(B,)``, on the whole images or over ``mask``."""
    return region_image_metrics(pred, target, {"region": mask}, lpips_net)["region"]


def region_image_metrics(pred: Tensor, target: Tensor, masks: Mapping[str, Tensor | None],
                         lpips_net: LPIPS | None = None) -> dict[str, dict[str, Tensor]]:
    """``{name: image_metrics(pred, target, mask)}`` for each of ``masks`` (None: the whole images), the same
    values, with the SSIM map of ``pred`` vs ``target`` computed once for all of them (it does not depend on
    the mask)."""
    _check(pred, target, None)
    whole, full = _ssim_maps(pred, target)
    out = {}
    for name, mask in masks.items():
        mask = _check(pred, target, mask)
        values = {"l1": l1(pred, target, mask), "psnr": psnr(pred, target, mask),
                  "ssim": whole if mask is None else _masked_mean(full, mask)}
        if lpips_net is not None:
            values["lpips"] = lpips(pred, target, lpips_net, mask)
        out[name] = values
    return out


def _crop_ssim(p: Tensor, t: Tensor, data_range: float) -> Tensor:
    side = min(p.shape[-2:])
    if side < 2:
        return p.new_full((1,), float("nan"))
    return ssim(p, t, data_range=data_range, sigma=min(1.5, (side - 1) / 3.5))


def crop_metrics(pred: Tensor, target: Tensor, boxes: Tensor, lpips_net: LPIPS | None = None,
                 data_range: float = 1.0) -> dict[str, Tensor]:
    """``{'l1', 'psnr', 'ssim'[, 'lpips']}`` per image ``(B,)`` on the crops ``boxes (B, 4)`` (module doc)."""
    _check(pred, target, None)
    if boxes.shape != (pred.shape[0], 4):
        raise ValueError(f"boxes must be (B, 4) with B = {pred.shape[0]}, got {tuple(boxes.shape)}")
    h, w = pred.shape[-2:]
    names = ["l1", "psnr", "ssim"] + (["lpips"] if lpips_net is not None else [])
    out: dict[str, list[Tensor]] = {k: [] for k in names}
    nan = pred.new_full((1,), float("nan"))
    # Crops differ in size: one small loop over the images of the batch.
    for i, (x0, y0, x1, y1) in enumerate(boxes.round().long().tolist()):
        x0, x1 = max(0, x0), min(w, x1)
        y0, y1 = max(0, y0), min(h, y1)
        if x1 <= x0 or y1 <= y0:
            for k in names:
                out[k].append(nan)
            continue
        p, t = pred[i:i + 1, :, y0:y1, x0:x1], target[i:i + 1, :, y0:y1, x0:x1]
        out["l1"].append(l1(p, t))
        out["psnr"].append(psnr(p, t, data_range=data_range))
        out["ssim"].append(_crop_ssim(p, t, data_range))
        if lpips_net is not None:
            out["lpips"].append(lpips(p, t, lpips_net))
    return {k: torch.cat(v) for k, v in out.items()}
