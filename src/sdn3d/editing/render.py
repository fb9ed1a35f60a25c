"""Drawing a (possibly edited) :class:`~sdn3d.scene.code.SceneCode`, and editing an image end to end (3D-SDN,
Fig. 2, right half): the library's Python entry.

:func:`render` draws a scene with the textural generator (:func:`sdn3d.scene.maps.scene_maps` +
:func:`sdn3d.editing.appearance.render_maps`); :func:`edit_image` chains :func:`sdn3d.derender.derender`,
:func:`sdn3d.editing.apply.apply_edits` and an appearance (:func:`sdn3d.editing.appearance.appearance_renderer`):
``'photo'`` (the default) draws each edited object with the input's own pixels through its fitted 3D shape at the
input's resolution (no generator needed); ``'generator'`` (the paper's) draws with the textural generator, composed
into the input (by default only the edited region redrawn, at the input's resolution; ``compose='full'``: the
generator's whole picture).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

from torch import Tensor

from sdn3d.data.edit_benchmark import BenchmarkEntry, BenchmarkOperation
from sdn3d.derender import GroundTruth, Models, derender
from sdn3d.editing.appearance import Appearance, appearance_renderer, generate, render_maps
from sdn3d.editing.apply import EditOp, apply_edits, ops_from_benchmark
from sdn3d.editing.compose import ComposeSettings
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.inputs import same_aspect
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import PhotoResult
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.rotations import NUM_POSE_BINS
from sdn3d.meshes.bank import MeshBank
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import ComposedMaps, scene_maps

if TYPE_CHECKING:
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["EditResult", "render", "edit_image"]


class EditResult(NamedTuple):
    """Output of :func:`edit_image`.

    Attributes:
        edited: the result: ``appearance='photo'``: ``(3, H_in, W_in)`` (``original``'s dtype); ``'generator'``
            with ``compose='edited'``: the input with the edit region redrawn, same shape; ``'full'``: ``generated``.
        generated: ``(3, H, W)`` in [0, 1], the generator's whole edited picture at the working size (None when
            the photo appearance needed none).
        region: ``(H, W)`` bool edit region (working size; None with ``compose='full'`` and with the photo
            appearance, whose :attr:`photo` ``.source`` says where each pixel came from).
        scene, edited_scene: the scenes before / after; maps: the edited scene's maps.
        photo: the photo appearance's :class:`~sdn3d.editing.photo.PhotoResult` (None with the generator).
    """

    edited: Tensor
    generated: Tensor | None
    region: Tensor | None
    scene: SceneCode
    edited_scene: SceneCode
    maps: ComposedMaps
    photo: PhotoResult | None = None


def render(scene: SceneCode, textural: TexturalRenderer, bank: MeshBank | None = None) -> Tensor:
    """Draw ``scene``: ``(3, H, W)`` in ``[0, 1]`` (:func:`scene_maps` + the textural generator)."""
    if textural is None:
        raise ValueError("rendering needs the textural branch (models.textural is None)")
    return render_maps(scene_maps(scene, bank, num_bins=textural.spec.pose_bins), textural)


def edit_image(image: Tensor, intrinsics: Intrinsics,
               ops: Sequence[EditOp] | BenchmarkEntry | Sequence[BenchmarkOperation], models: Models,
               proposals: str = "auto", ground_truth: GroundTruth | None = None,
               frame_size: tuple[int, int] | None = None, strict: bool = True, bank: MeshBank | None = None,
               compose: ComposeSettings | str = "edited", original: Tensor | None = None,
               transform: PixelFrame | None = None, appearance: Appearance | str = "photo",
               photo: PhotoSettings | None = None,
               **derender_kwargs) -> EditResult:
    """De-render ``image``, apply ``ops`` and draw the edit in ``appearance`` (module doc).

    Args:
        image: ``(3, H, W)`` float in [0, 1] at the working size.
        ops: :mod:`sdn3d.editing.apply` operations, or benchmark operations / an entry (objects picked by
            :func:`~sdn3d.editing.apply.ops_from_benchmark`, coordinates in ``frame_size`` pixels; None = image pixels).
        strict: reject benchmark ``to`` points outside the frame.
        compose: ``'edited'`` / ``'full'`` or :class:`~sdn3d.editing.compose.ComposeSettings` (module doc;
            the generator appearance only).
        appearance: ``'photo'`` (default) or ``'generator'`` (module doc); photo: its settings.
        original: ``(3, H_in, W_in)`` the input at its own resolution (uint8 or float); None: ``image``.
        transform: how ``original`` became ``image`` (:func:`sdn3d.editing.inputs.fit_image`'s); None: a plain
            resize, which needs the same aspect ratio.
        derender_kwargs: passed to :func:`derender`.
    """
    photo = photo or PhotoSettings()
    settings = compose if isinstance(compose, ComposeSettings) else ComposeSettings(mode=compose)
    renderer = appearance_renderer(appearance, photo=photo, compose=settings, textural=models.textural)
    if renderer.needs_generator and models.textural is None:
        raise ValueError(f"appearance={renderer.appearance.value!r} with fill={photo.fill!r} needs the textural "
                         "branch (models.textural is None)")
    original, transform = _input_frame(image, original, transform)
    scene = derender(image, intrinsics, models, proposals, ground_truth, **derender_kwargs)
    ops = list(ops.operations) if isinstance(ops, BenchmarkEntry) else list(ops)
    if ops and all(isinstance(op, BenchmarkOperation) for op in ops):
        ops = ops_from_benchmark(ops, scene, frame_size, strict)
    edited_scene = apply_edits(scene, ops, bank)
    generated = generate(edited_scene, models.textural, bank) if renderer.needs_generator else None
    drawn = renderer.draw(renderer.prepare(original, transform, scene, bank), edited_scene, ops, generated)
    maps = drawn.maps
    if maps is None:
        bins = models.textural.spec.pose_bins if models.textural is not None else NUM_POSE_BINS
        maps = scene_maps(edited_scene, bank, num_bins=bins)
    return EditResult(drawn.image, drawn.generated, drawn.region, scene, edited_scene, maps, drawn.photo)


def _input_frame(image: Tensor, original: Tensor | None, transform: PixelFrame | None) -> tuple[Tensor, PixelFrame]:
    """``(original (3, H_in, W_in), transform)`` of :func:`edit_image`'s arguments (checked)."""
    size = (int(image.shape[-1]), int(image.shape[-2]))
    if original is None:
        if transform is not None:
            raise ValueError("edit_image: a transform needs the original it maps from")
        return image, PixelFrame(size, size)
    if original.dim() != 3 or original.shape[0] != 3:
        raise ValueError(f"edit_image: original must be (3, H, W), got {tuple(original.shape)}")
    input_size = (int(original.shape[-1]), int(original.shape[-2]))
    if transform is None:
        if not same_aspect(input_size, size):
            raise ValueError(f"edit_image: the original {input_size[0]}x{input_size[1]} and the image "
                             f"{size[0]}x{size[1]} differ in aspect ratio: give the transform (fit_image's)")
        transform = PixelFrame(input_size, size)
    if tuple(transform.input_size) != input_size or tuple(transform.working_size) != size:
        raise ValueError(f"edit_image: the transform maps {tuple(transform.input_size)} to "
                         f"{tuple(transform.working_size)}, not the original {input_size} to the image {size}")
    return original, transform
