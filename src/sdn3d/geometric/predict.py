"""From raw network outputs to object attributes, and a predictor built from a training checkpoint.

:func:`decode_outputs` turns :class:`~sdn3d.geometric.model.GeometricNet` outputs into metric
attributes (differentiable: the training loop uses it for the reprojection loss);
:class:`GeometricPredictor` loads a Lightning checkpoint of ``lightning_modules.GeometricModule``
without importing Lightning; :func:`render_objects` draws predictions into scene maps.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import torch
from torch import Tensor

from sdn3d.geometric.model import GeometricNet
from sdn3d.math3d.camera import intrinsics_matrix
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.rotations import observation_angle
from sdn3d.math3d.transforms import center_to_bottom
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.render.maps import SceneMaps, render_scene_maps
from sdn3d.render.objects import pose_meshes
from sdn3d.render.settings import RasterSettings

if TYPE_CHECKING:
    from sdn3d.geometric.refine import RefineSettings

__all__ = [
    "as_intrinsics_matrix",
    "template_distribution",
    "decode_outputs",
    "net_kwargs_from_hparams",
    "GeometricPredictor",
    "render_objects",
]


def as_intrinsics_matrix(K: Tensor, batch: int | None = None) -> Tensor:
    """``(N, 4)`` vectors ``(fx, fy, cx, cy)``, ``(N, 3, 3)`` or ``(3, 3)`` -> ``(N, 3, 3)`` matrices.

    ``batch`` expands a single ``(3, 3)`` / ``(4,)`` calibration to ``N`` objects.
    """
    if K.dim() == 1 and K.shape[0] == 4:
        K = K.unsqueeze(0)
    if K.dim() == 2 and K.shape[1] == 4:
        K = intrinsics_matrix(K[:, 0], K[:, 1], K[:, 2], K[:, 3])
    elif K.dim() == 2 and K.shape == (3, 3):
        K = K.unsqueeze(0)
    elif K.dim() != 3 or K.shape[1:] != (3, 3):
        raise ValueError(f"K must have shape (N, 4) as (fx, fy, cx, cy), (N, 3, 3) or (3, 3), got {tuple(K.shape)}")
    if batch is not None:
        if K.shape[0] not in (1, batch):
            raise ValueError(f"K has {K.shape[0]} calibrations but there are {batch} objects")
        K = K.expand(batch, 3, 3)
    return K


def template_distribution(logits: Tensor, templates: Tensor, num_meshes: int = len(TEMPLATE_NAMES)) -> Tensor:
    """Softmax of ``(N, T)`` logits scattered to ``(N, num_meshes)`` mesh-id probabilities."""
    probs = logits.softmax(dim=-1)
    out = probs.new_zeros(probs.shape[0], num_meshes)
    return out.index_copy(1, templates.to(probs.device), probs)


def decode_outputs(
    raw: Mapping[str, Tensor],
    box: Tensor,
    K: Tensor,
    encoding: AttributeEncoding | None = None,
    templates: Tensor | None = None,
) -> dict[str, Tensor]:
    """Metric attributes from raw outputs (differentiable w.r.t. ``raw``).

    Args:
        raw: :meth:`GeometricNet.forward` outputs.
        box: ``(N, 4)`` 2D boxes in pixels of the image ``K`` describes.
        K: that image's intrinsics, ``(N, 4)`` ``(fx, fy, cx, cy)``, ``(N, 3, 3)`` or ``(3, 3)``.
        encoding: the target parameterisation the net was trained with (paper default).
        templates: ``(T,)`` mesh ids of the logits (``GeometricNet.templates``); default ``arange(T)``.

    Returns:
        ``dims (N, 3)`` as ``(l, h, w)``; ``ry (N,)``; ``center (N, 3)`` box centre and ``location
        (N, 3)`` bottom-face centre (camera frame); ``template_id (N,)`` (argmax mesh id);
        ``template_probs (N, M)`` with ``M = max(8, max id + 1)``; ``phi (N, 64, 3)``.
    """
    encoding = encoding or AttributeEncoding()
    n = box.shape[0]
    dims, ry, center = encoding.decode(raw, box, as_intrinsics_matrix(K, n).to(box.dtype))
    logits = raw["template_logits"]
    if templates is None:
        templates = torch.arange(logits.shape[1], device=logits.device)
    probs = template_distribution(logits, templates, max(len(TEMPLATE_NAMES), int(templates.max()) + 1))
    return {
        "dims": dims,
        "ry": ry,
        "center": center,
        "location": center_to_bottom(center, dims[:, 1]),
        "template_id": templates.to(logits.device)[logits.argmax(dim=1)],
        "template_probs": probs,
        "phi": raw["phi"],
    }


# Constructor arguments of GeometricNet read from the module's hyper-parameters.
_NET_ARGS = ("rotation", "hidden", "scale_prior")


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
    """

    def __init__(self, net: GeometricNet, encoding: AttributeEncoding | None = None) -> None:
        self.net = net.eval()
        self.bank: MeshBank | None = None  # built on first use
        self.encoding = encoding or AttributeEncoding(rotation=net.rotation)
        if self.encoding.rotation != net.rotation:
            raise ValueError(f"encoding.rotation={self.encoding.rotation!r} does not match the net's {net.rotation!r}")

    @classmethod
    def from_checkpoint(cls, path: str | Path, map_location: str | torch.device = "cpu") -> GeometricPredictor:
        """Load a ``GeometricModule`` Lightning checkpoint (``torch.load(weights_only=True)``).

        Uses its ``hyper_parameters`` (rotation, distance, single_cad, ...) to rebuild the net and
        the ``net.``-prefixed entries of its ``state_dict``.
        """
        from sdn3d.io import load_lightning_checkpoint

        path = Path(path).expanduser()
        ckpt = load_lightning_checkpoint(path, map_location)
        hparams = dict(ckpt.get("hyper_parameters") or {})
        net = GeometricNet(**net_kwargs_from_hparams(hparams))
        state = {k[len("net."):]: v for k, v in ckpt["state_dict"].items() if k.startswith("net.")}
        if not state:
            raise ValueError(f"{str(path)!r} has no 'net.' weights: not a GeometricModule checkpoint")
        net.load_state_dict(state, strict=True)
        encoding = AttributeEncoding(hparams.get("rotation", "yaw_quaternion"), hparams.get("distance", "log_tau"))
        return cls(net.to(map_location), encoding)

    @property
    def device(self) -> torch.device:
        return next(self.net.parameters()).device

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
        """
        from sdn3d.geometric.losses import render_silhouettes  # these import this module
        from sdn3d.geometric.refine import refine_by_reprojection

        device = self.device
        crop, box, intrinsics = crop.to(device), box.to(device), intrinsics.to(device)
        if mask is not None:
            crop = crop * mask.to(device)
        raw = self.net(crop, box, intrinsics)
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
        if crop_intrinsics is not None:
            out["silhouette"] = render_silhouettes(
                bank, out["template_id"], out["dims"], out["ry"], out["center"],
                out["phi"], crop_intrinsics.to(device), crop.shape[-1],
            )
        return out


def render_objects(
    pred: Mapping[str, Tensor],
    intrinsics: Tensor,
    image_size: tuple[int, int],
    mesh_to_image: Tensor | None = None,
    batch_size: int | None = None,
    instance_ids: Tensor | None = None,
    bank: MeshBank | None = None,
    settings: RasterSettings | None = None,
) -> SceneMaps:
    """Instance, depth, normal and pose maps of predicted objects (hard rasterizer).

    Args:
        pred: :meth:`GeometricPredictor.predict` / :func:`decode_outputs` output (``dims``, ``ry``,
            ``center``, ``template_id``, ``phi``) for ``N`` objects.
        intrinsics: ``(B, 4)``, ``(B, 3, 3)`` or shared ``(3, 3)`` / ``(4,)`` intrinsics of the images.
        image_size: ``(H, W)`` of the images.
        mesh_to_image: ``(N,)`` image of each object (default: all in image 0).
        batch_size: number of images ``B`` (default ``mesh_to_image.max() + 1``).
        instance_ids: ``(N,)`` ids written into the instance map (default ``1 .. N``).
        bank: the meshes ``template_id`` indexes (default: the 8 procedural templates).
        settings: rasterizer settings (default ``RasterSettings(image_size)``).
    """
    dims, ry, center = pred["dims"], pred["ry"], pred["center"]
    n, device = dims.shape[0], dims.device
    bank = (bank or MeshBank.templates()).to(device)
    if mesh_to_image is None:
        mesh_to_image = torch.zeros(n, dtype=torch.long, device=device)
    if batch_size is None:
        batch_size = int(mesh_to_image.max()) + 1 if n else 1
    if instance_ids is None:
        instance_ids = torch.arange(1, n + 1, device=device)
    K = as_intrinsics_matrix(intrinsics.to(device))
    if K.shape[0] == 1:
        K = K.expand(batch_size, 3, 3)
    verts, faces = pose_meshes(bank, pred["template_id"].long(), dims, ry, center, pred.get("phi"))
    alpha = observation_angle(ry, center[:, 0], center[:, 2])
    return render_scene_maps(
        verts.detach(), faces, K, settings or RasterSettings(tuple(image_size)), instance_ids, alpha.detach(),
        mesh_to_image, batch_size,
    )
