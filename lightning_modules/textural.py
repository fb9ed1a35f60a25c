"""TexturalModule: pix2pixHD training of the textural branch (generator G, encoder E, discriminator D).

Losses (3D-SDN textural code, pix2pixHD):

- D: ``0.5 * (LSGAN(D(c, G(x)), fake) + LSGAN(D(c, I), real))``, summed over the 2 scales.
- G and E: ``LSGAN(D(c, G(x)), real) + lambda_fm * FM + lambda_perceptual * P + lambda_recon * |G(x) - I|_1
  + lambda_swap * SWAP`` with FM the discriminator feature matching, P the perceptual loss
  (``perceptual``: ``'vgg'``, an ImageNet VGG-19 from the file ``perceptual_weights``, the paper's;
  ``'drn'``, the project's trained semantic DRN from a semantic checkpoint ``perceptual_weights``,
  :class:`sdn3d.nets.perceptual.DRNPerceptualLoss`; ``'none'``: off, logged as such), the L1 on ``[-1, 1]``
  images. Paper: lambda_FM = 5, lambda_Recon = 10; the perceptual term uses lambda_FM like 3D-SDN's code
  (``lambda_perceptual=None``).
- SWAP (not in the paper; ``lambda_swap = 0`` is the paper's recipe): the **code-swap colour term**. Every
  object's code is replaced by the code of another object of its class in the batch
  (:func:`sdn3d.textural.codes.code_donors`), G draws the batch again from the swapped code map, and each
  swapped object's mean colour in that drawing must match its donor's mean colour in the real image (L1 on
  ``[-1, 1]`` RGB, objects of at least ``swap_min_pixels`` pixels). Why: with the paper's losses alone G
  reconstructs objects from the label / pose / normal maps and barely reads the texture code (on the demo a
  car recoloured by a swapped code moved 3 % of the way to the donor's colour) although E's codes do carry
  the colour (linear R^2 about 0.65 from 5-d codes): nothing in the reconstruction makes G *need* the code
  within a short schedule, and the code's spread across cars (std ~0.07) is small next to the other
  inputs. The term asks for exactly what an edit needs, that the code decides the object's colour.

``x`` is the generator input (semantic one-hot, instance boundaries, E's per-instance code map,
pose map, normal map; see :class:`sdn3d.nets.pix2pixhd.TexturalSpec`), ``c`` the discriminator
condition (one-hot + boundaries).

Optimisation is manual: one G/E Adam step then one D Adam step per batch (lr 2e-4, betas
(0.5, 0.999)), constant for ``lr_constant_epochs`` epochs then linear decay to 0 over
``lr_decay_epochs`` (stepped at each epoch end). Step counts: **Lightning's ``global_step`` counts
optimizer steps, i.e. 2 per batch** (so ``trainer.max_steps = 2 * N`` trains N batches); logged
scalars use Lightning's logger step, which counts batches (= G updates), and the image grids use
the ``g_updates`` buffer (G updates, saved in checkpoints so that a resumed run continues it).

When fitting ends, ``<checkpoint>.code_bank.json`` is written next to the best and the last checkpoint
(``write_code_bank``): every training region's code under that checkpoint's E, with its class and mean colour
(:mod:`sdn3d.textural.code_bank`), for ``recolor: {color: red}`` / ``sample: true`` in ``sdn3d-edit``.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Mapping
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import Tensor
from torch.optim.lr_scheduler import LambdaLR

from lightning_modules._base import BranchModule
from sdn3d.errors import UserInputError
from sdn3d.evaluation.image_metrics import image_metrics
from sdn3d.labels import INSTANCE_DIVISOR, class_list
from sdn3d.nets.lpips import load_lpips
from sdn3d.nets.perceptual import DRNPerceptualLoss
from sdn3d.nets.pix2pixhd import TexturalSpec, feature_matching_loss, instance_mean, lsgan_loss, region_index
from sdn3d.nets.vgg import VGGPerceptualLoss
from sdn3d.semantic.predict import SemanticPredictor
from sdn3d.textural.code_bank import CodeBank, build_code_bank, code_bank_path, save_code_bank
from sdn3d.textural.codes import code_donors
from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["LinearDecay", "PERCEPTUAL_NETS", "TexturalModule", "perceptual_loss"]

log = logging.getLogger(__name__)

PERCEPTUAL_NETS = ("none", "vgg", "drn")


def perceptual_loss(kind: str, weights: str | None) -> torch.nn.Module | None:
    """The frozen perceptual loss ``kind`` (:data:`PERCEPTUAL_NETS`) from its file, None for ``'none'``.

    ``'vgg'``: a torchvision VGG-19 state dict; ``'drn'``: a semantic-branch checkpoint (``sdn3d-train
    branch=semantic``) whose DRN becomes F. Raises :class:`UserInputError` naming ``model.perceptual`` /
    ``model.perceptual_weights`` when the choice or its file is wrong.
    """
    if kind not in PERCEPTUAL_NETS:
        raise UserInputError(f"model.perceptual must be one of {PERCEPTUAL_NETS}, got {kind!r}")
    if kind == "none":
        log.warning("TexturalModule: training WITHOUT a perceptual term (model.perceptual=none)")
        return None
    if not weights:
        what = "a torchvision VGG-19 state dict (.pth)" if kind == "vgg" else "a semantic-branch checkpoint"
        raise UserInputError(f"model.perceptual={kind} needs model.perceptual_weights: {what}")
    if kind == "vgg":
        return VGGPerceptualLoss.from_file(weights)
    return DRNPerceptualLoss(SemanticPredictor.from_checkpoint(weights, map_location="cpu").net)



def silence_step_checkpoint_warning() -> None:
    """Ignore Lightning's warning that step-interval checkpoints of a manually optimised module hold the
    weights after the step (called when fitting starts).

    For this module that is the right state: those checkpoints are for resuming (weights, optimiser moments
    and step counters must all be from after the same step), never for picking a model by a training
    metric. Only this exact message is silenced.
    """
    warnings.filterwarnings("ignore", message=r"Using ModelCheckpoint with manual optimization and "
                            r"every_n_train_steps", category=UserWarning)


def _same_weights(a: Mapping[str, Tensor], b: Mapping[str, Tensor]) -> bool:
    """Whether two state dicts hold the same tensors (names, shapes, dtypes and values, bit for bit)."""
    return a.keys() == b.keys() and all(a[k].dtype == b[k].dtype and torch.equal(a[k], b[k]) for k in a)


class LinearDecay:
    """``LambdaLR`` factor of epoch ``e``: 1 for ``constant`` epochs, then ``1 - (e - constant) / decay`` (>= 0).

    A callable object (not a lambda) so that the scheduler's state dict keeps it.
    """

    def __init__(self, constant: int, decay: int) -> None:
        if constant < 0 or decay < 0:
            raise ValueError(f"lr_constant_epochs and lr_decay_epochs must be >= 0, got {constant}, {decay}")
        self.constant = int(constant)
        self.decay = int(decay)

    def __call__(self, epoch: int) -> float:
        if self.decay == 0:
            return 1.0
        return max(0.0, 1.0 - max(0, epoch - self.constant) / self.decay)


class TexturalModule(BranchModule):
    """pix2pixHD G + E + multi-scale D for the textural branch.

    Args:
        classes: class list name, ``'vkitti'`` (14) or ``'cityscapes'`` (19).
        code_dim: texture code size (paper 5).
        use_codes, use_pose, use_normal: generator inputs (decoupling ablation switches).
        ngf, n_downsampling, n_blocks: global generator (paper 64, 4, 9).
        nef, n_downsampling_encoder: texture encoder (pix2pixHD 16, 4).
        ndf, n_layers_d, num_d: discriminator (64, 3, 2).
        norm: ``'instance'`` or ``'batch'``.
        lambda_fm, lambda_recon: loss weights (paper 5, 10); lambda_perceptual: None = lambda_fm.
        lambda_swap: weight of the code-swap colour term (0 = off, the paper's recipe); swap_min_pixels: the
            smallest object (pixels at the training size) the term looks at.
        lr, beta1, beta2: Adam for both optimizers.
        lr_constant_epochs, lr_decay_epochs: linear decay schedule (pix2pixHD 100 + 100).
        perceptual: ``'none'``, ``'vgg'`` or ``'drn'`` (module doc); perceptual_weights: its file.
        write_code_bank: at the end of fitting, write ``<checkpoint>.code_bank.json`` next to the best and the
            last checkpoint (:mod:`sdn3d.textural.code_bank`; needs the datamodule's ``code_bank_loader``).
        lpips_weights: LPIPS file (see :mod:`sdn3d.nets.lpips`; None: no LPIPS metric).
        grid_samples: images per TensorBoard grid.
        nonfinite, max_skipped_batches: non-finite loss policy (:class:`BranchModule`; ``fault.nonfinite``,
            ``fault.max_skipped_batches``); not hyperparameters.
    """

    def __init__(
        self,
        classes: str = "vkitti",
        code_dim: int = 5,
        use_codes: bool = True,
        use_pose: bool = True,
        use_normal: bool = True,
        ngf: int = 64,
        n_downsampling: int = 4,
        n_blocks: int = 9,
        nef: int = 16,
        n_downsampling_encoder: int = 4,
        ndf: int = 64,
        n_layers_d: int = 3,
        num_d: int = 2,
        norm: str = "instance",
        lambda_fm: float = 5.0,
        lambda_recon: float = 10.0,
        lambda_perceptual: float | None = None,
        lambda_swap: float = 0.0,
        swap_min_pixels: int = 16,
        lr: float = 2e-4,
        beta1: float = 0.5,
        beta2: float = 0.999,
        lr_constant_epochs: int = 100,
        lr_decay_epochs: int = 100,
        perceptual: str = "none",
        perceptual_weights: str | None = None,
        write_code_bank: bool = True,
        lpips_weights: str | None = None,
        grid_samples: int = 4,
        nonfinite: str = "stop",
        max_skipped_batches: int = 10,
    ) -> None:
        super().__init__(nonfinite=nonfinite, max_skipped_batches=max_skipped_batches)
        self.save_hyperparameters(ignore=["nonfinite", "max_skipped_batches"])
        self.automatic_optimization = False
        self.classes = class_list(classes)
        self.spec = TexturalSpec(
            num_classes=len(self.classes), code_dim=code_dim, use_codes=use_codes, use_pose=use_pose,
            use_normal=use_normal, ngf=ngf, n_downsampling=n_downsampling, n_blocks=n_blocks, nef=nef,
            n_downsampling_encoder=n_downsampling_encoder, ndf=ndf, n_layers_d=n_layers_d, num_d=num_d, norm=norm)
        self.generator = self.spec.generator()
        self.encoder = self.spec.encoder()
        self.discriminator = self.spec.discriminator()
        self.lambda_perceptual = lambda_fm if lambda_perceptual is None else lambda_perceptual
        if lambda_swap < 0 or swap_min_pixels < 1:
            raise UserInputError(f"model.lambda_swap must be >= 0 and model.swap_min_pixels >= 1, got {lambda_swap} "
                                 f"and {swap_min_pixels}")
        # Frozen pretrained nets sit in a plain dict: not submodules, so not in checkpoints
        # (they come from their own files) and a run without them has the same state-dict keys.
        self._frozen = {"perceptual": perceptual_loss(perceptual, perceptual_weights),
                        "lpips": load_lpips(lpips_weights)}
        self.register_buffer("g_updates", torch.zeros((), dtype=torch.long))
        palette = torch.zeros(256, 3)
        palette[: len(self.classes)] = torch.tensor([c.color for c in self.classes], dtype=torch.float32) / 255
        self.register_buffer("palette", palette, persistent=False)

    # ------------------------------------------------------------------ forward
    def _frozen_net(self, name: str, like: Tensor):
        net = self._frozen[name]
        return None if net is None else net.to(like.device)

    def forward(self, batch: dict) -> Tensor:
        """Reconstruction ``(B, 3, H, W)`` in ``[0, 1]`` from the batch's image codes and maps."""
        return (self._generate(batch)[0] + 1) / 2

    def _generate(self, batch: dict) -> tuple[Tensor, Tensor, Tensor, Tensor | None]:
        """``(fake in [-1, 1], real in [-1, 1], condition, region codes (N, code_dim) or None)``."""
        real = batch["image"] * 2 - 1
        cond = self.spec.condition(batch["label"], batch["boundary"])
        code_map, codes = None, None
        if self.spec.use_codes:
            code_map, codes, _, _ = self.encoder.encode(real, batch["instance_label_map"])
        x = self.spec.generator_input(cond, code_map, batch.get("pose"), batch.get("normal"))
        return self.generator(x), real, cond, codes

    def swap_term(self, batch: dict, real: Tensor, cond: Tensor, codes: Tensor) -> Tensor:
        """The code-swap colour term (module doc): mean over swapped objects of
        ``|mean colour of G(x with donor codes) on the object - mean colour of the donor in the real image|_1``.

        ``codes``: ``(N, code_dim)`` region codes of E, in :func:`~sdn3d.nets.pix2pixhd.region_index` order.
        """
        L = batch["instance_label_map"]
        index, _, ids = region_index(L)
        donors = code_donors(ids)
        swapped = codes[donors][index].permute(0, 3, 1, 2)
        fake = self.generator(self.spec.generator_input(cond, swapped, batch.get("pose"), batch.get("normal")))
        _, colors, _, _ = instance_mean(torch.cat([fake, real], 1), L)  # one scatter-mean for both pictures
        fake_colors, real_colors = colors[:, :3], colors[:, 3:]
        pixels = torch.bincount(index.reshape(-1), minlength=ids.numel())
        used = (donors != torch.arange(ids.numel(), device=ids.device)) & (pixels >= self.hparams.swap_min_pixels)
        if not bool(used.any()):
            return fake.sum() * 0  # no two objects of one class: keeps the graph, adds nothing
        return (fake_colors[used] - real_colors[donors[used]].detach()).abs().mean()

    # ----------------------------------------------------------------- training
    def on_fit_start(self) -> None:
        silence_step_checkpoint_warning()

    def training_step(self, batch: dict, batch_idx: int) -> None:
        opt_g, opt_d = self.optimizers()
        fake, real, cond, codes = self._generate(batch)
        d = self.discriminator
        d.requires_grad_(False)  # G's adversarial/FM terms need gradients w.r.t. the image, not D's weights
        pred_fake_g = d(torch.cat([cond, fake], 1))
        d.requires_grad_(True)
        pred_real = d(torch.cat([cond, real], 1))
        pred_fake_d = d(torch.cat([cond, fake.detach()], 1))

        terms = {
            "g_gan": lsgan_loss(pred_fake_g, True),
            "g_fm": feature_matching_loss(pred_fake_g, pred_real),
            "g_l1": F.l1_loss(fake, real),
        }
        loss_g = terms["g_gan"] + self.hparams.lambda_fm * terms["g_fm"] + self.hparams.lambda_recon * terms["g_l1"]
        perceptual = self._frozen_net("perceptual", fake)
        if perceptual is not None:
            terms["g_perceptual"] = perceptual((fake + 1) / 2, (real + 1) / 2)
            loss_g = loss_g + self.lambda_perceptual * terms["g_perceptual"]
        if self.hparams.lambda_swap > 0 and codes is not None:
            terms["g_swap"] = self.swap_term(batch, real, cond, codes)
            loss_g = loss_g + self.hparams.lambda_swap * terms["g_swap"]
        terms["d_real"] = lsgan_loss(pred_real, True)
        terms["d_fake"] = lsgan_loss(pred_fake_d, False)
        loss_d = 0.5 * (terms["d_real"] + terms["d_fake"])
        if not (self.guard_loss(loss_g, "loss_g") and self.guard_loss(loss_d, "loss_d")):
            return None

        opt_g.zero_grad(set_to_none=True)
        self.manual_backward(loss_g)
        opt_g.step()
        opt_d.zero_grad(set_to_none=True)
        self.manual_backward(loss_d)
        opt_d.step()
        self.g_updates += 1

        bs = real.shape[0]
        self.log("train/loss_g", loss_g.detach(), prog_bar=True, batch_size=bs)
        self.log("train/loss_d", loss_d.detach(), prog_bar=True, batch_size=bs)
        self.log_dict({f"train/{k}": v.detach() for k, v in terms.items()}, batch_size=bs)
        return None

    def on_fit_end(self) -> None:
        """Write the code bank of the best and of the last checkpoint next to each (``write_code_bank``); a bank
        depends only on E's weights, so one is encoded once when both checkpoints hold the same E."""
        trainer = self.trainer
        if not self.hparams.write_code_bank or not self.spec.use_codes or trainer.fast_dev_run or \
                not trainer.is_global_zero or trainer.interrupted:
            return
        callback = trainer.checkpoint_callback
        paths = sorted({str(p) for p in (getattr(callback, "best_model_path", ""),
                                         getattr(callback, "last_model_path", "")) if p and Path(p).is_file()})
        if not paths or not hasattr(trainer.datamodule, "code_bank_loader"):
            return
        loader = trainer.datamodule.code_bank_loader()
        built: list[tuple[dict[str, Tensor], CodeBank]] = []  # (E's weights, bank): the best is often the last
        for path in paths:
            encoder = TexturalRenderer.from_checkpoint(path, map_location=self.device).encoder
            weights = encoder.state_dict()
            bank = next((b for w, b in built if _same_weights(w, weights)), None)
            if bank is None:
                bank = build_code_bank(encoder, loader)
                built.append((weights, bank))
            written = save_code_bank(bank, code_bank_path(path), checkpoint=Path(path).name)
            log.info("code bank of %s: %d regions of %d classes -> %s", Path(path).name, len(bank),
                     len(bank.classes), written)

    def on_train_epoch_end(self) -> None:
        schedulers = self.lr_schedulers()
        for sch in schedulers if isinstance(schedulers, list) else [schedulers]:
            sch.step()  # manual optimisation: Lightning does not step schedulers

    def configure_optimizers(self):
        hp = self.hparams
        betas = (hp.beta1, hp.beta2)
        opt_g = torch.optim.Adam([*self.generator.parameters(), *self.encoder.parameters()], lr=hp.lr, betas=betas)
        opt_d = torch.optim.Adam(self.discriminator.parameters(), lr=hp.lr, betas=betas)
        decay = LinearDecay(hp.lr_constant_epochs, hp.lr_decay_epochs)
        schedulers = [{"scheduler": LambdaLR(o, decay), "interval": "epoch", "name": f"lr_{n}"}
                      for o, n in ((opt_g, "g"), (opt_d, "d"))]
        return [opt_g, opt_d], schedulers

    # --------------------------------------------------------------- evaluation
    def colorize(self, label: Tensor) -> Tensor:
        """``(B, H, W)`` classes -> ``(B, 3, H, W)`` class colours in ``[0, 1]`` (ignore: black)."""
        return self.palette[label.long().clamp(0, 255)].permute(0, 3, 1, 2)

    def _evaluate(self, batch: dict, batch_idx: int, stage: str) -> None:
        real = batch["image"]
        fake = self(batch).clamp(0, 1)
        bs = real.shape[0]
        lp = self._frozen_net("lpips", real)
        whole = image_metrics(fake, real, lpips_net=lp)
        for k, v in whole.items():
            self.log(f"{stage}/{k}", v.mean(), prog_bar=k == "psnr", batch_size=bs, sync_dist=True)
        objects = batch["instance_label_map"] >= INSTANCE_DIVISOR
        has = objects.flatten(1).any(1)
        if bool(has.any()):
            region = image_metrics(fake[has], real[has], objects[has], lpips_net=lp)
            for k, v in region.items():
                self.log(f"{stage}/obj_{k}", v.mean(), batch_size=int(has.sum()), sync_dist=True)
        if batch_idx == 0:
            n = min(bs, self.hparams.grid_samples)
            self.log_image_grid(f"{stage}/label_reconstruction_real",
                                [self.colorize(batch["label"][:n]), fake[:n], real[:n]], step=int(self.g_updates))

    def validation_step(self, batch: dict, batch_idx: int) -> None:
        self._evaluate(batch, batch_idx, "val")

    def test_step(self, batch: dict, batch_idx: int) -> None:
        self._evaluate(batch, batch_idx, "test")
