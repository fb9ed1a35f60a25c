"""The independent Deep3DBox baseline of Table 2 (``sdn3d-train branch=geometric ablation=deep3dbox``).

:class:`Deep3DBoxModule` is a :class:`~lightning_modules.geometric.GeometricModule` with its own network
(:class:`~sdn3d.geometric.deep3dbox_net.Deep3DBoxNet`: ResNet-18 on the same masked crops, MultiBin local
orientation, dimension residuals over the class mean), its own losses and its own decoding; it shares the
evaluation (``_eval_step``: silhouette, Table-2 metrics, image grids) through ``decode_batch``.

Loss (Mousavian et al. 2017): ``L = dims_weight * L_dims + L_conf + loc_weight * L_loc`` with ``L_dims`` the
mean squared error of the dimension residuals (metres^2) and ``L_conf``, ``L_loc`` the MultiBin terms
(:mod:`sdn3d.geometric.multibin`, 2 bins). Optimiser: the geometric branch's recipe (Adam at ``lr_pred`` for
``pred_epochs``, then ``lr_joint`` for ``joint_epochs``, step decay, weight decay), so the baseline trains on
the same budget and schedule as the 3D-SDN rows; the paper's SGD at 1e-4 (momentum 0.9) is far too slow
for the budgets here. Translation: the 2D-box fit (:func:`~sdn3d.geometric.deep3dbox.solve_translation`);
silhouette: the ``single_template`` mesh without FFD.

The class mean of the dimensions is computed when fitting starts from the training part's annotations (the
datamodule's ``datasets['train']``) and kept in the checkpoint (``net.mean_dims``); the box padding of the fit
(half a native pixel in working-size pixels, ``box_pad``) likewise, from the data.

Logged besides the geometric metrics: ``train|val|test/`` ``loss``, ``loss_conf``, ``loss_loc``,
``loss_dims``; ``val|test/box_fit_invalid`` (share of objects whose box fit had no candidate in front of the
camera) and ``val|test/box_fit_iou``.
"""

from __future__ import annotations

import inspect
import logging
from collections.abc import Mapping
from typing import Any

import torch
import torch.nn.functional as F
from torch import Tensor

from lightning_modules._base import plain_hparams
from lightning_modules.geometric import GeometricModule
from sdn3d.errors import UserInputError
from sdn3d.geometric.deep3dbox import border_sides
from sdn3d.geometric.deep3dbox_net import Deep3DBoxNet, decode_deep3dbox, local_yaw
from sdn3d.geometric.metrics import predicted_rotation
from sdn3d.geometric.multibin import bin_half_width, multibin_losses
from sdn3d.math3d.encodings import encode_yaw_quaternion
from sdn3d.math3d.ffd import FFD_NUM_HALF
from sdn3d.meshes.templates import TEMPLATE_NAMES

__all__ = ["Deep3DBoxModule", "Deep3DBoxSettingError", "object_dimensions", "native_pixel_pad"]

log = logging.getLogger(__name__)

#: Geometric-branch settings whose value the baseline fixes (it predicts a yaw, has no L_reproj and draws one
#: template without FFD); the ablation file sets them so, and any other value is refused.
FIXED_SETTINGS = {"rotation": "yaw_quaternion", "reproj": False, "single_cad": True}


class Deep3DBoxSettingError(UserInputError):
    """A geometric-branch setting the Deep3DBox baseline can not honour (the message names it)."""


def object_dimensions(dataset: Any) -> Tensor | None:
    """``(M, 3)`` float64 annotated ``(l, h, w)`` of a :class:`~sdn3d.data.datasets.GeometricDataset`'s objects
    (read from its records, no image decoded), or None for a dataset without ``records`` and ``objects``."""
    records, objects = getattr(dataset, "records", None), getattr(dataset, "objects", None)
    if records is None or objects is None or len(objects) == 0:
        return None
    return torch.tensor([records[ref.frame].objects[ref.object].dims for ref in objects], dtype=torch.float64)


def native_pixel_pad(dataset: Any) -> float | None:
    """Half a native pixel in working-size pixels (annotation boxes bound pixel centres), or None when the
    dataset does not say its working size and native camera."""
    records, size = getattr(dataset, "records", None), getattr(dataset, "image_size", None)
    if records and size is not None and getattr(records[0], "intrinsics", None) is not None:
        return 0.5 * float(size[0]) / float(records[0].intrinsics.width)
    return None


class Deep3DBoxModule(GeometricModule):
    """Deep3DBox (Mousavian et al. 2017) trained and evaluated like the geometric branch (see the module doc).

    Args:
        num_bins: MultiBin bins (paper: 2).
        overlap: how far each bin reaches past half its width, as a fraction (0.1: two bins overlap by 18 deg).
        dims_weight: ``alpha``, weight of the dimension loss.
        loc_weight: ``w``, weight of the MultiBin residual loss.
        truncation: fit only the 2D box sides not cut by the image border (needs ``image_size``); False is
            the plain baseline (all four sides).
        box_pad: pixels added on every side of the 2D box before the fit; None: half a native pixel, from the
            data.
        **geometric: :class:`GeometricModule`'s arguments, as ``conf/branch/geometric.yaml`` passes them. Used:
            ``pretrained``, ``single_template``, ``hidden``, ``scale_prior`` (the dimension prior until the data
            sets it), ``pred_epochs``, ``joint_epochs``, ``lr_pred``, ``lr_joint``, ``lr_decay_epochs``,
            ``lr_decay_rate``, ``weight_decay``, ``sigma``, ``image_size``, ``log_images``, ``nonfinite``,
            ``max_skipped_batches``. :data:`FIXED_SETTINGS` must keep their values; the rest (``distance``,
            ``regression``, the reprojection / REINFORCE / FFD weights) do not apply and are ignored.
    """

    def __init__(
        self,
        num_bins: int = 2,
        overlap: float = 0.1,
        dims_weight: float = 1.0,
        loc_weight: float = 1.0,
        truncation: bool = False,
        box_pad: float | None = None,
        **geometric: Any,
    ) -> None:
        accepted = set(inspect.signature(GeometricModule.__init__).parameters) - {"self"}
        unknown = sorted(set(geometric) - accepted)
        if unknown:
            raise TypeError(f"Deep3DBoxModule got unexpected keyword arguments {unknown}")
        for key, value in FIXED_SETTINGS.items():
            if geometric.get(key, value) != value:
                raise Deep3DBoxSettingError(
                    f"ablation.{key}={geometric[key]!r}: the Deep3DBox baseline needs {key}={value!r} (it predicts a "
                    "yaw, has no reprojection loss and draws one template without FFD)")
        super().__init__(**{**geometric, **FIXED_SETTINGS})
        bin_half_width(num_bins, overlap)  # validates both
        if dims_weight < 0 or loc_weight < 0 or (box_pad is not None and box_pad < 0):
            raise ValueError(f"dims_weight, loc_weight and box_pad must be non-negative, got {dims_weight}, "
                             f"{loc_weight}, {box_pad}")
        if truncation and self.image_size is None:
            raise ValueError("truncation=True needs image_size (the image border the box sides are tested against)")
        self.save_hyperparameters(plain_hparams({"num_bins": num_bins, "overlap": overlap, "dims_weight": dims_weight,
                                                 "loc_weight": loc_weight, "truncation": truncation,
                                                 "box_pad": box_pad}))
        hp = self.hparams
        self.net = Deep3DBoxNet(num_bins, int(hp.hidden), TEMPLATE_NAMES.index(str(hp.single_template)),
                                hp.pretrained, tuple(float(v) for v in hp.scale_prior))
        self.register_buffer("box_pad", torch.tensor(0.5 if box_pad is None else float(box_pad)))

    # -- data-derived buffers ---------------------------------------------------------------------------------
    def setup(self, stage: str) -> None:
        """Class-mean dimensions (fit) and the box padding from the datamodule's parts; a checkpoint being
        restored afterwards overrides both with its own (equal for the same data)."""
        datasets = getattr(self.trainer.datamodule, "datasets", None) if self._trainer is not None else None
        datasets = datasets if isinstance(datasets, Mapping) else {}
        if stage == "fit":
            dims = object_dimensions(datasets.get("train"))
            if dims is None:
                log.warning("Deep3DBoxModule: no geometric training dataset to take the class-mean dimensions from; "
                            "keeping %s", self.net.mean_dims.tolist())
            else:
                self.net.set_mean_dims(dims)
                log.info("Deep3DBox class-mean dimensions (l, h, w) from %d training objects: %s", dims.shape[0],
                         [round(v, 3) for v in self.net.mean_dims.tolist()])
        if self.hparams.box_pad is None:
            pads = [native_pixel_pad(datasets[p]) for p in ("train", "val", "test") if p in datasets]
            pads = [p for p in pads if p is not None]
            if pads:
                self.box_pad.fill_(pads[0])

    # -- losses -----------------------------------------------------------------------------------------------
    def _losses(self, out: Mapping[str, Tensor], batch: Mapping[str, Any]) -> dict[str, Tensor]:
        """``loss``, ``loss_conf``, ``loss_loc``, ``loss_dims`` (batch means) of the net's outputs ``out``."""
        hp = self.hparams
        alpha = local_yaw(batch["ry"], batch["box"], batch["intrinsics"])
        multibin = multibin_losses(out["conf_logits"], out["residual"], alpha, float(hp.overlap))
        dims_target = batch["dims"].to(out["dims_residual"].dtype) - self.net.mean_dims
        terms = {"loss_conf": multibin["conf"].mean(), "loss_loc": multibin["loc"].mean(),
                 "loss_dims": (out["dims_residual"] - dims_target).pow(2).mean()}
        terms["loss"] = hp.dims_weight * terms["loss_dims"] + terms["loss_conf"] + hp.loc_weight * terms["loss_loc"]
        return terms

    def training_step(self, batch: dict[str, Any], batch_idx: int) -> Tensor | None:
        terms = self._losses(self.net(batch["crop"]), batch)
        if not self.guard_loss(terms["loss"]):
            return None
        n = batch["crop"].shape[0]
        self.log("train/loss", terms["loss"], on_step=True, on_epoch=True, prog_bar=True, batch_size=n, sync_dist=True)
        for key in ("loss_conf", "loss_loc", "loss_dims"):
            self.log(f"train/{key}", terms[key].detach(), on_step=False, on_epoch=True, batch_size=n, sync_dist=True)
        return terms["loss"]

    # -- predictions ------------------------------------------------------------------------------------------
    def _predictions(self, out: Mapping[str, Tensor], box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        """The ``decode_batch`` dict from the net's outputs for boxes ``(N, 4)`` and intrinsics ``(N, 4)``."""
        n = box.shape[0]
        sides = border_sides(box, self.image_size) if self.hparams.truncation else None
        pred = decode_deep3dbox(out, self.net.mean_dims, box, intrinsics, float(self.box_pad), sides)
        template = self.net.templates.expand(n)
        pred["template_id"] = template
        pred["template_probs"] = F.one_hot(template, len(TEMPLATE_NAMES)).to(pred["dims"].dtype)
        pred["phi"] = pred["dims"].new_zeros(n, 2 * FFD_NUM_HALF, 3)
        pred["rot"] = predicted_rotation(encode_yaw_quaternion(pred["ry"]), pred["ry"], "yaw_quaternion")
        return pred

    def forward(self, crop: Tensor, box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        """Decoded predictions (:meth:`decode_batch`'s dict) for crops ``(N, 3, S, S)``, boxes and intrinsics."""
        return self._predictions(self.net(crop), box, intrinsics)

    @torch.no_grad()
    def decode_batch(self, stage: str, batch: Mapping[str, Any]) -> dict[str, Tensor]:
        """Deep3DBox's own per-object predictions (the :class:`GeometricModule` contract: ``template_id (N,)``,
        ``template_probs (N, 8)`` one-hot, ``phi (N, 64, 3)`` zeros, ``dims (N, 3)``, ``ry (N,)``, ``center (N, 3)``
        box centre, ``location (N, 3)``, ``rot``); logs its losses and the box fit's quality."""
        out = self.net(batch["crop"])
        n = batch["crop"].shape[0]
        for key, value in self._losses(out, batch).items():
            self.log(f"{stage}/{key}", value, on_step=False, on_epoch=True, batch_size=n, sync_dist=True)
        pred = self._predictions(out, batch["box"], batch["intrinsics"])
        fit = {"box_fit_invalid": (~pred["fit_valid"]).float().mean(), "box_fit_iou": pred["fit_iou"].float().mean()}
        for key, value in fit.items():
            self.log(f"{stage}/{key}", value, on_step=False, on_epoch=True, batch_size=n, sync_dist=True)
        return pred

    @torch.no_grad()
    def predict_step(self, batch: dict[str, Any], batch_idx: int) -> dict[str, Tensor]:
        return self(batch["crop"], batch["box"], batch["intrinsics"])
