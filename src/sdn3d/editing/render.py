"""Drawing a (possibly edited) :class:`~sdn3d.scene.code.SceneCode` with the textural generator, and
editing an image end to end (3D-SDN, Fig. 2, right half).

:func:`render_maps` runs the generator on composed maps, :func:`render` draws a scene
(:func:`sdn3d.scene.maps.scene_maps` + :func:`render_maps`), :func:`edit_image` chains
:func:`sdn3d.derender.derender`, :func:`sdn3d.editing.apply.apply_edits` and :func:`render`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

from torch import Tensor

from sdn3d.data.edit_benchmark import BenchmarkEntry, BenchmarkOperation
from sdn3d.derender import GroundTruth, Models, derender
from sdn3d.editing.apply import EditOp, apply_edits, ops_from_benchmark
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import MeshBank
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import ComposedMaps, scene_maps

if TYPE_CHECKING:
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["EditResult", "render_maps", "render", "edit_image"]


class EditResult(NamedTuple):
    """Output of :func:`edit_image`: ``edited (3, H, W)``, the scenes before / after and the edited maps."""

    edited: Tensor
    scene: SceneCode
    edited_scene: SceneCode
    maps: ComposedMaps


def render_maps(maps: ComposedMaps, textural: TexturalRenderer) -> Tensor:
    """``(3, H, W)`` image in ``[0, 1]`` the generator draws from composed maps (their code map included)."""
    if textural is None:
        raise ValueError("rendering needs the textural branch (models.textural is None)")
    spec = textural.spec
    if spec.use_codes and maps.feature.shape[0] != spec.code_dim:
        raise ValueError(f"the scene's texture codes have {maps.feature.shape[0]} values, the generator "
                         f"expects {spec.code_dim}")
    dev = textural.device
    out = textural.render(maps.label[None].to(dev), maps.instance_label_map[None].to(dev),
                          maps.boundary[None].to(dev), code_map=maps.feature[None].to(dev),
                          pose=maps.pose[None].to(dev), normal=maps.normal[None].to(dev))
    return out[0].clamp(0, 1)


def render(scene: SceneCode, textural: TexturalRenderer, bank: MeshBank | None = None) -> Tensor:
    """Draw ``scene``: ``(3, H, W)`` in ``[0, 1]`` (:func:`scene_maps` + the textural generator)."""
    if textural is None:
        raise ValueError("rendering needs the textural branch (models.textural is None)")
    return render_maps(scene_maps(scene, bank, num_bins=textural.spec.pose_bins), textural)


def edit_image(image: Tensor, intrinsics: Intrinsics,
               ops: Sequence[EditOp] | BenchmarkEntry | Sequence[BenchmarkOperation], models: Models,
               proposals: str = "auto", ground_truth: GroundTruth | None = None,
               frame_size: tuple[int, int] | None = None, strict: bool = True, bank: MeshBank | None = None,
               **derender_kwargs) -> EditResult:
    """De-render ``image``, apply ``ops`` and render the edited scene.

    Args:
        ops: :mod:`sdn3d.editing.apply` operations, or benchmark operations / an entry (objects picked by
            :func:`~sdn3d.editing.apply.ops_from_benchmark`, coordinates in ``frame_size`` pixels; None = image pixels).
        strict: reject benchmark ``to`` points outside the frame.
        derender_kwargs: passed to :func:`derender`.
    """
    if models.textural is None:
        raise ValueError("edit_image needs the textural branch (models.textural is None)")
    scene = derender(image, intrinsics, models, proposals, ground_truth, **derender_kwargs)
    ops = list(ops.operations) if isinstance(ops, BenchmarkEntry) else list(ops)
    if ops and all(isinstance(op, BenchmarkOperation) for op in ops):
        ops = ops_from_benchmark(ops, scene, frame_size, strict)
    edited_scene = apply_edits(scene, ops, bank)
    maps = scene_maps(edited_scene, bank, num_bins=models.textural.spec.pose_bins)
    return EditResult(render_maps(maps, models.textural), scene, edited_scene, maps)

