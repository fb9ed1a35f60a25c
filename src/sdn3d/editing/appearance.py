"""How an edited scene becomes a picture: the appearance interface, its two implementations, and the one place
that chooses between them (:func:`appearance_renderer`).

An appearance turns a de-rendered scene and its edit into the edited picture at the input's resolution, in two
calls (as a renderer of PyTorch3D's: settings fixed at construction, state passed in)::

    renderer = appearance_renderer(Appearance.PHOTO, photo=PhotoSettings(), textural=models.textural)
    state = renderer.prepare(original, frame, scene)      # SourceState: what the unedited scene alone decides
    drawn = renderer.draw(state, edited_scene, ops)       # Drawn: the picture (and what it was made of)
    drawn = renderer.draw(state, other_edit, other_ops)   # the same state again: bit-identical to a fresh one

:class:`Appearance` names the two:

- ``photo`` (:class:`PhotoRenderer`, the default): each edited object drawn with the input's own pixels through its
  fitted 3D shape (:func:`sdn3d.editing.photo.transfer.render_photo`; the generator only for ``fill='generator'``);
  its state keeps the source rasterization, the fitted light and the vacated-road fills
  (:class:`~sdn3d.editing.photo.transfer.PhotoSource`), made on the first draw.
- ``generator`` (:class:`GeneratorRenderer`, the paper's): the textural generator's picture of the edited scene's
  maps, composed into the input (:func:`sdn3d.editing.compose.compose_edit`: ``compose='edited'`` redraws only the
  edit region; ``'full'`` is the generator's whole picture at the working size); its state keeps the unedited
  scene's maps.

A third appearance implements :class:`AppearanceRenderer` and gets an entry in :data:`RENDERERS`; every caller
(:class:`~sdn3d.editing.session.EditSession`, :func:`~sdn3d.editing.render.edit_image`, the editing benchmark, the
demo, ``benchmarks/``) goes through :func:`appearance_renderer`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING, Protocol

from torch import Tensor

from sdn3d.editing.compose import (
    Compose,
    ComposeSettings,
    ComposeSettingsError,
    compose_edit,
    edited_object_ids,
)
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import EditOp
from sdn3d.editing.photo.recolor import paints
from sdn3d.editing.photo.settings import PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import PhotoResult, PhotoSource, render_photo
from sdn3d.editing.spec import EditSpec, code_bank_needed
from sdn3d.math3d.rotations import NUM_POSE_BINS
from sdn3d.meshes.bank import MeshBank
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import ComposedMaps, scene_maps

if TYPE_CHECKING:
    from sdn3d.textural.codes import CodeBank
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["Appearance", "APPEARANCES", "SourceState", "Drawn", "AppearanceRenderer", "PhotoRenderer",
           "GeneratorRenderer", "RENDERERS", "appearance_renderer", "PictureMode", "PICTURE_MODES",
           "picture_mode", "render_maps",
           "generate"]


class Appearance(StrEnum):
    """How edited objects are drawn (module doc). A ``str`` equal to its value (as :class:`sdn3d.proposals.Proposals`),
    so records and messages that wrote the name write the same."""

    PHOTO = "photo"
    GENERATOR = "generator"


#: The appearances' names (``appearance:`` of ``conf/edit.yaml``, ``edits.appearance`` of the demo).
APPEARANCES = tuple(a.value for a in Appearance)


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


def generate(scene: SceneCode, textural: TexturalRenderer, bank: MeshBank | None = None
             ) -> tuple[ComposedMaps, Tensor]:
    """``(maps, picture (3, h, w))``: ``scene``'s maps (:func:`~sdn3d.scene.maps.scene_maps`) and the generator's
    picture of them."""
    maps = scene_maps(scene, bank, num_bins=textural.spec.pose_bins)
    return maps, render_maps(maps, textural)


@dataclass(eq=False)
class SourceState:
    """What an appearance computes from the unedited scene alone, kept between edits of that scene (an interactive
    editor redraws only what changed). Pictures are the same bit for bit with a fresh state and a reused one.

    Attributes:
        original: ``(3, H_in, W_in)`` the input at its resolution (uint8 or float in [0, 1]).
        frame: how the input became the scene's working image.
        scene: the de-rendered scene.
        bank: its meshes (None: the default templates).
        photo: the photo appearance's state (:class:`~sdn3d.editing.photo.transfer.PhotoSource`), made on its first
            draw; None until then and for the generator.
    """

    original: Tensor
    frame: PixelFrame
    scene: SceneCode
    bank: MeshBank | None = None
    photo: PhotoSource | None = None
    _maps: dict[int, ComposedMaps] = field(default_factory=dict, repr=False)

    def source_maps(self, num_bins: int = NUM_POSE_BINS) -> ComposedMaps:
        """The unedited scene's maps with ``num_bins`` pose bins (made once)."""
        if num_bins not in self._maps:
            self._maps[num_bins] = scene_maps(self.scene, self.bank, num_bins=num_bins)
        return self._maps[num_bins]


@dataclass
class Drawn:
    """An edit drawn by an appearance.

    Attributes:
        image: ``(3, H_in, W_in)`` the edited picture at the input's resolution (the original's dtype for the photo
            appearance and ``compose='edited'``); ``compose='full'``: the generator's ``(3, h, w)`` float picture.
        generated: ``(3, h, w)`` float in [0, 1], the generator's picture of the edited scene (None: not run).
        maps: the edited scene's maps where the generator ran, else None.
        region: ``(h, w)`` bool pixels taken from the generator (``compose='edited'``), else None.
        photo: the photo appearance's :class:`~sdn3d.editing.photo.transfer.PhotoResult` (its ``source`` map says
            where each pixel came from), else None.
        edited_ids: ``(K,)`` ids of the objects the edit changed (generator), else None.
        times: wall times in ms of the steps run (``render_ms``: the generator; ``photo_ms``; ``compose_ms``).
    """

    image: Tensor
    generated: Tensor | None = None
    maps: ComposedMaps | None = None
    region: Tensor | None = None
    photo: PhotoResult | None = None
    edited_ids: Tensor | None = None
    times: dict[str, float] = field(default_factory=dict)


class AppearanceRenderer(Protocol):
    """An appearance (module doc): settings fixed at construction, the source state passed in."""

    appearance: Appearance

    @property
    def needs_generator(self) -> bool:
        """Whether :meth:`draw` runs the textural generator."""

    def check(self, spec: EditSpec, code_bank: CodeBank | None) -> None:
        """Raises :class:`~sdn3d.editing.ops.EditError` (naming the op) where ``spec``, resolved with ``code_bank``
        (:func:`~sdn3d.editing.spec.resolve_ops`), asks for what this appearance cannot draw; called right after
        resolving, before anything is drawn."""

    def prepare(self, original: Tensor, frame: PixelFrame, scene: SceneCode,
                bank: MeshBank | None = None) -> SourceState:
        """The state of the unedited ``scene`` (``original (3, H_in, W_in)`` the input, ``frame`` its transform,
        ``bank`` its meshes)."""

    def draw(self, state: SourceState, edited: SceneCode, ops: Sequence[EditOp] = (),
             generated: tuple[ComposedMaps, Tensor] | None = None) -> Drawn:
        """``edited`` (``state.scene`` after ``ops``) drawn. ``generated``: the edited scene's maps and the generator's
        picture when the caller already made them (:func:`generate`); else made here where needed."""


def _timed(times: dict[str, float], key: str, fn: Callable, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    times[key] = 1000 * (time.perf_counter() - t0)
    return out


@dataclass(frozen=True)
class PhotoRenderer:
    """The photo appearance (module doc). textural: the generator, for ``settings.fill == 'generator'`` only."""

    settings: PhotoSettings = field(default_factory=PhotoSettings)
    textural: TexturalRenderer | None = None
    appearance: Appearance = Appearance.PHOTO

    @property
    def needs_generator(self) -> bool:
        return self.settings.fill == "generator"

    def check(self, spec: EditSpec, code_bank: CodeBank | None) -> None:
        """Everything resolved is drawable: a named colour repaints the car's own pixels (no code bank needed)."""

    def prepare(self, original: Tensor, frame: PixelFrame, scene: SceneCode,
                bank: MeshBank | None = None) -> SourceState:
        return SourceState(original, frame, scene, bank)

    def draw(self, state: SourceState, edited: SceneCode, ops: Sequence[EditOp] = (),
             generated: tuple[ComposedMaps, Tensor] | None = None) -> Drawn:
        times: dict[str, float] = {}
        if generated is None and self.needs_generator:
            if self.textural is None:
                raise PhotoSettingsError("photo.fill=generator needs the generator's picture (the textural branch)")
            generated = _timed(times, "render_ms", generate, edited, self.textural, state.bank)
        maps, picture = generated if generated is not None else (None, None)
        t0 = time.perf_counter()
        if state.photo is None:
            state.photo = PhotoSource(state.original, state.frame, state.scene, state.bank, self.settings)
        result = render_photo(state.original, state.frame, state.scene, edited, state.bank, self.settings,
                              paints(ops), picture, source=state.photo)
        times["photo_ms"] = 1000 * (time.perf_counter() - t0)
        return Drawn(result.image, picture, maps, photo=result, times=times)


@dataclass(frozen=True)
class GeneratorRenderer:
    """The generator appearance (module doc): the textural generator, composed by ``compose``."""

    compose: ComposeSettings = field(default_factory=ComposeSettings)
    textural: TexturalRenderer | None = None
    appearance: Appearance = Appearance.GENERATOR

    @property
    def needs_generator(self) -> bool:
        return True

    def check(self, spec: EditSpec, code_bank: CodeBank | None) -> None:
        """A named colour is drawn through a bank code of that colour: without a code bank, an error."""
        code_bank_needed(spec, code_bank)

    def prepare(self, original: Tensor, frame: PixelFrame, scene: SceneCode,
                bank: MeshBank | None = None) -> SourceState:
        return SourceState(original, frame, scene, bank)

    def draw(self, state: SourceState, edited: SceneCode, ops: Sequence[EditOp] = (),
             generated: tuple[ComposedMaps, Tensor] | None = None) -> Drawn:
        times: dict[str, float] = {}
        if generated is None:
            if self.textural is None:
                raise ValueError("appearance=generator needs the textural branch (models.textural is None)")
            generated = _timed(times, "render_ms", generate, edited, self.textural, state.bank)
        maps, picture = generated
        bins = self.textural.spec.pose_bins if self.textural is not None else NUM_POSE_BINS
        t0 = time.perf_counter()
        before = state.source_maps(bins) if self.compose.mode == "edited" else maps
        original = state.original if self.compose.mode == "edited" else None
        ids = edited_object_ids(state.scene.objects, edited.objects)
        image, region = compose_edit(self.compose, picture, original, state.frame, before, maps, ids)
        times["compose_ms"] = 1000 * (time.perf_counter() - t0)
        return Drawn(image, picture, maps, region, edited_ids=ids, times=times)


#: The implementation of each appearance; its keyword arguments are :func:`appearance_renderer`'s.
RENDERERS: dict[Appearance, Callable[..., AppearanceRenderer]] = {
    Appearance.PHOTO: lambda photo, compose, textural: PhotoRenderer(photo or PhotoSettings(), textural),
    Appearance.GENERATOR: lambda photo, compose, textural: GeneratorRenderer(compose or ComposeSettings(), textural),
}


def appearance_renderer(appearance: Appearance | str, *, photo: PhotoSettings | None = None,
                        compose: ComposeSettings | None = None,
                        textural: TexturalRenderer | None = None) -> AppearanceRenderer:
    """The renderer of ``appearance`` (the one place an appearance is chosen).

    Args:
        appearance: :class:`Appearance` or its name (:data:`APPEARANCES`).
        photo: the photo appearance's settings; compose: the generator's (None: defaults).
        textural: the textural generator (the generator appearance; the photo one with ``fill='generator'``).

    Raises:
        PhotoSettingsError: an unknown appearance.
    """
    try:
        mode = Appearance(appearance.value if isinstance(appearance, Appearance) else appearance)
    except ValueError:
        raise PhotoSettingsError(f"appearance must be one of {APPEARANCES}, got {appearance!r}") from None
    return RENDERERS[mode](photo, compose, textural)


class PictureMode(StrEnum):
    """The editing benchmark's picture modes (:mod:`sdn3d.evaluation.edit_benchmark`): ``photo``, the photo
    appearance, or a compose mode of :mod:`sdn3d.editing.compose` (``edited``, ``full``), the generator appearance
    composed so. A ``str`` equal to its value."""

    PHOTO = Appearance.PHOTO.value
    EDITED = Compose.EDITED.value
    FULL = Compose.FULL.value

    @classmethod
    def parse(cls, value: object) -> PictureMode:
        """``value`` (a name, or a :class:`PictureMode`) as a :class:`PictureMode`.

        Raises:
            ComposeSettingsError: not a picture mode.
        """
        if not isinstance(value, str) or value not in PICTURE_MODES:
            raise ComposeSettingsError(f"a picture mode must be one of {PICTURE_MODES}, got {value!r}")
        return cls(value)


#: The picture modes' names, in the order messages list them.
PICTURE_MODES = tuple(m.value for m in PictureMode)


def picture_mode(mode: PictureMode | str, compose: ComposeSettings | None = None
                 ) -> tuple[Appearance, ComposeSettings | None]:
    """``(appearance, its compose settings or None)`` of a picture mode (:class:`PictureMode` or its name), for
    :func:`appearance_renderer`; ``compose``: the dilation and feathering of the generator's modes (None: defaults).

    Raises:
        ComposeSettingsError: not a picture mode (or bad compose settings).
    """
    mode = PictureMode.parse(mode)
    if mode is PictureMode.PHOTO:
        return Appearance.PHOTO, None
    base = compose or ComposeSettings()
    return Appearance.GENERATOR, ComposeSettings(Compose(mode), base.dilate_px, base.feather_px)
