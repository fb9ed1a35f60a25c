"""The geometric branch at inference: :class:`GeometricPredictor` loads a Lightning checkpoint of
``lightning_modules.GeometricModule`` or its inference export (:mod:`sdn3d.inference_export`) without
importing Lightning and predicts object attributes (decoded by :func:`sdn3d.geometric.decode.decode_outputs`),
optionally refined by reprojection.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.geometric.decode import decode_outputs
from sdn3d.geometric.lamps import LampCue, border_side, face_by_reading, read_lamps
from sdn3d.geometric.losses import render_silhouettes
from sdn3d.geometric.model import GeometricNet, ray_angle
from sdn3d.geometric.refine import RefineSettings, refine_by_reprojection
from sdn3d.inference_export import BranchWeights, load_branch_weights, module_with_weights
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import TEMPLATE_NAMES

__all__ = [
    "net_kwargs_from_hparams",
    "GeometricPredictor",
]


#: :meth:`GeometricPredictor.predict` runs the backbone on at least this many rows and the fully connected layers on
#: blocks of exactly this many, a short batch or block padded with copies of its first row: then each object's outputs
#: are the same bits whatever else is predicted with it. PyTorch's CPU convolutions sum in another order for batches
#: under 4 rows: on the real frame in ``tests/data`` the red car's prediction moved in its 7th digit when the black car
#: was boxed too, and the fit's search (``sdn3d.geometric.fit``) then chose another template for it
#: (docs/results/2026-11-29_cpu/session17/lead/rows/). Its matrix products sum in another order for other numbers of
#: rows: on tuning tree 11's frame 0001/clone/00034 three of seven distance predictions moved in their last bits from a
#: batch of 8 to one of 7, and a fit started one bit away ended 0.32 m away (docs/results/2026-12-01_cpu/session29/
#: joincost29).
MIN_NET_ROWS = 4


# Constructor arguments of GeometricNet read from the module's hyper-parameters.
_NET_ARGS = ("rotation", "hidden", "scale_prior", "yaw_bins", "yaw_overlap")


def net_kwargs_from_hparams(hparams: Mapping[str, Any]) -> dict[str, Any]:
    """``GeometricNet`` arguments from ``GeometricModule`` hyper-parameters (single_cad, templates, ...)."""
    kwargs = {k: hparams[k] for k in _NET_ARGS if k in hparams and hparams[k] is not None}
    if "scale_prior" in kwargs:
        kwargs["scale_prior"] = tuple(float(v) for v in kwargs["scale_prior"])
    if hparams.get("single_cad", False):
        kwargs["templates"] = (TEMPLATE_NAMES.index(str(hparams.get("single_template", TEMPLATE_NAMES[0]))),)
        kwargs["ffd"] = False
    return kwargs


class GeometricPredictor:
    """Inference wrapper: a :class:`GeometricNet` in eval mode plus its target encoding.

    Args:
        net: the network (moved to eval mode).
        encoding: the parameterisation it was trained with.
        lamp_cue: where :meth:`predict` is given the masks, each predicted yaw is turned end for end where the red
            tail lights in the crop clearly say the other end is seen (:mod:`sdn3d.geometric.lamps`, issue 40);
            None: the net's yaw as it is.
    """

    def __init__(self, net: GeometricNet, encoding: AttributeEncoding | None = None,
                 lamp_cue: LampCue | None = LampCue()) -> None:
        self.net = net.eval()
        self.lamp_cue = lamp_cue
        self.bank: MeshBank | None = None  # built on first use
        self.encoding = encoding or AttributeEncoding(rotation=net.rotation)
        if self.encoding.rotation != net.rotation:
            raise ValueError(f"encoding.rotation={self.encoding.rotation!r} does not match the net's {net.rotation!r}")

    @classmethod
    def from_checkpoint(cls, path: str | Path, map_location: str | torch.device = "cpu") -> GeometricPredictor:
        """Load a ``GeometricModule`` Lightning checkpoint or its inference export (``weights_only=True``).

        Uses its ``hyper_parameters`` (rotation, distance, single_cad, ...) to rebuild the net and
        the ``net.``-prefixed entries of its ``state_dict``.
        """
        return cls.from_weights(load_branch_weights(path, "geometric", map_location), map_location)

    @classmethod
    def from_weights(cls, weights: BranchWeights, map_location: str | torch.device = "cpu") -> GeometricPredictor:
        """The predictor of loaded geometric-branch weights (:func:`~sdn3d.inference_export.load_branch_weights`;
        the network takes over their tensors)."""
        hparams = dict(weights.hyper_parameters)
        if "num_bins" in hparams:  # lightning_modules.Deep3DBoxModule's MultiBin head
            raise UserInputError(f"{str(weights.path)!r} is a Deep3DBox baseline checkpoint (ablation=deep3dbox): it "
                                 f"scores Table 2 only and cannot de-render; use a geometric run of another ablation")
        kwargs = net_kwargs_from_hparams(hparams)
        state = {k[len("net."):]: v for k, v in weights.state_dict.items() if k.startswith("net.")}
        if not state:
            raise UserInputError(f"{str(weights.path)!r} has no 'net.' weights: not a GeometricModule checkpoint")
        net = module_with_weights(lambda: GeometricNet(**kwargs), state, weights.path)
        encoding = AttributeEncoding(hparams.get("rotation", "yaw_quaternion"), hparams.get("distance", "log_tau"))
        return cls(net.to(map_location), encoding)

    @property
    def device(self) -> torch.device:
        return next(self.net.parameters()).device

    def _net_rows(self, crop: Tensor, box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        """The net's raw outputs for ``N`` rows, each the same whatever the other rows are (:data:`MIN_NET_ROWS`):
        the backbone on at least that many rows, the fully connected layers on blocks of exactly that many (rows
        padded with copies of the first)."""
        n = crop.shape[0]
        if n == 0:
            return self.net(crop, box, intrinsics)
        feats = self.net.features(torch.cat([crop, crop[[0] * (max(n, MIN_NET_ROWS) - n)]]))[:n]
        pad = [0] * (-n % MIN_NET_ROWS)
        feats, box, intrinsics = (torch.cat([t, t[pad]]) for t in (feats, box, intrinsics))
        blocks = [self.net.decode(*(t[i:i + MIN_NET_ROWS] for t in (feats, box, intrinsics)))
                  for i in range(0, len(feats), MIN_NET_ROWS)]
        return {k: torch.cat([b[k] for b in blocks])[:n] for k in blocks[0]}

    @torch.no_grad()
    def predict(
        self,
        crop: Tensor,
        mask: Tensor | None,
        box: Tensor,
        intrinsics: Tensor,
        crop_intrinsics: Tensor | None = None,
        ignore: Tensor | None = None,
        refine: RefineSettings | None = None,
        lamp_mask: Tensor | None = None,
        tail_mask: Tensor | None = None,
        image_width: int | None = None,
    ) -> dict[str, Tensor]:
        """3D attributes of ``N`` objects (see :func:`decode_outputs` for the keys).

        Args:
            crop: ``(N, 3, S, S)`` object crops in ``[0, 1]`` (as :class:`GeometricDataset` makes them).
            mask: ``(N, 1, S, S)`` visible masks; when given the crop is masked with it (a no-op
                for already masked crops). None: the crop is used as is.
            box: ``(N, 4)`` 2D boxes in image pixels.
            intrinsics: ``(N, 4)`` image ``(fx, fy, cx, cy)``.
            crop_intrinsics: ``(N, 4)`` crop intrinsics; when given, ``silhouette (N, S, S)`` of the
                predicted (argmax) mesh is added, rendered into the crop (soft, default sigma).
            ignore: ``(N, 1, S, S)`` crop pixels the refinement does not count (closer objects).
            refine: when given (needs ``mask`` and ``crop_intrinsics``), the predictions are refined
                by :func:`~sdn3d.geometric.refine.refine_by_reprojection` against ``mask`` (Cityscapes).
            lamp_mask: ``(N, 1, S, S)`` the crop pixels the lamp cue reads (default: ``mask``); e.g. only those
                surely on the object where the mask is coarser than the crop's pixels
                (:func:`sdn3d.derender.derender` with a photo).
            tail_mask: ``(N, 1, S, S)`` where ``lamp_mask`` shows no usable red lamps (none, or too spread or too
                many to read), the crop pixels the red tail-lamp test reads instead, from ``crop`` as given (not
                masked with ``mask``): e.g. a semantic mask and the band under it, where the lamps lie when the mask
                stopped above them (:func:`sdn3d.derender.derender`). A mask that shows usable red lamps is read as
                before (a wider reading adds rows of other red: its lamps then fail the one-band test). The
                headlights' test of red bodies keeps ``lamp_mask`` (a band's road reads near-white through rain).
            image_width: the image's width in pixels: with it the lamp cue knows the boxes that the left or right
                border cuts (:func:`~sdn3d.geometric.lamps.border_side`), whose end facing the camera may lie
                outside the image (an absence of lamps then gives way to the traffic's side); None: none is cut.

        With ``mask`` and :attr:`lamp_cue`, the yaw is then turned end for end where the lamps disagree with it; the
        output then also holds what the appearance says of any yaw (:func:`~sdn3d.geometric.facing.facing_belief`):
        ``net_ry (N,)`` the net's yaw before the lamps, ``ray (N,)`` the ray angle of each box, and the lamps'
        reading ``lamp_present``, ``lamp_usable`` (``(N,)`` bool) and ``lamp_offset (N,)``
        (:func:`~sdn3d.geometric.lamps.red_lamps`), and of a red body's headlights ``front_present``,
        ``front_usable``, ``front_offset`` (:func:`~sdn3d.geometric.lamps.white_lamps`), and with ``image_width``
        ``border_side (N,)`` (:func:`~sdn3d.geometric.lamps.border_side`).
        """

        device = self.device
        crop, box, intrinsics = crop.to(device), box.to(device), intrinsics.to(device)
        given = crop  # the tail-lamp test may read past the mask
        if mask is not None:
            crop = crop * mask.to(device)
        raw = self._net_rows(crop, box, intrinsics)
        if (refine is not None or crop_intrinsics is not None) and self.bank is None:
            self.bank = MeshBank.templates()  # only silhouettes need meshes
        bank = None if self.bank is None else self.bank.to(device)
        if refine is not None:
            if mask is None or crop_intrinsics is None:
                raise ValueError("refine needs mask and crop_intrinsics")
            raw = refine_by_reprojection(
                raw, box, intrinsics, crop_intrinsics.to(device), mask.to(device),
                None if ignore is None else ignore.to(device), encoding=self.encoding,
                templates=self.net.templates, bank=bank, settings=refine,
            ).raw
        out = decode_outputs(raw, box, intrinsics, self.encoding, self.net.templates)
        if self.lamp_cue is not None and mask is not None:
            ray = ray_angle(box, intrinsics)
            lamps = mask.to(device) if lamp_mask is None else lamp_mask.to(device)
            red, white = read_lamps(crop, lamps, self.lamp_cue, given,
                                    None if tail_mask is None else tail_mask.to(device))
            out.update(net_ry=out["ry"], ray=ray, lamp_present=red[0], lamp_usable=red[1], lamp_offset=red[2],
                       front_present=white[0], front_usable=white[1], front_offset=white[2])
            border = None if image_width is None else border_side(box, image_width)
            if border is not None:
                out["border_side"] = border
            out["ry"] = face_by_reading(out["ry"], ray, red, white, self.lamp_cue, border)
        if crop_intrinsics is not None:
            out["silhouette"] = render_silhouettes(
                bank, out["template_id"], out["dims"], out["ry"], out["center"],
                out["phi"], crop_intrinsics.to(device), crop.shape[-1],
            )
        return out
