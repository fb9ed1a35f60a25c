"""Semantic branch training: DRN segmentation + Panoptic-DeepLab instance head (``sdn3d-train branch=semantic``).

Loss: cross-entropy (ignore index 255; optionally class-weighted, ``class_weighting``, with weights from
the training split's label histogram computed once at the start of fitting and kept in the checkpoint)
+ ``center_weight`` * focal loss of the centre heatmap
(CenterNet's; Panoptic-DeepLab's 200x MSE diverges under plain SGD) + ``offset_weight`` * L1 of
the offsets on thing pixels.
Optimiser: SGD (DRN code; or AdamW, ``optimizer=adamw``) with a per-step poly schedule
``lr * (1 - step / total) ** poly_power`` (DRN code).
Metrics (val/ and test/): ``miou`` and ``iou_<class>`` from a torchmetrics confusion matrix,
``pq`` / ``sq`` / ``rq`` and ``pq_<class>`` of the thing classes (instances grouped from the
predictions, compared with the ground-truth instance maps), and ``proposal_recall`` / ``proposal_precision``:
the share of thing objects over the paper's 256 pixels (at 624x192, scaled by the area to the working size) that
some proposal covers with IoU >= 0.5, and the share of proposals covering an object
(:mod:`sdn3d.evaluation.proposal_recall`, the demo's measure: what editing needs, without PQ's tiny far cars).
TensorBoard: ``<stage>/segmentation`` grids (input | prediction | ground truth, in the dataset's colours) and
``<stage>/instances``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from typing import Any

import torch
import torch.nn.functional as F
from torch import Tensor
from torchmetrics import Metric
from torchmetrics.classification import MulticlassConfusionMatrix

from lightning_modules._base import BranchModule, plain_hparams
from sdn3d.evaluation.proposal_recall import match_proposals, min_pixels_at
from sdn3d.labels import IGNORE_INDEX, class_list, thing_class_ids
from sdn3d.nets.drn import DRNSeg
from sdn3d.nets.weights import load_pretrained
from sdn3d.semantic import (
    CLASS_WEIGHTINGS,
    GROUPING_DEFAULTS,
    center_focal_loss,
    class_weights,
    color_jitter,
    flip_averaged_outputs,
    group_vehicles,
    label_histogram,
    panoptic_targets,
    pq_from_stats,
    pq_stats,
    random_crop_flip,
)
from sdn3d.visualize import colorize_instances, colorize_labels

__all__ = ["SemanticModule", "PanopticQuality", "ProposalRecall", "OPTIMIZERS"]

#: ``SemanticModule(optimizer=...)``.
OPTIMIZERS = ("sgd", "adamw")

log = logging.getLogger(__name__)


class PanopticQuality(Metric):
    """Summed :func:`~sdn3d.semantic.pq.pq_stats` over a dataset; ``compute()`` -> ``{'pq','sq','rq'}`` per class."""

    full_state_update = False

    def __init__(self, thing_classes: Sequence[int]) -> None:
        super().__init__()
        self.thing_classes = list(thing_classes)
        self.add_state("stats", default=torch.zeros(4, len(self.thing_classes), dtype=torch.float64),
                       dist_reduce_fx="sum")

    def update(self, pred_instance: Tensor, gt_instance: Tensor, gt_label: Tensor) -> None:
        self.stats += pq_stats(pred_instance, gt_instance, gt_label, self.thing_classes)

    def compute(self) -> dict[str, Tensor]:
        return pq_from_stats(self.stats)


class ProposalRecall(Metric):
    """Proposal recall and precision summed over a part (:func:`~sdn3d.evaluation.proposal_recall.match_proposals`;
    objects over :func:`~sdn3d.evaluation.proposal_recall.min_pixels_at` the maps' size); ``compute()`` ->
    ``{'recall', 'precision'}`` (NaN where nothing was counted)."""

    full_state_update = False

    def __init__(self, thing_classes: Sequence[int]) -> None:
        super().__init__()
        self.thing_classes = list(thing_classes)
        for name in ("objects", "found", "proposals", "true_proposals"):
            self.add_state(name, default=torch.zeros((), dtype=torch.float64), dist_reduce_fx="sum")

    def update(self, pred_instance: Tensor, gt_instance: Tensor) -> None:
        counts = match_proposals(pred_instance, gt_instance, self.thing_classes,
                                 min_pixels_at(gt_instance.shape[-1], gt_instance.shape[-2]))
        self.objects += sum(counts.objects.values())
        self.found += sum(counts.found.values())
        self.proposals += counts.proposals
        self.true_proposals += counts.true_proposals

    def compute(self) -> dict[str, Tensor]:
        nan = torch.tensor(float("nan"), dtype=torch.float64, device=self.objects.device)
        return {"recall": self.found / self.objects if self.objects > 0 else nan,
                "precision": self.true_proposals / self.proposals if self.proposals > 0 else nan}


def _tag(name: str) -> str:
    return name.replace(" ", "_")


class SemanticModule(BranchModule):
    """DRN semantic segmentation with instance proposals (centre / offset head).

    Args:
        classes: class-list name (``'vkitti'``, ``'cityscapes'``; ``${data.classes}`` in the config).
        arch: ``'drn_d_22'`` (paper) or ``'drn_c_26'``.
        pretrained: optional local ImageNet checkpoint of the backbone (None: random init).
        channels: backbone channels per level; None = the published DRN widths.
        instance_head: train the centre / offset head (instance proposals without ground-truth masks).
        head_channels: width of the instance head.
        thing_classes: class names / ids split into instances; None = those with ``has_instances``.
        lr, momentum, weight_decay, poly_power: SGD and poly schedule.
        crop_size: training crop (square side or ``[W, H]``, clamped to the image); None = whole image.
        hflip: random horizontal flips in training.
        center_sigma: Gaussian sigma of the centre targets, pixels of the working size.
        center_weight, offset_weight: loss weights of the instance head.
        center_threshold, nms_kernel, top_k, min_area, thing_odds, split_separation, part_separation: instance
            grouping at evaluation / inference (:data:`sdn3d.semantic.predict.GROUPING_DEFAULTS`).
        log_images: samples per TensorBoard grid (first validation / test batch); 0 = none.
        class_weighting: None (plain cross-entropy), ``'median_frequency'`` or ``'enet'``
            (:mod:`sdn3d.semantic.balance`), for rare classes.
        max_class_weight: upper clip of those weights.
        decoder: ``'bilinear'`` (the paper's stride-8 head) or ``'skip'`` (full-resolution skip decoder,
            :class:`~sdn3d.nets.drn.SkipDecoder`; thin classes need it).
        decoder_channels: skip-decoder widths at strides 4, 2, 1.
        optimizer: ``'sgd'`` (the paper; ``momentum`` applies) or ``'adamw'`` (faster on short budgets).
        color_jitter: strength of the random brightness / contrast / saturation in training; 0 = none.
        test_flip: validate and test on the image and its mirror image, outputs averaged
            (:func:`sdn3d.semantic.tta.flip_averaged_outputs`); checkpoints carry it to ``SemanticPredictor``.
        nonfinite, max_skipped_batches: non-finite loss policy (:class:`BranchModule`; ``fault.nonfinite``,
            ``fault.max_skipped_batches``); not hyperparameters.
    """

    def __init__(
        self,
        classes: str = "vkitti",
        arch: str = "drn_d_22",
        pretrained: str | None = None,
        channels: Sequence[int] | None = None,
        instance_head: bool = True,
        head_channels: int = 128,
        thing_classes: Sequence[str | int] | None = None,
        lr: float = 0.01,
        momentum: float = 0.9,
        weight_decay: float = 1e-4,
        poly_power: float = 0.9,
        crop_size: int | Sequence[int] | None = None,
        hflip: bool = True,
        center_sigma: float = 4.0,
        center_weight: float = 1.0,
        offset_weight: float = 0.5,
        center_threshold: float = 0.1,
        nms_kernel: int = 7,
        top_k: int = 50,
        min_area: int = 16,
        thing_odds: float | None = GROUPING_DEFAULTS["thing_odds"],
        split_separation: float | None = GROUPING_DEFAULTS["split_separation"],
        part_separation: float | None = GROUPING_DEFAULTS["part_separation"],
        log_images: int = 4,
        class_weighting: str | None = None,
        max_class_weight: float = 10.0,
        decoder: str = "bilinear",
        decoder_channels: Sequence[int] = (64, 32, 16),
        optimizer: str = "sgd",
        color_jitter: float = 0.0,
        test_flip: bool = False,
        nonfinite: str = "stop",
        max_skipped_batches: int = 10,
    ) -> None:
        super().__init__(nonfinite=nonfinite, max_skipped_batches=max_skipped_batches)
        args = {k: plain_hparams(v) for k, v in locals().items()
                if k not in ("self", "__class__", "nonfinite", "max_skipped_batches")}
        self.save_hyperparameters(args)
        if lr <= 0 or not 0 <= momentum < 1 or weight_decay < 0 or poly_power < 0:
            raise ValueError(f"need lr > 0, 0 <= momentum < 1, weight_decay >= 0, poly_power >= 0; got lr={lr}, "
                             f"momentum={momentum}, weight_decay={weight_decay}, poly_power={poly_power}")
        self.classes = class_list(classes)
        self.num_classes = len(self.classes)
        if optimizer not in OPTIMIZERS:
            raise ValueError(f"optimizer must be one of {OPTIMIZERS}, got {optimizer!r}")
        if not 0.0 <= color_jitter < 1.0:
            raise ValueError(f"color_jitter must be in [0, 1), got {color_jitter}")
        self.things = thing_class_ids(self.classes, args["thing_classes"])
        extra = {} if args["channels"] is None else {"channels": args["channels"]}
        self.net = DRNSeg(self.num_classes, arch=arch, instance_head=instance_head, head_channels=head_channels,
                          decoder=decoder, decoder_channels=args["decoder_channels"], **extra)
        # Loaded here rather than by DRNSeg so that training without weights says so (load_pretrained warns).
        load_pretrained(self.net.backbone, pretrained, what=f"{arch} backbone", ignore_prefixes=("fc.",))
        self.crop_size = args["crop_size"]
        if class_weighting is not None and class_weighting not in CLASS_WEIGHTINGS:
            raise ValueError(f"class_weighting must be null or one of {CLASS_WEIGHTINGS}, got {class_weighting!r}")
        # Filled from the training labels at the first fit (on_fit_start); a checkpoint carries them on.
        self.register_buffer("ce_weight", torch.ones(self.num_classes))
        self.register_buffer("ce_weight_ready", torch.tensor(class_weighting is None))
        self.metrics = torch.nn.ModuleDict({
            f"{stage}_confmat": MulticlassConfusionMatrix(self.num_classes, ignore_index=IGNORE_INDEX,
                                                          validate_args=False)
            for stage in ("val", "test")
        })
        if instance_head and self.things:
            self.metrics.update({f"{stage}_pq": PanopticQuality(self.things) for stage in ("val", "test")})
            self.metrics.update({f"{stage}_proposals": ProposalRecall(self.things) for stage in ("val", "test")})

    def on_load_checkpoint(self, checkpoint: dict[str, Any]) -> None:
        super().on_load_checkpoint(checkpoint)
        # Checkpoints written before class weighting existed have no such buffers: plain cross-entropy.
        state = checkpoint.get("state_dict", {})
        state.setdefault("ce_weight", torch.ones(self.num_classes))
        state.setdefault("ce_weight_ready", torch.tensor(True))

    def on_fit_start(self) -> None:
        if bool(self.ce_weight_ready):
            return
        datamodule = getattr(self.trainer, "datamodule", None)
        dataset = getattr(datamodule, "datasets", {}).get("train") if datamodule is not None else None
        if dataset is None:
            raise RuntimeError("class_weighting needs the datamodule's training split (datamodule.datasets['train'])")
        counts = label_histogram((dataset[i]["label"] for i in range(len(dataset))), self.num_classes)
        weights = class_weights(counts, self.hparams.class_weighting, float(self.hparams.max_class_weight))
        self.ce_weight.copy_(weights.to(self.ce_weight.device))
        self.ce_weight_ready.fill_(True)
        shown = ", ".join(f"{c.name} {float(w):.2f}" for c, w in zip(self.classes, weights, strict=True))
        log.info("class weights (%s, %d training images): %s", self.hparams.class_weighting, len(dataset), shown)

    def forward(self, image: Tensor) -> dict[str, Tensor]:
        """``image`` ``(B, 3, H, W)`` in [0, 1] -> network outputs (see :class:`~sdn3d.nets.drn.DRNSeg`)."""
        return self.net(image)

    # -- losses ---------------------------------------------------------------------------------------------
    def losses(self, out: dict[str, Tensor], label: Tensor, instance: Tensor) -> dict[str, Tensor]:
        """Loss terms for network outputs and ``(B, H, W)`` targets; ``'loss'`` is the weighted total."""
        hp = self.hparams
        weight = None if self.hparams.get("class_weighting") is None else self.ce_weight.to(out["logits"].dtype)
        terms = {"ce": F.cross_entropy(out["logits"], label, weight=weight, ignore_index=IGNORE_INDEX)}
        loss = terms["ce"]
        if "center" in out and self.things:
            target = panoptic_targets(instance, self.things, sigma=hp.center_sigma)
            terms["center"] = center_focal_loss(out["center_logits"], target.center)
            mask = target.offset_mask.expand_as(out["offset"]).float()
            terms["offset"] = ((out["offset"] - target.offset).abs() * mask).sum() / mask.sum().clamp_min(1.0)
            loss = loss + hp.center_weight * terms["center"] + hp.offset_weight * terms["offset"]
        terms["loss"] = loss
        return terms

    def training_step(self, batch: dict[str, Any], batch_idx: int) -> Tensor | None:
        image, (label, instance) = random_crop_flip(batch["image"], [batch["label"], batch["instance"]],
                                                    self.crop_size, self.hparams.hflip)
        image = color_jitter(image, float(self.hparams.get("color_jitter", 0.0)))
        terms = self.losses(self(image), label, instance)
        if not self.guard_loss(terms["loss"]):
            return None
        bs = image.shape[0]
        self.log("train/loss", terms["loss"], on_step=True, on_epoch=True, prog_bar=True, batch_size=bs,
                 sync_dist=True)
        for key in ("ce", "center", "offset"):
            if key in terms:
                self.log(f"train/{key}", terms[key], on_step=False, on_epoch=True, batch_size=bs, sync_dist=True)
        return terms["loss"]

    # -- evaluation -----------------------------------------------------------------------------------------
    @torch.no_grad()
    def predict_maps(self, out: dict[str, Tensor]) -> tuple[Tensor, Tensor]:
        """``(label, instance)`` ``(B, H, W)`` from network outputs (raw argmax labels; grouped instances)."""
        label = out["logits"].argmax(1)
        if "center" not in out or not self.things:
            return label, torch.zeros_like(label)
        hp = self.hparams
        instance, _ = group_vehicles(label, out["logits"].softmax(1), out["center"], out["offset"], self.things,
                                     thing_odds=hp.thing_odds, threshold=hp.center_threshold, nms_kernel=hp.nms_kernel,
                                     top_k=hp.top_k, min_area=hp.min_area, split_separation=hp.split_separation,
                                     part_separation=hp.part_separation)
        return label, instance

    def _eval_step(self, stage: str, batch: dict[str, Any], batch_idx: int) -> None:
        image, label, instance = batch["image"], batch["label"], batch["instance"]
        out = flip_averaged_outputs(self.net, image) if self.hparams.get("test_flip", False) else self(image)
        terms = self.losses(out, label, instance)
        self.log(f"{stage}/loss", terms["loss"], on_step=False, on_epoch=True, batch_size=image.shape[0],
                 sync_dist=True)
        pred, pred_instance = self.predict_maps(out)
        self.metrics[f"{stage}_confmat"].update(pred, label)
        if f"{stage}_pq" in self.metrics:
            self.metrics[f"{stage}_pq"].update(pred_instance, instance, label)
            self.metrics[f"{stage}_proposals"].update(pred_instance, instance)
        n = min(int(self.hparams.log_images), image.shape[0])
        if batch_idx == 0 and n > 0:
            self.log_image_grid(f"{stage}/segmentation", [image[:n], colorize_labels(pred[:n], self.classes),
                                                          colorize_labels(label[:n], self.classes)])
            if f"{stage}_pq" in self.metrics:
                self.log_image_grid(f"{stage}/instances", [image[:n], colorize_instances(pred_instance[:n]),
                                                           colorize_instances(instance[:n])])

    def _eval_epoch_end(self, stage: str) -> None:
        confmat = self.metrics[f"{stage}_confmat"].compute().double()
        self.metrics[f"{stage}_confmat"].reset()
        tp = confmat.diagonal()
        union = confmat.sum(0) + confmat.sum(1) - tp
        present = union > 0  # classes absent from both prediction and ground truth do not count
        iou = tp / union.clamp_min(1)
        metrics = {f"{stage}/miou": iou[present].mean() if present.any() else iou.new_tensor(0.0),
                   f"{stage}/pixel_acc": tp.sum() / confmat.sum().clamp_min(1)}
        metrics.update({f"{stage}/iou_{_tag(c.name)}": iou[c.id] for c in self.classes if present[c.id]})
        if f"{stage}_pq" in self.metrics:
            pq = self.metrics[f"{stage}_pq"].compute()
            self.metrics[f"{stage}_pq"].reset()
            defined = ~torch.isnan(pq["pq"])
            for key in ("pq", "sq", "rq"):
                metrics[f"{stage}/{key}"] = pq[key][defined].mean() if defined.any() else pq[key].new_tensor(0.0)
            metrics.update({f"{stage}/pq_{_tag(self.classes[c].name)}": pq["pq"][i]
                            for i, c in enumerate(self.things) if defined[i]})
            proposals = self.metrics[f"{stage}_proposals"].compute()
            self.metrics[f"{stage}_proposals"].reset()
            metrics.update({f"{stage}/proposal_{key}": value for key, value in proposals.items()
                            if not torch.isnan(value)})
        self.log_dict({k: v.float() for k, v in metrics.items()}, sync_dist=True)

    def validation_step(self, batch: dict[str, Any], batch_idx: int) -> None:
        self._eval_step("val", batch, batch_idx)

    def on_validation_epoch_end(self) -> None:
        self._eval_epoch_end("val")

    def test_step(self, batch: dict[str, Any], batch_idx: int) -> None:
        self._eval_step("test", batch, batch_idx)

    def on_test_epoch_end(self) -> None:
        self._eval_epoch_end("test")

    def predict_step(self, batch: dict[str, Any], batch_idx: int) -> dict[str, Any]:
        label, instance = self.predict_maps(self(batch["image"]))
        return {"key": batch.get("key"), "label": label, "instance": instance}

    # -- optimisation ---------------------------------------------------------------------------------------
    def configure_optimizers(self) -> dict[str, Any]:
        hp = self.hparams
        if hp.get("optimizer", "sgd") == "adamw":
            optimizer = torch.optim.AdamW(self.parameters(), lr=hp.lr, weight_decay=hp.weight_decay)
        else:
            optimizer = torch.optim.SGD(self.parameters(), lr=hp.lr, momentum=hp.momentum,
                                        weight_decay=hp.weight_decay)
        total = float(self.trainer.estimated_stepping_batches)
        power = float(hp.poly_power)

        def poly(step: int) -> float:
            if not math.isfinite(total):  # no step or epoch limit: no end to decay towards
                return 1.0
            return (1.0 - min(step, total) / max(total, 1.0)) ** power

        scheduler = torch.optim.lr_scheduler.LambdaLR(optimizer, poly)
        return {"optimizer": optimizer, "lr_scheduler": {"scheduler": scheduler, "interval": "step"}}
