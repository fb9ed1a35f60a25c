"""Per-image refinement of predicted 3D attributes by minimising L_reproj (3D-SDN on Cityscapes).

Cityscapes has no 3D labels, so the paper takes a Virtual-KITTI-trained de-renderer and refines
its predictions on each image: Adam (lr 0.03) for 16 iterations on the reprojection loss between
the rendered silhouette and the instance mask. As in the released code, the rotation, the
projected-centre offset, the log scale and the FFD are optimised; the distance (``log tau``) and
the mesh choice are kept, and the FFD is held small by ``ffd_reg * mean(phi^2)`` (weight 100 there).
The FFD stays mirror-symmetric: its free half lattice is what is optimised.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.geometric.decode import decode_outputs
from sdn3d.geometric.losses import outside_image_mask, render_silhouettes, reprojection_error
from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.ffd import expand_half_ffd, half_indices
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.settings import SoftSilhouetteSettings

__all__ = ["RefineSettings", "RefineResult", "refine_by_reprojection", "adam_fit", "REFINABLE"]

#: Raw outputs that can be refined.
REFINABLE = ("rotation", "offset", "log_scale", "log_distance", "phi")


@dataclass(frozen=True)
class RefineSettings:
    """How :func:`refine_by_reprojection` optimises (defaults: the paper's Cityscapes setting).

    Args:
        iterations: Adam steps.
        lr: Adam learning rate.
        params: raw outputs to optimise (subset of :data:`REFINABLE`).
        ffd_reg: weight of ``mean(phi^2)``.
        sigma: soft-silhouette softness in pixels^2.
    """

    iterations: int = 16
    lr: float = 0.03
    params: tuple[str, ...] = ("rotation", "offset", "log_scale", "phi")
    ffd_reg: float = 100.0
    sigma: float = 0.25

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", tuple(str(p) for p in self.params))
        if self.iterations < 0:
            raise ValueError(f"iterations must be non-negative, got {self.iterations}")
        if not self.lr > 0:
            raise ValueError(f"lr must be positive, got {self.lr}")
        unknown = sorted(set(self.params) - set(REFINABLE))
        if unknown or not self.params:
            raise ValueError(f"params must be a non-empty subset of {REFINABLE}, got {self.params}")
        if self.ffd_reg < 0 or not self.sigma > 0:
            raise ValueError(f"ffd_reg must be >= 0 and sigma > 0, got {self.ffd_reg}, {self.sigma}")


@dataclass
class RefineResult:
    """Output of :func:`refine_by_reprojection`.

    Attributes:
        raw: refined raw outputs (detached; the keys of the input).
        pred: :func:`decode_outputs` of ``raw``.
        losses: ``(iterations + 1, N)`` per-object loss before each step and after the last.
    """

    raw: dict[str, Tensor]
    pred: dict[str, Tensor]
    losses: Tensor


def refine_by_reprojection(
    raw: Mapping[str, Tensor],
    box: Tensor,
    intrinsics: Tensor,
    crop_intrinsics: Tensor,
    mask: Tensor,
    ignore: Tensor | None = None,
    *,
    encoding: AttributeEncoding | None = None,
    templates: Tensor | None = None,
    bank: MeshBank | None = None,
    settings: RefineSettings | None = None,
    crop_box: Tensor | None = None,
    image_size: tuple[int, int] | None = None,
) -> RefineResult:
    """Refine predicted attributes of ``N`` objects so their silhouettes match their masks.

    Args:
        raw: :class:`~sdn3d.geometric.model.GeometricNet` outputs (not modified; any float dtype: the fit runs in
            float32).
        box: ``(N, 4)`` 2D boxes in image pixels; intrinsics: ``(N, 4)`` image ``(fx, fy, cx, cy)``.
        crop_intrinsics: ``(N, 4)`` intrinsics of each ``S x S`` crop.
        mask: ``(N, 1, S, S)`` visible instance masks in the crops.
        ignore: ``(N, 1, S, S)`` pixels that do not count (e.g. closer objects), or None.
        encoding: the parameterisation of ``raw`` (paper default).
        templates: ``(T,)`` mesh ids of the logits (``GeometricNet.templates``); the argmax mesh is used.
        bank: meshes (default: the 8 templates).
        settings: iterations, lr, parameters, FFD weight (default: paper).
        crop_box, image_size: the crops' windows ``(N, 4)`` and the image ``(W, H)``: when both are
            given, crop pixels outside the image are ignored too.
    """
    settings = settings or RefineSettings()
    encoding = encoding or AttributeEncoding()
    n, size = box.shape[0], mask.shape[-1]
    device = box.device
    bank = (bank or MeshBank.templates()).to(device)
    if mask.dim() != 4 or mask.shape[0] != n or mask.shape[1] != 1:
        raise ValueError(f"mask must have shape ({n}, 1, S, S), got {tuple(mask.shape)}")
    ign = torch.zeros_like(mask) if ignore is None else ignore.to(mask.dtype)
    if crop_box is not None and image_size is not None:
        ign = torch.maximum(ign, outside_image_mask(crop_box, image_size, size))
    K = as_intrinsics_matrix(intrinsics, n)
    crop_K = as_intrinsics_matrix(crop_intrinsics, n)
    sil_settings = SoftSilhouetteSettings((size, size), sigma=settings.sigma)
    # Float32 whatever the network ran in: Adam on half-precision leaves turns a zero gradient into 0 / 0 (its eps
    # underflows), and mixed-precision inference hands over half-precision outputs.
    fixed = {k: v.detach().float() if v.is_floating_point() else v.detach() for k, v in raw.items()}
    with torch.no_grad():
        template_ids = decode_outputs(fixed, box, K, encoding, templates)["template_id"]
    free = {k: fixed[k].clone().requires_grad_(True) for k in settings.params if k != "phi"}
    if "phi" in settings.params:
        free["phi_half"] = fixed["phi"][:, half_indices(device)].clone().requires_grad_(True)

    def current() -> dict[str, Tensor]:
        out = dict(fixed)
        out.update({k: v for k, v in free.items() if k != "phi_half"})
        if "phi_half" in free:
            out["phi"] = expand_half_ffd(free["phi_half"])
        return out

    def objective(values: dict[str, Tensor]) -> Tensor:
        pred = decode_outputs(values, box, K, encoding, templates)
        sil = render_silhouettes(bank, template_ids, pred["dims"], pred["ry"], pred["center"], values["phi"],
                                 crop_K, sil_settings)
        per_phi = values["phi"].square().flatten(1).mean(1)
        return reprojection_error(sil, mask, ign) + settings.ffd_reg * per_phi

    history = adam_fit(list(free.values()), lambda: objective(current()), settings.iterations, settings.lr)
    with torch.no_grad():
        refined = {k: v.detach() for k, v in current().items()}
        history.append(objective(refined))
        pred = decode_outputs(refined, box, K, encoding, templates)
    return RefineResult(raw=refined, pred=pred, losses=torch.stack(history))


def adam_fit(params: Sequence[Tensor], objective: Callable[[], Tensor], iterations: int, lr: float) -> list[Tensor]:
    """Minimise ``objective()`` over ``params`` with ``iterations`` Adam steps: the one pose-fitting loop.

    Used by :func:`refine_by_reprojection`, :func:`sdn3d.geometric.fit.fit_to_masks` and by ``sdn3d-render-demo``'s
    soft-silhouette fit. The update is :class:`torch.optim.Adam`'s with its defaults (betas 0.9 and 0.999, eps
    1e-8; ``tests/test_geometric_refine.py`` holds them equal), written out because the first ``torch.optim`` step
    of a process imports ``torch._dynamo``: 1.2-1.4 s of every fresh ``sdn3d-edit`` call that fits a box, on a
    2-core CPU.

    Args:
        params: leaf tensors with ``requires_grad`` (updated in place).
        objective: the loss at the current ``params``, a scalar or per-object ``(N,)``: objects are
            independent, so minimising the sum gives each one its own gradient.
        iterations, lr: Adam steps and learning rate.

    Returns:
        the detached loss before each step (gradients are enabled even when the caller runs under
        ``no_grad``, e.g. inference).
    """
    beta1, beta2, eps = 0.9, 0.999, 1e-8
    params = list(params)
    first = [torch.zeros_like(p) for p in params]
    second = [torch.zeros_like(p) for p in params]
    history = []
    for step in range(1, iterations + 1):
        with torch.enable_grad():
            loss = objective()
            grads = torch.autograd.grad(loss.sum(), params, allow_unused=True)
        history.append(loss.detach())
        step_size, root2 = lr / (1 - beta1**step), math.sqrt(1 - beta2**step)
        with torch.no_grad():
            for p, g, m, v in zip(params, grads, first, second, strict=True):
                if g is None:  # a parameter the loss does not reach stays where it is, as torch.optim's does
                    continue
                m.lerp_(g, 1 - beta1)
                v.mul_(beta2).addcmul_(g, g, value=1 - beta2)
                p.addcdiv_(m, (v.sqrt() / root2).add_(eps), value=-step_size)
    return history
