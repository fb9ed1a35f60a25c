"""Dense reference of applying edits: the pixels an edit frees found by composing every observed object
over the whole frame (:func:`sdn3d.reference.scene_maps.dense_layers`), for tests and
``benchmarks/edit_latency.py``."""

from __future__ import annotations

from collections.abc import Sequence

import torch
from torch import Tensor

from sdn3d.editing.apply import _apply_edits, _grow
from sdn3d.editing.ops import EditOp
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.reference.scene_maps import dense_layers
from sdn3d.scene.code import SceneCode

__all__ = ["apply_edits_dense", "footprints_dense"]


def apply_edits_dense(scene: SceneCode, ops: Sequence[EditOp], bank: MeshBank | None = None,
                      grow: int = 2) -> SceneCode:
    """:func:`sdn3d.editing.apply.apply_edits` with the freed pixels of :func:`footprints_dense`."""
    return _apply_edits(scene, ops, bank, grow, footprints_dense)


def footprints_dense(scene: SceneCode, vacate: Tensor, bank: MeshBank | None, grow: int) -> Tensor:
    """:func:`sdn3d.editing.apply._footprints` as it was: the observed objects always composed (dense
    reference renderer)."""
    obj = scene.objects
    observed = scene.replace(objects=obj.select(obj.observed))
    layers = dense_layers(observed, bank or default_bank(), None)
    ids = observed.objects.instance_id.to(layers.winner.device)
    inst = torch.where(layers.visible, ids[layers.winner] if len(ids) else 0, 0).cpu()
    region = torch.isin(inst, obj.instance_id[vacate]) | obj.mask[vacate & obj.has_mask].any(0)
    return _grow(scene, vacate, region, inst != 0, grow)
