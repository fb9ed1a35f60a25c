"""TexturalModule: pix2pixHD training of the textural branch (generator G, encoder E, discriminator D).

Losses (3D-SDN textural code, pix2pixHD):

- D: ``0.5 * (LSGAN(D(c, G(x)), fake) + LSGAN(D(c, I), real))``, summed over the 2 scales.
- G and E: ``LSGAN(D(c, G(x)), real) + lambda_fm * FM + lambda_vgg * VGG + lambda_recon * |G(x) - I|_1``
  with FM the discriminator feature matching, VGG the VGG-19 perceptual loss (only when
  ``vgg_weights`` names a file; otherwise off and logged as such), the L1 on ``[-1, 1]`` images.
  Paper: lambda_FM = 5, lambda_Recon = 10; the perceptual term uses lambda_FM like 3D-SDN's code
  (``lambda_vgg=None``).

``x`` is the generator input (semantic one-hot, instance boundaries, E's per-instance code map,
pose map, normal map; see :class:`sdn3d.nets.pix2pixhd.TexturalSpec`), ``c`` the discriminator
condition (one-hot + boundaries).

Optimisation is manual: one G/E Adam step then one D Adam step per batch (lr 2e-4, betas
(0.5, 0.999)), constant for ``lr_constant_epochs`` epochs then linear decay to 0 over
``lr_decay_epochs`` (stepped at each epoch end). Step counts: **Lightning's ``global_step`` counts
optimizer steps, i.e. 2 per batch** (so ``trainer.max_steps = 2 * N`` trains N batches); logged
scalars use Lightning's logger step, which counts batches (= G updates), and the image grids use
the ``g_updates`` buffer (G updates, saved in checkpoints so that a resumed run continues it).
"""

from __future__ import annotations

import logging
import warnings

import torch
import torch.nn.functional as F
from torch import Tensor
from torch.optim.lr_scheduler import LambdaLR

from lightning_modules._base import BranchModule
from sdn3d.evaluation.image_metrics import image_metrics
from sdn3d.labels import INSTANCE_DIVISOR, class_list
from sdn3d.nets.lpips import load_lpips
from sdn3d.nets.pix2pixhd import TexturalSpec, feature_matching_loss, lsgan_loss
from sdn3d.nets.vgg import VGGPerceptualLoss

__all__ = ["LinearDecay", "TexturalModule"]

log = logging.getLogger(__name__)



def silence_step_checkpoint_warning() -> None:
    """Ignore Lightning's warning that step-interval checkpoints of a manually optimised module hold the
    weights after the step (called when fitting starts).

    For this module that is the right state: those checkpoints are for resuming (weights, optimiser moments
    and step counters must all be from after the same step), never for picking a model by a training
    metric. Only this exact message is silenced.
    """
    warnings.filterwarnings("ignore", message=r"Using ModelCheckpoint with manual optimization and "
                            r"every_n_train_steps", category=UserWarning)


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
        lambda_fm, lambda_recon: loss weights (paper 5, 10); lambda_vgg: None = lambda_fm.
        lr, beta1, beta2: Adam for both optimizers.
        lr_constant_epochs, lr_decay_epochs: linear decay schedule (pix2pixHD 100 + 100).
        vgg_weights: torchvision VGG-19 state dict file (None: no perceptual loss).
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
        lambda_vgg: float | None = None,
        lr: float = 2e-4,
        beta1: float = 0.5,
        beta2: float = 0.999,
        lr_constant_epochs: int = 100,
        lr_decay_epochs: int = 100,
        vgg_weights: str | None = None,
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
        self.lambda_vgg = lambda_fm if lambda_vgg is None else lambda_vgg
        # Frozen pretrained nets sit in a plain dict: not submodules, so not in checkpoints
        # (they come from their own files) and a run without them has the same state-dict keys.
        self._frozen = {"vgg": VGGPerceptualLoss.from_file(vgg_weights), "lpips": load_lpips(lpips_weights)}
        if self._frozen["vgg"] is None:
            log.warning("TexturalModule: training WITHOUT the VGG perceptual term (vgg_weights=null)")
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

    def _generate(self, batch: dict) -> tuple[Tensor, Tensor, Tensor]:
        """``(fake in [-1, 1], real in [-1, 1], condition)``."""
        real = batch["image"] * 2 - 1
        cond = self.spec.condition(batch["label"], batch["boundary"])
        codes = self.encoder(real, batch["instance_label_map"]) if self.spec.use_codes else None
        x = self.spec.generator_input(cond, codes, batch.get("pose"), batch.get("normal"))
        return self.generator(x), real, cond

    # ----------------------------------------------------------------- training
    def on_fit_start(self) -> None:
        silence_step_checkpoint_warning()

    def training_step(self, batch: dict, batch_idx: int) -> None:
        opt_g, opt_d = self.optimizers()
        fake, real, cond = self._generate(batch)
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
        vgg = self._frozen_net("vgg", fake)
        if vgg is not None:
            terms["g_vgg"] = vgg((fake + 1) / 2, (real + 1) / 2)
            loss_g = loss_g + self.lambda_vgg * terms["g_vgg"]
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
