"""Geometric branch training (``sdn3d-train branch=geometric``): 3D-SDN Sec. 3.1 in two stages.

Stage 1 (``pred_epochs``): ``L_pred`` only, Adam at ``lr_pred`` (paper 1e-3).
Stage 2 (``joint_epochs``): ``L_pred + reproj_weight * L_reproj`` (paper 0.1) plus REINFORCE for the
mesh choice and ``ffd_reg * mean(phi^2)``, at ``lr_joint`` (paper 1e-4). The paper trains 256 epochs
with L_pred, then 64 with L_reproj and REINFORCE; the released code runs 256 + 256 (this module's
defaults). The loss switches at the
epoch boundary; the learning rate comes from an epoch-wise ``LambdaLR`` (stage factor times
``lr_decay_rate ** (epochs into the stage // lr_decay_epochs)``), so a resumed run gets the same
rates. Adam's moments are kept across the boundary (restarting them would make a resume from a
mid-epoch checkpoint differ from an uninterrupted run). The REINFORCE baseline is a buffer.

Ablations (``conf/ablation``): ``reproj=False`` keeps stage 2 at ``L_pred`` only; ``single_cad``
uses one template and no FFD; ``rotation`` / ``distance`` pick the target parameterisation.

Evaluation works from :meth:`GeometricModule.decode_batch`'s per-object predictions alone (a baseline
module overrides that method), with :mod:`sdn3d.geometric.metrics`: the paper's reprojection error
(hard silhouette, mismatching image pixels over the ``W x H`` frame; needs ``image_size``) beside the
soft crop mean, and at test the mesh choice against its floors: the 8 templates are rendered at the
predicted pose (selection regret) and at the true pose (identifiability ceiling); the majority floor
uses the templates of the training part, counted when fitting starts (buffer ``train_template_counts``).

Logged: ``train/loss``, ``train/loss_pred`` and its terms, ``train/loss_reproj``, ``train/reinforce``,
``train/baseline``, ``train/template_entropy``, ``train/stage``; ``val|test/`` ``loss_pred``,
``orientation_similarity``, ``distance_error``, ``scale_error``, ``reprojection_error_image``,
``reprojection_error_crop_soft``, ``mesh_accuracy``, ``mesh_uniform_floor``, ``mesh_majority_floor``
(mesh figures: objects with a known template only) and ``template_prob/<name>``; ``test/`` also
``selection_regret`` and ``mesh_identifiability_ceiling``; TensorBoard grids ``val|test/silhouettes``
(crop | mask | rendered soft silhouette | overlay) and a histogram of the selected templates.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

import torch
from torch import Tensor

from lightning_modules._base import BranchModule, plain_hparams
from sdn3d.data.datasets.geometric import template_id
from sdn3d.geometric import (
    BASELINES,
    PRED_KEYS,
    GeometricNet,
    MovingAverageBaseline,
    expected_reward_loss,
    ffd_regularizer,
    leave_one_out_baseline,
    net_kwargs_from_hparams,
    outside_image_mask,
    prediction_loss,
    prediction_losses,
    refine_by_reprojection,
    reinforce_loss,
    render_silhouettes,
    reprojection_error,
    sample_templates,
)
from sdn3d.geometric.decode import decode_outputs
from sdn3d.geometric.metrics import (
    GeometricMetrics,
    image_reprojection_error,
    predicted_rotation,
    template_reprojection_errors,
    window_silhouettes,
)
from sdn3d.geometric.refine import RefineSettings
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.nets.weights import load_pretrained
from sdn3d.render.settings import SoftSilhouetteSettings
from sdn3d.render.silhouette import SILHOUETTES

__all__ = ["GeometricModule", "lr_factor"]

log = logging.getLogger(__name__)


def lr_factor(epoch: int, pred_epochs: int, lr_pred: float, lr_joint: float, decay_epochs: int,
              decay_rate: float) -> float:
    """Multiplier of ``lr_pred`` at ``epoch``: stage rate times step decay within the stage."""
    stage_epoch = epoch if epoch < pred_epochs else epoch - pred_epochs
    base = 1.0 if epoch < pred_epochs else lr_joint / lr_pred
    return base * (decay_rate ** (stage_epoch // decay_epochs) if decay_epochs > 0 else 1.0)


class GeometricModule(BranchModule):
    """ResNet-18 de-renderer of object geometry (see the module doc for the schedule).

    Args:
        pretrained: optional local ImageNet ResNet-18 weights (torchvision names); None: random init.
        rotation, distance: target parameterisation (``${ablation.rotation}``, ``${ablation.distance}``); rotation
            ``'multibin'``: MultiBin over the local orientation (issue 40), the paper's ``'yaw_quaternion'`` the
            Table-2 rows.
        yaw_bins, yaw_overlap: the MultiBin head's bins and overlap (``rotation='multibin'`` only).
        single_cad: one template (``single_template``) and no FFD (ablation).
        reproj: use L_reproj + REINFORCE in stage 2 (ablation ``no_reproj``: False).
        pred_epochs, joint_epochs: stage lengths (paper: 256 + 64; released code and defaults: 256 + 256).
        lr_pred, lr_joint, lr_decay_epochs, lr_decay_rate, weight_decay: Adam and its step schedule
            (released code: x0.5 every 16 epochs, weight decay 1e-3).
        regression: ``'l2'`` (paper) or ``'smooth_l1'`` for the scale / offset / distance terms.
        reproj_weight: weight of L_reproj (paper 0.1).
        reinforce_weight: weight of the REINFORCE surrogate.
        num_samples: templates sampled per object for REINFORCE (each rendered).
        baseline: ``'moving_average'`` (buffer), ``'leave_one_out'`` or ``'exact'`` (every template rendered for
            every object, the exact expected-reward gradient; ``num_samples`` unused); baseline_momentum: the
            moving average's momentum.
        reproj_silhouette: the silhouette of L_reproj and the REINFORCE rewards: ``'soft'`` (SoftRas; its L1
            optimum is a shrunken car) or ``'straight_through'`` (the hard silhouette with the soft one's
            gradient: L_reproj is then the hard mismatch, unbiased; :mod:`sdn3d.render.silhouette`).
        test_refine: at test, also score the predictions after the paper's per-image fit (Adam 0.03 x 16 on
            L_reproj, :class:`~sdn3d.geometric.refine.RefineSettings`): ``test/refined/...``.
        ffd_reg: weight of ``mean(phi^2)`` in stage 2 (released code: 10).
        sigma: soft-silhouette softness in pixels^2.
        hidden, scale_prior: MLP width and initial ``(l, h, w)`` of the net.
        image_size: working image ``(W, H)`` (``${data.image_size}``): crop pixels outside it are
            ignored by L_reproj and the soft crop figure, and it is the frame of the paper's reprojection
            error (``reprojection_error_image``); None: no such pixels are ignored and that error is not logged.
        log_images: crops per TensorBoard grid (first validation / test batch); 0 = none.
        nonfinite, max_skipped_batches: non-finite loss policy (:class:`BranchModule`; ``fault.nonfinite``,
            ``fault.max_skipped_batches``); not hyperparameters.
    """

    def __init__(
        self,
        pretrained: str | None = None,
        rotation: str = "yaw_quaternion",
        distance: str = "log_tau",
        single_cad: bool = False,
        single_template: str = "sedan",
        reproj: bool = True,
        pred_epochs: int = 256,
        joint_epochs: int = 256,
        lr_pred: float = 1e-3,
        lr_joint: float = 1e-4,
        lr_decay_epochs: int = 16,
        lr_decay_rate: float = 0.5,
        weight_decay: float = 1e-3,
        regression: str = "l2",
        reproj_weight: float = 0.1,
        reinforce_weight: float = 1.0,
        num_samples: int = 4,
        baseline: str = "moving_average",
        baseline_momentum: float = 0.9,
        reproj_silhouette: str = "soft",
        test_refine: bool = False,
        ffd_reg: float = 10.0,
        sigma: float = 0.25,
        hidden: int = 256,
        scale_prior: Sequence[float] = (4.0, 1.6, 1.8),
        yaw_bins: int = 4,
        yaw_overlap: float = 0.1,
        image_size: Sequence[int] | None = None,
        log_images: int = 8,
        nonfinite: str = "stop",
        max_skipped_batches: int = 10,
    ) -> None:
        super().__init__(nonfinite=nonfinite, max_skipped_batches=max_skipped_batches)
        args = {k: plain_hparams(v) for k, v in locals().items()
                if k not in ("self", "__class__", "nonfinite", "max_skipped_batches")}
        self.save_hyperparameters(args)
        if pred_epochs < 0 or joint_epochs < 0 or lr_pred <= 0 or lr_joint <= 0:
            raise ValueError(f"need pred_epochs, joint_epochs >= 0 and lr_pred, lr_joint > 0; got {pred_epochs}, "
                             f"{joint_epochs}, {lr_pred}, {lr_joint}")
        if baseline not in BASELINES:
            raise ValueError(f"baseline must be one of {BASELINES}, got {baseline!r}")
        if reproj_silhouette not in SILHOUETTES:
            raise ValueError(f"reproj_silhouette must be one of {SILHOUETTES}, got {reproj_silhouette!r}")
        if num_samples < 1 or (baseline == "leave_one_out" and num_samples < 2):
            raise ValueError(f"num_samples must be >= 1 (>= 2 for leave_one_out), got {num_samples}")
        if single_cad and single_template not in TEMPLATE_NAMES:
            raise ValueError(f"single_template must be one of {TEMPLATE_NAMES}, got {single_template!r}")
        self.encoding = AttributeEncoding(rotation, distance)
        self.net = GeometricNet(**net_kwargs_from_hparams(self.hparams))
        load_pretrained(self.net.backbone, pretrained, what="ResNet-18 backbone", ignore_prefixes=("fc.",))
        self.baseline = MovingAverageBaseline(baseline_momentum)
        self.metrics = torch.nn.ModuleDict({stage: GeometricMetrics() for stage in ("val", "test", "test_refined")})
        self.image_size = None if image_size is None else tuple(int(v) for v in args["image_size"])
        self._bank = MeshBank.templates()
        self._template_stats: dict[str, list[Tensor]] = {}
        self._decomposition: dict[str, list[Tensor]] = {}
        # True templates of the training part (the majority floor of the mesh accuracy; on_fit_start), checkpointed.
        self.register_buffer("train_template_counts", torch.zeros(len(TEMPLATE_NAMES), dtype=torch.long))

    # -- helpers ----------------------------------------------------------------------------------------------
    def stage(self, epoch: int | None = None) -> str:
        """``'pred'`` during the first ``pred_epochs`` epochs, then ``'joint'``."""
        return "pred" if (self.current_epoch if epoch is None else epoch) < self.hparams.pred_epochs else "joint"

    def bank(self, device: torch.device) -> MeshBank:
        if self._bank.device != device:
            self._bank.to(device)
        return self._bank

    def soft_settings(self, size: int) -> SoftSilhouetteSettings:
        """The soft silhouette of L_reproj for ``size x size`` crops."""
        return SoftSilhouetteSettings((size, size), sigma=self.hparams.sigma)

    def forward(self, crop: Tensor, box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        return self.net(crop, box, intrinsics)

    def _ignore(self, batch: Mapping[str, Any]) -> Tensor:
        """Crop pixels L_reproj does not count: closer objects, and outside the image when its size is known."""
        ignore = batch["ignore"]
        if self.image_size is not None:
            ignore = torch.maximum(ignore, outside_image_mask(batch["crop_box"], self.image_size, ignore.shape[-1]))
        return ignore

    def _render(self, pred: Mapping[str, Tensor], objects: Tensor, template_ids: Tensor, crop_intrinsics: Tensor,
                size: int) -> Tensor:
        """Silhouettes ``(P, S, S)`` of ``objects (P,)`` (batch indices, may repeat), meshes ``template_ids (P,)``."""
        def pick(t: Tensor) -> Tensor:
            return t.index_select(0, objects)

        phi = pick(pred["phi"]) if self.net.use_ffd else None
        return render_silhouettes(self.bank(template_ids.device), template_ids, pick(pred["dims"]), pick(pred["ry"]),
                                  pick(pred["center"]), phi, pick(crop_intrinsics), self.soft_settings(size),
                                  self.hparams.get("reproj_silhouette", "soft"))

    def _reprojection_terms(self, raw: dict[str, Tensor], batch: Mapping[str, Any]) -> dict[str, Tensor]:
        """L_reproj (mean over objects and samples), the REINFORCE surrogate and diagnostics."""
        hp = self.hparams
        pred = decode_outputs(raw, batch["box"], batch["intrinsics"], self.encoding, self.net.templates)
        n, size = batch["crop"].shape[0], batch["crop"].shape[-1]
        multi = self.net.num_templates > 1
        exact = multi and hp.baseline == "exact"
        k = self.net.num_templates if exact else int(hp.num_samples) if multi else 1
        if exact:
            ids = self.net.templates.expand(n, k)
        elif multi:
            idx, log_probs = sample_templates(raw["template_logits"], k)
            ids = self.net.templates[idx]
        else:
            ids = self.net.templates.expand(n, 1)
        # Render each distinct (object, template) pair once: samples of a peaked distribution coincide.
        num_meshes = len(self._bank)
        pairs = torch.arange(n, device=ids.device).repeat_interleave(k) * num_meshes + ids.reshape(-1)
        unique, inverse = torch.unique(pairs, return_inverse=True)
        objects = unique // num_meshes
        sil = self._render(pred, objects, unique % num_meshes, batch["crop_intrinsics"], size)
        err = reprojection_error(sil, batch["mask"].index_select(0, objects),
                                 self._ignore(batch).index_select(0, objects))[inverse].view(n, k)
        if exact:  # the pose's L_reproj is the expected one under the (constant) template distribution
            probs = raw["template_logits"].softmax(1)
            terms = {"loss_reproj": (probs.detach() * err).sum(1).mean(),
                     "reinforce": expected_reward_loss(raw["template_logits"], -err.detach())}
            terms["baseline"] = -(probs.detach() * err.detach()).sum(1).mean()  # the expected reward
            terms["template_entropy"] = -(probs * probs.clamp_min(1e-12).log()).sum(1).mean()
            return terms
        terms = {"loss_reproj": err.mean()}
        if multi:
            rewards = -err.detach()
            if hp.baseline == "leave_one_out":
                b = leave_one_out_baseline(rewards)
            else:
                b = self.baseline().to(rewards.dtype)
                self.baseline.update(rewards)
            terms["reinforce"] = reinforce_loss(log_probs, rewards, b)
            terms["baseline"] = self.baseline.value if hp.baseline == "moving_average" else b.mean()
            probs = raw["template_logits"].softmax(1)
            terms["template_entropy"] = -(probs * probs.clamp_min(1e-12).log()).sum(1).mean()
        return terms

    # -- training ---------------------------------------------------------------------------------------------
    def training_step(self, batch: dict[str, Any], batch_idx: int) -> Tensor | None:
        hp = self.hparams
        raw = self.net(batch["crop"], batch["box"], batch["intrinsics"])
        n = batch["crop"].shape[0]
        if not all(bool(torch.isfinite(v).all()) for v in raw.values()):
            # decode_outputs rejects non-finite values: the guard applies the NaN policy (stop / skip).
            self.guard_loss(raw["log_scale"].sum() * float("nan"))
            return None
        terms = prediction_losses(raw, batch["targets"], self.encoding.rotation, hp.regression, self.net.yaw_overlap)
        loss_pred = prediction_loss(terms)
        loss = loss_pred
        joint = self.stage() == "joint"
        logs = {"loss_pred": loss_pred, **{f"loss_{k}": terms[k].mean() for k in PRED_KEYS},
                "stage": loss_pred.new_tensor(float(joint))}
        if joint and hp.reproj:
            rep = self._reprojection_terms(raw, batch)
            loss = loss + hp.reproj_weight * rep["loss_reproj"]
            logs["loss_reproj"] = rep["loss_reproj"]
            if "reinforce" in rep:
                loss = loss + hp.reinforce_weight * rep["reinforce"]
                logs.update({k: rep[k] for k in ("reinforce", "baseline", "template_entropy")})
            if self.net.use_ffd and hp.ffd_reg > 0:
                logs["ffd_reg"] = ffd_regularizer(raw["phi"])
                loss = loss + hp.ffd_reg * logs["ffd_reg"]
        if not self.guard_loss(loss):
            return None
        self.log("train/loss", loss, on_step=True, on_epoch=True, prog_bar=True, batch_size=n, sync_dist=True)
        for key, value in logs.items():
            self.log(f"train/{key}", value.detach().float(), on_step=False, on_epoch=True, batch_size=n,
                     sync_dist=True)
        return loss

    def configure_optimizers(self):
        hp = self.hparams
        optimizer = torch.optim.Adam(self.net.parameters(), lr=hp.lr_pred, weight_decay=hp.weight_decay)
        args = (int(hp.pred_epochs), float(hp.lr_pred), float(hp.lr_joint), int(hp.lr_decay_epochs),
                float(hp.lr_decay_rate))

        def factor(epoch: int) -> float:  # a plain function: LambdaLR's state_dict skips it
            return lr_factor(epoch, *args)

        scheduler = torch.optim.lr_scheduler.LambdaLR(optimizer, factor)
        return {"optimizer": optimizer, "lr_scheduler": {"scheduler": scheduler, "interval": "epoch"}}

    def on_fit_start(self) -> None:
        total = int(self.hparams.pred_epochs) + int(self.hparams.joint_epochs)
        if self.trainer.max_epochs is not None and self.trainer.max_epochs not in (-1, total):
            log.warning("trainer.max_epochs=%s but pred_epochs + joint_epochs = %d: the joint stage %s",
                        self.trainer.max_epochs, total,
                        "is cut short" if self.trainer.max_epochs < total else "runs longer")
        self._count_training_templates()

    def _count_training_templates(self) -> None:
        """The true templates of the training part's objects (the majority floor of the mesh accuracy), from the
        datamodule's records (no image is read); kept in the checkpoint for a later test."""
        datasets = getattr(self.trainer.datamodule, "datasets", None)
        train = datasets.get("train") if isinstance(datasets, Mapping) else None
        records, objects = getattr(train, "records", None), getattr(train, "objects", None)
        if records is None or objects is None:
            log.warning("no geometric training dataset in the datamodule: the mesh accuracy's majority floor "
                        "(test/mesh_majority_floor) is not computed")
            return
        ids = torch.tensor([template_id(records[ref.frame].objects[ref.object].model) for ref in objects],
                           dtype=torch.long)
        counts = torch.bincount(ids[ids >= 0], minlength=len(TEMPLATE_NAMES))
        self.train_template_counts.copy_(counts.to(self.train_template_counts.device))

    def on_save_checkpoint(self, checkpoint: dict[str, Any]) -> None:
        super().on_save_checkpoint(checkpoint)
        if "hyper_parameters" in checkpoint:
            checkpoint["hyper_parameters"] = plain_hparams(checkpoint["hyper_parameters"])

    # -- evaluation -------------------------------------------------------------------------------------------
    @torch.no_grad()
    def decode_batch(self, stage: str, batch: Mapping[str, Any]) -> dict[str, Tensor]:
        """Per-object predictions of one evaluation batch, decoded (the seam a baseline module overrides).

        Returns the :func:`~sdn3d.geometric.decode.decode_outputs` dict (``template_id (N,)``,
        ``template_probs (N, T)``, ``phi (N, 64, 3)``, ``dims (N, 3)``, ``ry (N,)``, ``center (N, 3)``, ...)
        plus ``rot (N, 4)`` for the orientation metric and ``raw``, the net's outputs (the test-time fit starts
        from them; a baseline's dict without them is not refined); logs ``<stage>/loss_pred``.
        """
        raw = self.net(batch["crop"], batch["box"], batch["intrinsics"])
        terms = prediction_losses(raw, batch["targets"], self.encoding.rotation, self.hparams.regression,
                                  self.net.yaw_overlap)
        self.log(f"{stage}/loss_pred", prediction_loss(terms), on_step=False, on_epoch=True,
                 batch_size=batch["crop"].shape[0], sync_dist=True)
        pred = decode_outputs(raw, batch["box"], batch["intrinsics"], self.encoding, self.net.templates)
        pred["rot"] = predicted_rotation(raw["rotation"], pred["ry"], self.encoding.rotation)
        pred["raw"] = raw
        return pred

    @torch.no_grad()
    def _eval_step(self, stage: str, batch: dict[str, Any], batch_idx: int) -> None:
        """Metrics from :meth:`decode_batch`'s dict alone (``template_id``, ``template_probs``, ``phi``, ``dims``,
        ``ry``, ``center``, ``rot``): a baseline overriding it is scored by the same code."""
        size = batch["crop"].shape[-1]
        pred = self.decode_batch(stage, batch)
        bank = self.bank(batch["crop"].device)
        ignore = self._ignore(batch)
        sil = render_silhouettes(bank, pred["template_id"], pred["dims"], pred["ry"], pred["center"], pred["phi"],
                                 batch["crop_intrinsics"], self.soft_settings(size))
        image_error = None
        if self.image_size is not None:
            image_error = self._image_errors(batch, pred["template_id"], pred["dims"], pred["ry"], pred["center"],
                                             pred["phi"])
        metrics = self.metrics[stage]
        metrics.update(pred, batch, sil, ignore, image_error)
        if stage == "test":
            settings = self.soft_settings(size)
            at_prediction = template_reprojection_errors(bank, pred["dims"], pred["ry"], pred["center"], pred["phi"],
                                                         batch["crop_intrinsics"], batch["mask"], ignore, settings)
            at_truth = template_reprojection_errors(bank, batch["dims"], batch["ry"], batch["center"], None,
                                                    batch["crop_intrinsics"], batch["mask"], ignore, settings)
            metrics.update_selection(pred["template_id"], at_prediction, at_truth, batch["template_id"])
            if image_error is not None:
                self._update_decomposition(batch, pred, image_error)
                if self.hparams.get("test_refine") and "raw" in pred:
                    self._update_refined(batch, pred["raw"])
        stats = self._template_stats.setdefault(stage, [])
        stats.append(torch.cat([pred["template_probs"], pred["template_id"].unsqueeze(1).float()], 1).cpu())
        if batch_idx == 0:
            self._log_silhouettes(stage, batch, sil)

    def _image_errors(self, batch: Mapping[str, Any], template_ids: Tensor, dims: Tensor, ry: Tensor, center: Tensor,
                      phi: Tensor | None) -> Tensor:
        """The paper's reprojection error ``(N,)`` (hard, per image pixel) of the given meshes and poses."""
        sil = window_silhouettes(self.bank(dims.device), template_ids, dims, ry, center, phi, batch["intrinsics"],
                                 batch["crop_box"], self.image_size)
        return image_reprojection_error(sil, batch["mask"], batch["ignore"], batch["crop_box"], self.image_size)

    #: The decomposition of the test reprojection error (``test/decomposition/<name>``): which pose, which mesh,
    #: which FFD; objects whose true template is known.
    DECOMPOSITION = ("predicted", "chosen_no_ffd", "sedan", "true_template", "true_template_no_ffd", "best_of_8",
                     "truth_pose_true_template")

    @torch.no_grad()
    def _update_decomposition(self, batch: Mapping[str, Any], pred: Mapping[str, Tensor], predicted: Tensor) -> None:
        """Score the predicted pose with other meshes and FFDs, and the true pose (the floor): where the test
        reprojection error comes from (issue 29). Each entry of :attr:`DECOMPOSITION` gets ``(N,)`` errors;
        ``predicted`` is the prediction's own ``(N,)`` (:meth:`_image_errors`, already computed for the metrics)."""
        known = batch["template_id"] >= 0
        if not bool(known.any()):
            return
        batch = {k: v[known] if isinstance(v, Tensor) and v.shape[:1] == known.shape else v for k, v in batch.items()}
        pred = {k: v[known] if isinstance(v, Tensor) and v.shape[:1] == known.shape else v for k, v in pred.items()}
        dims, ry, center, phi = pred["dims"], pred["ry"], pred["center"], pred["phi"]
        zero = None if phi is None else torch.zeros_like(phi)
        truth = batch["template_id"]
        # Every template at the predicted pose and FFD, (N, 8): the sedan, the true template and the best are read off.
        each = torch.stack([self._image_errors(batch, torch.full_like(truth, t), dims, ry, center, phi)
                            for t in range(len(TEMPLATE_NAMES))], 1)
        errors = {
            "predicted": predicted[known],
            "chosen_no_ffd": self._image_errors(batch, pred["template_id"], dims, ry, center, zero),
            "sedan": each[:, TEMPLATE_NAMES.index("sedan")],
            "true_template": each.gather(1, truth.unsqueeze(1)).squeeze(1),
            "true_template_no_ffd": self._image_errors(batch, truth, dims, ry, center, zero),
            "best_of_8": each.amin(1),
            "truth_pose_true_template": self._image_errors(batch, truth, batch["dims"], batch["ry"], batch["center"],
                                                           None),
        }
        for name, value in errors.items():
            self._decomposition.setdefault(name, []).append(value.detach().float().cpu())

    def _update_refined(self, batch: Mapping[str, Any], raw: Mapping[str, Tensor]) -> None:
        """The test figures after the paper's per-image fit (Adam 0.03 x 16 on L_reproj; 3D-SDN on Cityscapes),
        started from the net's outputs ``raw`` of :meth:`decode_batch`."""
        # Lightning tests under inference mode, whose tensors autograd refuses: the fit runs outside it, on copies
        # (the fit itself runs in float32), and not under a mixed-precision autocast.
        with torch.inference_mode(False), torch.autocast(batch["crop"].device.type, enabled=False):
            inputs = {k: batch[k].clone().float()
                      for k in ("box", "intrinsics", "crop_intrinsics", "mask", "ignore", "crop_box")}
            raw = {k: v.clone() for k, v in raw.items()}
            refined = refine_by_reprojection(raw, inputs["box"], inputs["intrinsics"], inputs["crop_intrinsics"],
                                             inputs["mask"], inputs["ignore"], encoding=self.encoding,
                                             templates=self.net.templates, bank=self.bank(batch["crop"].device),
                                             settings=RefineSettings(sigma=float(self.hparams.sigma)),
                                             crop_box=inputs["crop_box"], image_size=self.image_size)
        pred = dict(refined.pred)
        pred["rot"] = predicted_rotation(refined.raw["rotation"], pred["ry"], self.encoding.rotation)
        image_error = self._image_errors(batch, pred["template_id"], pred["dims"], pred["ry"], pred["center"],
                                         pred["phi"])
        self.metrics["test_refined"].update(pred, batch, None, None, image_error)

    def _log_silhouettes(self, stage: str, batch: Mapping[str, Any], sil: Tensor) -> None:
        count = min(int(self.hparams.log_images), sil.shape[0])
        if count > 0:
            crop, mask, s = batch["crop"][:count], batch["mask"][:count], sil[:count].unsqueeze(1)
            overlay = crop * 0.5
            overlay[:, :1] = torch.maximum(overlay[:, :1], s)  # silhouette in red over the darkened crop
            self.log_image_grid(f"{stage}/silhouettes", [crop, mask, s, overlay])

    def _eval_epoch_end(self, stage: str) -> None:
        counts = self.train_template_counts if bool(self.train_template_counts.sum() > 0) else None
        values = self.metrics[stage].compute(counts)
        self.metrics[stage].reset()
        for name, value in values.items():  # figures without objects (mesh ones on real data) are left out
            self.log(f"{stage}/{name}", value.to(self.device), sync_dist=True)
        if stage == "test":
            refined = self.metrics["test_refined"]
            if refined["orientation_similarity"].count > 0:
                for name, value in refined.compute(counts).items():
                    if name in ("orientation_similarity", "distance_error", "scale_error", "reprojection_error_image"):
                        self.log(f"test/refined/{name}", value.to(self.device), sync_dist=True)
            refined.reset()
            for name, parts in self._decomposition.items():
                self.log(f"test/decomposition/{name}", torch.cat(parts).mean().to(self.device), sync_dist=True)
            self._decomposition = {}
        stats = self._template_stats.pop(stage, [])
        if not stats:
            return
        stats = torch.cat(stats)
        mean_probs = stats[:, :-1].mean(0)
        for i, name in enumerate(TEMPLATE_NAMES):
            self.log(f"{stage}/template_prob/{name}", mean_probs[i].to(self.device), sync_dist=True)
        writer = self.tensorboard
        if writer is not None and not self.trainer.sanity_checking:
            writer.add_histogram(f"{stage}/selected_template", stats[:, -1], global_step=self.global_step,
                                 bins=torch.arange(len(TEMPLATE_NAMES) + 1).float().sub(0.5).numpy())

    def validation_step(self, batch: dict[str, Any], batch_idx: int) -> None:
        self._eval_step("val", batch, batch_idx)

    def on_validation_epoch_end(self) -> None:
        self._eval_epoch_end("val")

    def test_step(self, batch: dict[str, Any], batch_idx: int) -> None:
        self._eval_step("test", batch, batch_idx)

    def on_test_epoch_end(self) -> None:
        self._eval_epoch_end("test")

    @torch.no_grad()
    def predict_step(self, batch: dict[str, Any], batch_idx: int) -> dict[str, Tensor]:
        raw = self.net(batch["crop"], batch["box"], batch["intrinsics"])
        return decode_outputs(raw, batch["box"], batch["intrinsics"], self.encoding, self.net.templates)
