"""The photo appearance's surface transfer and its pipeline (:func:`render_photo`; steps 1, 3 and 6 of
:mod:`sdn3d.editing.photo`): who owns each pixel, each edited object's pixels carried from its source pose.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.frame import PixelFrame, input_intrinsics, input_window, upsample_ids, working_to_input
from sdn3d.editing.photo.fill import (
    fill_hole,
    inpaint,
    relight_faint_shadow,
    relight_shadow,
    removal_guides,
    shadow_gain,
    shadow_pieces,
    vacated_hole,
)
from sdn3d.editing.photo.light import LightEstimate, fit_light, fit_reflection, grazing
from sdn3d.editing.photo.nearest import nearest_examples
from sdn3d.editing.photo.occluders import thin_occluders
from sdn3d.editing.photo.recolor import (
    DARK_PAINT_L,
    body_paint,
    body_pixels,
    ground_in_mask,
    recolor_pixels,
    registered_tyres,
    srgb_to_lab,
)
from sdn3d.editing.photo.road import PictureLab, road_colours, road_like
from sdn3d.editing.photo.settings import (
    ANOTHER_CAR,
    DEFAULT,
    FALLBACK,
    FILL,
    FLAT_CODES,
    IN_FRONT,
    INPUT,
    MIRROR,
    PART,
    PART_DEFAULTS,
    PHOTO,
    RAY_FILLS,
    RECOLORED,
    RELIT,
    SHADOW,
    SOURCE_NAMES,
    PhotoSettings,
    PhotoSettingsError,
)
from sdn3d.image_ops import (
    any_along,
    any_set,
    dilate_square,
    flat_nonzero,
    id_counts,
    ids_present,
    isin_ids,
    luminance,
    mask_boxes,
    nonzero_yx,
)
from sdn3d.math3d.rotations import observation_angle, roty, wrap_angle
from sdn3d.math3d.sums import sum3
from sdn3d.math3d.transforms import box_corners
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.meshes.parts import Part, greenhouse_glass
from sdn3d.meshes.templates import TEMPLATE_NAMES, TEMPLATE_SPECS
from sdn3d.meshes.vehicle_family import canonical_belt
from sdn3d.proposals import predicted_masks
from sdn3d.render.maps import normal_map
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode
from sdn3d.scene.maps import compose_instances, posed_meshes

__all__ = ["PhotoResult", "PhotoSource", "render_photo", "ROAD_FILL_MAX_SIDE"]

#: ``delete_effects``: PatchMatch fills a removed object's hole on crops at most this many pixels on a side (its time
#: grows with their area; road texture is coarse): the removal's cost bound. On the tuning seed's 9 deletes at
#: 1242x375: 160 gave 16.31 dB on vacated + shadow (256: 15.71, 112: 15.95), CPU median 0.32 s, worst 0.88 s.
ROAD_FILL_MAX_SIDE = 160


@dataclass
class PhotoResult:
    """Output of :func:`render_photo`.

    Attributes:
        image: ``(3, H_in, W_in)`` the edited picture (the original's dtype).
        source: ``(H_in, W_in)`` uint8 :data:`SOURCE_NAMES` code of each pixel.
        parts: ``(H_in, W_in)`` int8 :class:`~sdn3d.meshes.parts.Part` of each drawn pixel (-1: not drawn, or an
            object without geometry): with ``source`` it says which part of the car a pixel shows and where it came
            from.
        light: the fitted light (None: relighting off or not fitted).
        objects: ``{instance id: {pixels, photo, mirror, fallback (shares), ...}}`` per drawn object.
        warnings: what the user should know (an object none of whose surface the input shows, ...).
    """

    image: Tensor
    source: Tensor
    light: LightEstimate | None
    objects: dict[int, dict] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    parts: Tensor | None = None

    def summary(self) -> dict:
        counts = torch.bincount(self.source.flatten().long(), minlength=len(SOURCE_NAMES))
        return {"source_pixels": {n: int(c) for n, c in zip(SOURCE_NAMES, counts.tolist(), strict=True)},
                "light": self.light.to_dict() if self.light is not None else None, "objects": self.objects,
                "warnings": list(self.warnings)}


class PhotoSource:
    """What :func:`render_photo` computes from the unedited scene alone, kept between edits of that one scene (an
    interactive editor redraws only what changed; :mod:`sdn3d.editing.appearance`'s ``SourceState`` holds it).

    Every value is what a call without it computes, so pictures are bit-identical with and without it. It serves one
    ``(original, scene, frame, settings)`` (:meth:`check`: a stale one would draw another image's pixels).

    Attributes:
        original: ``(3, H_in, W_in)`` the input (uint8 or float); frame: how it became the scene's working image;
        scene: the unedited scene; bank: its meshes; settings: the photo settings it was made for.
        image: ``(3, H_in, W_in)`` float32 in [0, 1], the input.
        K: ``(3, 3)`` float64, the input image's camera (:func:`~sdn3d.editing.frame.input_intrinsics`).
        erode: input pixels the instance masks are eroded by (:attr:`PhotoSettings.mask_erode_px`, resolved).
        work_ids: ``(h, w)`` int64 source instance map at the working size; src_ids: ``(H_in, W_in)`` the same at the
            input's resolution (nearest); vis_ids: eroded.
        raster: the source objects rasterized at the input's resolution; outline_ids: ``(H_in, W_in)`` the instance id
            of the object rasterized at each pixel (:func:`_raster_ids`: the fitted outlines); parts: ``(H_in * W_in,)``
            long :class:`~sdn3d.meshes.parts.Part` of the rasterized face at each pixel (-1: none);
            :meth:`registered_parts` the same with the drawn dark cars' tyres where the input shows them;
        :meth:`lab` the input's Lab for the removal's road tests;
            :meth:`face_parts` the loft's face labels alone (no greenhouse glass), which the recolour paints by.
        row_to_mesh: ``(N,)`` long, the index in :attr:`raster` of each row of the scene's objects (-1: not
            rasterized). :meth:`visible_pixels`, :meth:`part_examples` and :meth:`clear_air`: each car's eroded mask
            pixels, its part examples and whether it is seen through clear air (the transfer's unseen sides read
            them), each made on first use and kept: they depend on the input alone, so a later edit of the same
            source (an editor's drag of a turn) does not make them again.
        in_front: ``(H_in, W_in)`` bool, thin things in front of a car that its mask leaves out (a pole, a sign post:
            :func:`~sdn3d.editing.photo.occluders.thin_occluders`); every edit keeps them in front.
        max_fills: removals kept (each the filled picture, its relit matte and its leftover pieces, ``5 x H x W``
            float32: ~9.3 MB at 1242x375); the oldest goes first.
    """

    def __init__(self, original: Tensor, frame: PixelFrame, scene: SceneCode, bank: MeshBank | None = None,
                 settings: PhotoSettings | None = None, max_fills: int = 8) -> None:
        self.original, self.frame, self.scene = original, frame, scene
        self.bank = bank or default_bank()
        self.settings = settings or PhotoSettings()
        self.max_fills = int(max_fills)
        self._key = self._bind_key(original, scene, frame, self.settings)
        self.image = original.float() / 255 if original.dtype == torch.uint8 else original.float().clone()
        self.K = input_intrinsics(scene.intrinsics, frame).matrix(dtype=torch.float64)
        erode = self.settings.mask_erode_px
        self.erode = max(1, math.ceil(1 / min(frame.scale))) if erode is None else erode
        w_in, h_in = frame.input_size
        self.work_ids = compose_instances(scene, self.bank).cpu()
        self.src_ids = upsample_ids(self.work_ids, frame)
        self.vis_ids = _erode_ids(self.src_ids, self.erode)
        rows, verts, faces = posed_meshes(scene.objects, self.bank)
        self.raster = _rasterize(rows.cpu(), verts.cpu(), faces.cpu(), self.K, (h_in, w_in))
        self.parts = _part_map(self.raster, scene.objects, self.bank)
        self.row_to_mesh = torch.full((len(scene.objects),), -1, dtype=torch.long)
        self.row_to_mesh[self.raster.rows] = torch.arange(len(self.raster.rows))
        self.outline_ids = _raster_ids(self.raster, scene.objects)
        self.in_front = (thin_occluders(self.image, self.src_ids, self.outline_ids)
                         if self.settings.keep_in_front else torch.zeros_like(self.src_ids, dtype=torch.bool))
        self._light: tuple[Tensor, LightEstimate | None] | None = None
        self._registered_tyres: dict[int, tuple[Tensor, Tensor, Tensor, Tensor, Tensor] | None] = {}
        self._face_parts: Tensor | None = None
        self._fills: dict[tuple, Tensor] = {}
        self._pyramids: dict[int, list[Tensor]] = {}
        self._lab: PictureLab | None = None
        self._flat: Tensor | None = None
        self._visible_of: Callable[[int], Tensor] | None = None
        self._examples: dict[int, tuple[_PartExamples, Tensor]] = {}
        self._air: dict[int, bool] = {}
        self._lamp_air: dict[int, LampAir] = {}
        self._seen_air: dict[int, LampAir] = {}

    @staticmethod
    def _bind_key(original: Tensor, scene: SceneCode, frame: PixelFrame, settings: PhotoSettings) -> tuple:
        return original.data_ptr(), tuple(original.shape), original.dtype, id(scene), frame, settings

    def check(self, original: Tensor, scene: SceneCode, frame: PixelFrame, settings: PhotoSettings) -> None:
        """Raises ValueError unless this serves ``(original, scene, frame, settings)``."""
        if self._bind_key(original, scene, frame, settings) != self._key:
            raise ValueError("PhotoSource serves one (original, scene, transform, settings); make one per scene")

    def light(self) -> tuple[Tensor, LightEstimate | None]:
        """``(normals (H*W, 3), light or None)`` of the source (:func:`_source_light`), fitted on first use."""
        if self._light is None:
            self._light = _source_light(self.raster, self.vis_ids, self.scene.objects, self.image)
        return self._light

    def face_parts(self) -> Tensor:
        """``(H_in * W_in,)`` long: :attr:`parts` without the greenhouse's glass (:func:`_part_map` with
        ``greenhouse=False``), made on first use (a recolour)."""
        if self._face_parts is None:
            self._face_parts = _part_map(self.raster, self.scene.objects, self.bank, greenhouse=False)
        return self._face_parts

    def registered_parts(self, instance_ids: Sequence[int]) -> Tensor:
        """``(H_in * W_in,)`` long: :attr:`parts` with the tyres of each dark car among ``instance_ids`` (the cars an
        edit draws) where the input shows them: a template tyre moved onto the car's wheel is
        :data:`~sdn3d.meshes.parts.Part.TYRE` there, the pixels it left are ``BODY`` (:func:`_dark_car_tyres`, each
        car's found on its first use: the transfer reads them). Other pixels keep the templates' parts."""
        out = self.parts
        for iid in instance_ids:
            found = self._dark_tyres(iid)
            if found is not None:
                out = out.clone() if out is self.parts else out
                out[found[0]] = int(Part.TYRE)
                out[found[1]] = int(Part.BODY)
        return out

    def registered_wheels(self, instance_ids: Sequence[int]) -> Tensor | None:
        """``(H_in * W_in, 2)`` float64: for each template tyre pixel of a dark car among ``instance_ids`` that
        :meth:`registered_parts` moved onto the car's real wheel, the ``(x, y)`` input pixel where the same point of
        the real wheel lies (NaN elsewhere); None where no car's tyre moved."""
        out = None
        for iid in instance_ids:
            found = self._dark_tyres(iid)
            if found is not None and len(found[2]):
                if out is None:
                    out = torch.full((len(self.parts), 2), math.nan, dtype=torch.float64)
                out[found[2]] = found[3]
        return out

    def real_wheels(self, iid: int) -> Tensor | None:
        """``(N, 4)`` float64: the ellipses ``(x, y, semi-axis x, semi-axis y)`` (input pixels) of the real wheels of
        car ``iid`` where :meth:`registered_parts` found them (a dark car's rims); None where it found none."""
        found = self._dark_tyres(iid)
        return found[4] if found is not None and len(found[4]) else None

    def _dark_tyres(self, iid: int) -> tuple[Tensor, Tensor, Tensor, Tensor, Tensor] | None:
        """:func:`_dark_car_tyres` of car ``iid``, found on first use."""
        if iid not in self._registered_tyres:
            self._registered_tyres[iid] = _dark_car_tyres(self.image, self.src_ids, self.parts, iid)
        return self._registered_tyres[iid]

    def pyramid(self, levels: int) -> list[Tensor]:
        """The input's pyramid (:func:`_pyramid`) with at most ``levels`` halvings, made on first use (the transfer and
        the mask paste sample it)."""
        if levels not in self._pyramids:
            self._pyramids[levels] = _pyramid(self.image, levels)
        return self._pyramids[levels]

    def lab(self) -> PictureLab:
        """The input's :class:`~sdn3d.editing.photo.road.PictureLab` (the removal's road tests; each pixel's Lab
        converted on its first use, by any edit)."""
        if self._lab is None:
            self._lab = PictureLab(self.image, self.original if self.original.dtype == torch.uint8 else None)
        return self._lab

    def flat_image(self) -> Tensor:
        """``(H_in * W_in, 3)`` float32: :attr:`image`'s pixels row by row (a copy made on first use)."""
        if self._flat is None:
            self._flat = self.image.permute(1, 2, 0).reshape(-1, 3)
        return self._flat

    def visible_pixels(self, iid: int) -> Tensor:
        """``(P,)`` ascending flat input indices of the pixels of :attr:`vis_ids` equal to instance ``iid`` (one of the
        scene's objects; :func:`_pixels_of`: one scan of the picture for all of them, on first use)."""
        if self._visible_of is None:
            self._visible_of = _pixels_of(self.vis_ids, self.scene.objects.instance_id)
        return self._visible_of(iid)

    def part_examples(self, row: int) -> tuple[_PartExamples, Tensor]:
        """The part examples of the scene's object ``row`` and all its visible colours (:func:`_part_examples`, with
        the road its mask took in, :func:`~sdn3d.editing.photo.recolor.ground_in_mask`, where it is seen through
        clear air: in fog the car's lower body is the road's grey and the colour test takes it for road); made on
        first use."""
        if row not in self._examples:
            visible = self.visible_pixels(int(self.scene.objects.instance_id[row]))
            road = None
            if self.clear_air(row):
                height, width = self.vis_ids.shape
                car = torch.zeros(height * width, dtype=torch.bool)
                car[visible] = True
                road = ground_in_mask(self.image, car.view(height, width)).view(-1)
            self._examples[row] = _part_examples(row, int(self.row_to_mesh[row]), visible, self.scene.objects,
                                                 self.raster, self.parts, self.flat_image(), road, self.settings,
                                                 self.lamp_air(row))
        return self._examples[row]

    def clear_air(self, row: int) -> bool:
        """Whether the scene's object ``row`` is seen through clear air (:func:`_clear_air` of all its visible
        colours, those :meth:`part_examples` returns: its darks near black); made on first use, without its examples
        (a car passed over for another car's wheel or tyres is not looked at further)."""
        if row not in self._air:
            self._air[row] = _clear_air(self._visible_colors(row))
        return self._air[row]

    def lamp_air(self, row: int) -> LampAir:
        """The air the scene's object ``row`` is seen through, for reading its lamps' colours (:func:`_lamp_air` of
        the colours :meth:`clear_air` reads); made on first use."""
        if row not in self._lamp_air:
            self._lamp_air[row] = None if self.clear_air(row) else self.seen_air(row)  # as _lamp_air reads it
        return self._lamp_air[row]

    def seen_air(self, row: int) -> LampAir:
        """The air the scene's object ``row`` is seen through as :func:`seen_through_the_air` reads it off the colours
        :meth:`clear_air` reads (:func:`_seen_air`); made on first use (each of a car's part lookups asks for it: a
        few ms of quantiles each time)."""
        if row not in self._seen_air:
            self._seen_air[row] = _seen_air(self._visible_colors(row))
        return self._seen_air[row]

    def _visible_colors(self, row: int) -> Tensor:
        """``(Q, 3)`` float64 all the visible colours of the scene's object ``row`` (those :meth:`part_examples`
        returns, taken from them once they are made)."""
        return (self._examples[row][1] if row in self._examples
                else self.flat_image()[self.visible_pixels(int(self.scene.objects.instance_id[row]))].double())

    def fill(self, key: tuple, make) -> Tensor:
        """A copy of the removal of ``key`` (the objects that left and stayed: :func:`render_photo`'s filled picture,
        relit matte and leftovers), made by ``make()`` once."""
        if self.max_fills <= 0:
            return make()
        if key not in self._fills:
            while len(self._fills) >= self.max_fills:
                self._fills.pop(next(iter(self._fills)))
            self._fills[key] = make()
        return self._fills[key].clone()  # the caller draws into its picture


def _erode_ids(ids: Tensor, radius: int) -> Tensor:
    """``ids (H, W)`` with every pixel whose ``(2r+1)^2`` neighbourhood (the picture's edge replicated) holds another
    id set to 0: the neighbourhood's largest and smallest ids differ (OpenCV's dilation and erosion, on float32,
    exact for ids below 2^24; a max pool's result at a fraction of its time)."""
    if radius <= 0:
        return ids
    import cv2

    if not len(ids.view(-1)) or int(ids.abs().max()) >= 2**24:  # float32 holds these ids exactly
        x = ids[None, None].double()
        k = 2 * radius + 1
        hi = F.max_pool2d(F.pad(x, (radius,) * 4, mode="replicate"), k, stride=1)
        lo = -F.max_pool2d(F.pad(-x, (radius,) * 4, mode="replicate"), k, stride=1)
        return torch.where((hi == lo)[0, 0], ids, torch.zeros_like(ids))
    x = ids.numpy().astype(np.float32)
    kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
    hi = cv2.dilate(x, kernel, borderType=cv2.BORDER_REPLICATE)
    lo = cv2.erode(x, kernel, borderType=cv2.BORDER_REPLICATE)
    return torch.where(torch.from_numpy(hi == lo), ids, torch.zeros_like(ids))


@dataclass
class _Raster:
    """A rasterization at the input's resolution: ``rows (G,)`` of the table, ``verts (G, V, 3)``, ``faces``,
    fragments ``(1, h, w)`` of the box the meshes cover (:attr:`Fragments.box`; the ``*_at`` lookups take the
    input's flat pixel indices)."""

    rows: Tensor
    verts: Tensor
    faces: Tensor
    frags: Fragments


def _rasterize(rows: Tensor, verts: Tensor, faces: Tensor, K: Tensor, size: tuple[int, int]) -> _Raster:
    g = len(rows)
    # cropped to the box the meshes cover: a car's fraction of the picture, the same values
    frags = rasterize_meshes(verts.double(), faces, K, RasterSettings(image_size=size),
                             mesh_to_image=torch.zeros(g, dtype=torch.long), batch_size=1, crop=True)
    return _Raster(rows, verts.double(), faces, frags)


def _raster_ids(r: _Raster, objects: ObjectTable) -> Tensor:
    """``(H, W)`` instance id of the object rasterized at each pixel of ``r`` (0: none): the fitted silhouettes."""
    mesh = r.frags.pix_to_mesh
    if not len(r.rows):
        return torch.zeros(r.frags.image_size, dtype=mesh.dtype)
    # a table of the meshes' ids after a 0 for "none" (mesh -1), looked up once per pixel of the box
    ids = objects.instance_id[r.rows].to(torch.promote_types(objects.instance_id.dtype, mesh.dtype))
    return r.frags.in_image(torch.cat([ids.new_zeros(1), ids])[mesh + 1], 0)[0]


def _part_map(r: _Raster, objects: ObjectTable, bank: MeshBank, at: Tensor | None = None,
              greenhouse: bool = True) -> Tensor:
    """``(H * W,)`` long :class:`~sdn3d.meshes.parts.Part` of the face rasterized at each pixel of ``r`` (-1: none);
    with ``at (P,)`` flat indices of covered pixels, ``(P,)`` the same at those pixels alone. ``greenhouse``: with
    the greenhouse's glass added per point (:func:`_greenhouse_glass`); False: the loft's face labels alone (what the
    recolour paints: a real car's pillars and roof rails above its belt are paint, :func:`_recolor`)."""
    if at is None:
        out = torch.full((r.frags.image_size[0] * r.frags.image_size[1],), -1, dtype=torch.long)
        pix = r.frags.covered()
        if not len(pix):
            return out
    else:
        pix = at
    where = r.frags.locate(pix)
    mesh = r.frags.mesh_at(where)
    local = r.frags.face_at(where) - mesh * r.faces.shape[1]
    parts = bank.face_parts.cpu()
    template = objects.template_id[r.rows[mesh]].long()
    found = parts[template, local.clamp(max=parts.shape[1] - 1)]
    if greenhouse:
        found = _greenhouse_glass(found, pix, r, bank, template, local)
    if at is not None:
        return found.long()  # as the long map's entries
    out[pix] = found
    return out


def _bank_belts(bank: MeshBank) -> Tensor:
    """``(M,)`` float64 canonical belt line of each mesh of ``bank`` (:func:`~sdn3d.meshes.vehicle_family.
    canonical_belt`; -inf for a mesh that is no template: no point above it)."""
    return torch.tensor([canonical_belt(TEMPLATE_SPECS[n]) if n in TEMPLATE_SPECS else -math.inf for n in bank.names],
                        dtype=torch.float64)


def _greenhouse_glass(found: Tensor, pix: Tensor, r: _Raster, bank: MeshBank, template: Tensor,
                      local: Tensor) -> Tensor:
    """``found (P,)`` parts at flat pixels ``pix (P,)`` of ``r`` (their meshes' ``template (P,)`` ids in ``bank``,
    faces ``local (P,)``) with the body points of the greenhouse glass (:func:`~sdn3d.meshes.parts.greenhouse_glass`
    at the surface point's canonical height, the template's own, before the FFD): the end panels are fans from a
    centre below the belt, so their windows are told per point, not per face."""
    body = (found == int(Part.BODY)).nonzero().flatten()
    if not len(body):
        return found
    t, f = template[body], local[body]
    tri = bank.verts.cpu()[t[:, None], bank.faces.cpu()[t, f]].double()  # (B, 3, 3) canonical
    bary = r.frags.bary_at(pix[body]).double()
    height = (bary * tri[..., 1]).sum(1)
    normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
    glass = greenhouse_glass(found[body], height, -normal[:, 1], _bank_belts(bank)[t])
    out = found.clone()
    out[body[glass]] = int(Part.GLASS)
    return out


def _surface(r: _Raster, pix: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """``(mesh (P,), vertex ids (P, 3), barycentrics (P, 3), camera-facing unit normal (P, 3))`` at flat pixel
    indices ``pix (P,)`` of ``r`` (all covered)."""
    return _surface_points(r, pix)[:4]


def _surface_points(r: _Raster, pix: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor, Tensor, Tensor]:
    """:func:`_surface` and the ``(P, 3, 3)`` triangles and ``(P, 3)`` surface points it found them from (row by row:
    rows selected from them are those of the selected pixels)."""
    where = r.frags.locate(pix)
    f_all = r.frags.face_at(where)
    mesh = r.frags.mesh_at(where)
    nf = r.faces.shape[1]
    vid = r.faces[mesh, f_all - mesh * nf]  # (P, 3)
    bary = r.frags.bary_at(where).double()
    tri = r.verts[mesh[:, None], vid]  # (P, 3, 3)
    point = sum3(bary[..., None] * tri, 1)
    normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
    normal = torch.where((sum3(normal * point) > 0)[:, None], -normal, normal)
    return mesh, vid, bary, normal, tri, point


def _project(points: Tensor, K: Tensor) -> tuple[Tensor, Tensor]:
    """``(uv (P, 2), in front (P,))`` pixel coordinates of camera-frame ``points (P, 3)``."""
    z = points[:, 2]
    front = z > RasterSettings.near
    zs = torch.where(front, z, torch.ones_like(z))
    uv = torch.stack([K[0, 0] * points[:, 0] / zs + K[0, 2], K[1, 1] * points[:, 1] / zs + K[1, 2]], 1)
    return uv, front


def _nearest_pixel(uv: Tensor, valid: Tensor, size: tuple[int, int]) -> tuple[Tensor, Tensor]:
    """``(inside (P,), flat index (P,))`` of the pixel nearest each ``uv (P, 2)`` in an ``(H, W)`` picture: inside where
    ``valid (P,)``, finite and within the picture (the index is clamped to it either way)."""
    height, width = size
    j, i = torch.floor(uv[:, 0] + 0.5).long(), torch.floor(uv[:, 1] + 0.5).long()
    inside = valid & (j >= 0) & (j < width) & (i >= 0) & (i < height) & torch.isfinite(uv).all(1)
    return inside, i.clamp(0, height - 1) * width + j.clamp(0, width - 1)


def _visible(points: Tensor, mesh: Tensor, iid: Tensor, src: _Raster, vis_ids: Tensor, K: Tensor,
             tolerance: float) -> tuple[Tensor, Tensor]:
    """``(visible (P,), uv (P, 2))``: is each source-pose point ``points (P, 3)`` of source mesh ``mesh (P,)``
    (instance ``iid (P,)``) seen in the input (module doc, step 3)?"""
    uv, front = _project(points, K)
    inside, flat = _nearest_pixel(uv, front, tuple(vis_ids.shape))
    where = src.frags.locate(flat)
    same = src.frags.mesh_at(where) == mesh
    depth = src.frags.depth_at(where).double()
    z = points[:, 2]
    near = (depth - z).abs() <= tolerance * z.abs() + 0.05
    ok = inside & same & near & (vis_ids.view(-1)[flat] == iid)
    return ok, uv


def _in_silhouette(points: Tensor, background: Tensor, K: Tensor) -> Tensor:
    """``(P,)``: does each source-pose point ``points (P, 3)`` project onto a pixel the input's masks do not rule out
    (``background (H, W)`` bool is False there, or it falls off the picture or behind the camera)? A point of the
    object itself projects into its mask or onto whatever hides it, never onto open background."""
    uv, front = _project(points, K)
    inside, flat = _nearest_pixel(uv, front, tuple(background.shape))
    return ~inside | ~background.view(-1)[flat]


def _on_real_wheel(uv: Tensor, ok: Tensor, wheels: Tensor, registered: Tensor,
                   size: tuple[int, int]) -> tuple[Tensor, Tensor, Tensor]:
    """``(uv (P, 2), moved (P,), on the wheel (P,))``: each input-pixel lookup ``uv (P, 2)`` (where ``ok (P,)``) that
    falls on a dark car's template tyre moved onto the real wheel (``wheels (H * W, 2)``, the real wheel's ``(x, y)``
    of each such pixel, NaN elsewhere: :meth:`PhotoSource.registered_wheels`) moved there, with its offset within the
    pixel; ``on the wheel``: it lands on the car's tyre in ``registered (H * W,)``
    (:meth:`PhotoSource.registered_parts`). A template's wheel is often a third of a wheel off the real one: its
    points read where it lay draw paint or a rimless black disc (the rims were not there), read off the real wheel
    they draw its rim and rubber."""
    inside, flat = _nearest_pixel(uv, ok, size)
    at = wheels[flat]
    moved = inside & torch.isfinite(at[:, 0])
    centre = torch.floor(uv + 0.5)
    uv = torch.where(moved[:, None], at + (uv - centre), uv)
    landed, flat = _nearest_pixel(uv, moved, size)
    return uv, moved, landed & (registered[flat] == int(Part.TYRE))


def _wheel_faces(bank: MeshBank, template: int, vid: Tensor, bary: Tensor) -> tuple[Tensor, Tensor]:
    """``(offset (P, 2), on a face (P,) bool)`` of points of mesh ``template`` of ``bank`` given by the vertex ids
    ``vid (P, 3)`` and barycentrics ``bary (P, 3)`` of their faces: where each lies on its wheel's outer or inner face
    (a cap of the wheel's cylinder, ``|offset| <= 1``), as the offset from the wheel's centre along the car and down,
    in the wheel's radii. The wheels are the mesh's tyre faces in each quarter (front or rear, left or right); the
    template's own coordinates, which an FFD does not move."""
    verts = bank.verts[template].double()
    tri = verts[vid]
    point = (bary.double()[..., None] * tri).sum(1)
    normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
    tyre = bank.faces[template][bank.face_parts[template] == int(Part.TYRE)]
    offset = torch.full((len(point), 2), math.nan, dtype=torch.float64)
    if not len(tyre):
        return offset, torch.zeros(len(point), dtype=torch.bool)
    wheel_verts = verts[tyre.flatten().unique()]
    for ahead in (False, True):
        for left in (False, True):
            mine = ((wheel_verts[:, 0] > 0) == ahead) & ((wheel_verts[:, 2] > 0) == left)
            here = ((point[:, 0] > 0) == ahead) & ((point[:, 2] > 0) == left)
            if not any_set(mine) or not any_set(here):
                continue
            lo, hi = wheel_verts[mine].amin(0), wheel_verts[mine].amax(0)
            offset[here] = (point[here, :2] - (lo + hi)[:2] / 2) / ((hi - lo)[:2] / 2).clamp(min=1e-9)
    face = (normal[:, 2].abs() > WHEEL_FACE_COS) & (offset.norm(dim=1) <= 1.0)
    return offset, face


#: :func:`_wheel_faces`: a wheel face's normal points along the axle at least this closely (the caps of a wheel's
#: cylinder; its tread's normals are across it).
WHEEL_FACE_COS = 0.9
#: :func:`_from_real_wheels`: the share of the real tyre's ellipse a wheel face is drawn from (its edge meets the
#: wheel arch's paint and the road).
REAL_WHEEL_REACH = 0.95


def _wheel_face_points(parts: Tensor, bank: MeshBank, template: int, vid: Tensor,
                       bary: Tensor) -> tuple[Tensor, Tensor]:
    """``(points (N,) long, offset (N, 2))``: which never-seen points of one car (``parts (P,)``) lie on a wheel face
    of its template (:func:`_wheel_faces` of ``bank`` mesh ``template``, ``vid (P, 3)``, ``bary (P, 3)``), and their
    offsets from the wheel's centre: the points :func:`_from_real_wheels` draws."""
    tyre = (parts == int(Part.TYRE)).nonzero().flatten()
    if not len(tyre):
        return tyre, torch.zeros(0, 2, dtype=torch.float64)
    offset, face = _wheel_faces(bank, template, vid[tyre], bary[tyre])
    return tyre[face], offset[face]


def _from_real_wheels(colors: Tensor, codes: Tensor, wheel: tuple[Tensor, int], tyre: Tensor, offset: Tensor,
                      pyramid: list[Tensor]) -> tuple[Tensor, Tensor]:
    """``(colours (P, 3), codes (P,))``: never-seen points of one car (``colors``, ``codes`` as :func:`_part_colors`
    drew them) that lie on a wheel face of its template (``tyre (N,)`` at ``offset (N, 2)``,
    :func:`_wheel_face_points`) drawn from the real wheel ``wheel`` = ``((x, y, semi-axis x, semi-axis y), code)`` at
    the same offset from its centre, read off the input's ``pyramid``: a wheel is a rim in a ring of rubber, which the
    part's examples (tyre pixels lighter than most of the car are dropped, and a car seen from behind shows only
    treads) drew as a flat black disc (the real frame's red car turned 90 degrees)."""
    ellipse, code = wheel
    if not len(tyre):
        return colors, codes
    uv = ellipse[:2] + REAL_WHEEL_REACH * offset * ellipse[2:]
    colors, codes = colors.clone(), codes.clone()
    colors[tyre] = _sample(pyramid, uv, torch.zeros(len(uv), dtype=torch.float64)).double()
    codes[tyre] = code
    return colors, codes


def _view_cos(points: Tensor, normals: Tensor) -> Tensor:
    """``(P,)`` ``|cos|`` of the angle between each surface normal and the line of sight to its point (camera at the
    origin): 1 seen squarely, 0 edge-on."""
    return sum3(F.normalize(points, dim=-1) * normals).abs()


def _pyramid(image: Tensor, levels: int) -> list[Tensor]:
    out = [image[None].float()]
    for _ in range(levels):
        prev = out[-1]
        if min(prev.shape[-2:]) < 4:
            break
        out.append(F.interpolate(prev, scale_factor=0.5, mode="bilinear", antialias=True, align_corners=False,
                                 recompute_scale_factor=False))
    return out


def _sample(pyramid: list[Tensor], uv: Tensor, level: Tensor) -> Tensor:
    """``(P, 3)`` bilinear samples at input pixels ``uv (P, 2)``, blended between pyramid levels ``level (P,)``."""
    height, width = pyramid[0].shape[-2:]
    grid = torch.stack([(uv[:, 0] + 0.5) / width * 2 - 1, (uv[:, 1] + 0.5) / height * 2 - 1], 1)
    grid = grid.float()[None, None]  # (1, 1, P, 2): normalised coordinates are the same at every level
    level = level.clamp(0, len(pyramid) - 1).float()
    lo = level.floor().long()
    hi = (lo + 1).clamp(max=len(pyramid) - 1)
    t = (level - lo.float())[:, None]
    # the levels down to the deepest one some point blends (an object that kept its size: the first two of four), each
    # by the call on the same grid that sampled every level
    deepest = int(hi.max()) if len(hi) else 0
    samples = torch.stack([F.grid_sample(p, grid, mode="bilinear", padding_mode="border",
                                         align_corners=False)[0, :, 0].T for p in pyramid[:deepest + 1]])  # (L, P, 3)
    idx = torch.arange(len(uv))
    return samples[lo, idx] * (1 - t) + samples[hi, idx] * t


def _same_pose(before: ObjectTable, after: ObjectTable, rb: Tensor, ra: Tensor) -> Tensor:
    return ((before.location[rb] - after.location[ra]).abs().amax(1) < 1e-9) & (
        (before.ry[rb] - after.ry[ra]).abs() < 1e-9)


def _origins(before: ObjectTable, after: ObjectTable) -> Tensor:
    """``(N_after,)`` row in ``before`` of each object of ``after`` (same id; for a duplicate, the object with the
    same template, size and shape), -1 where none."""
    origin = torch.full((len(after),), -1, dtype=torch.long)
    pairs = (after.instance_id[:, None] == before.instance_id[None, :]).nonzero()
    origin[pairs[:, 0]] = pairs[:, 1]
    for a in (origin < 0).nonzero().flatten().tolist():
        same = ((before.template_id == after.template_id[a]) & (before.dims == after.dims[a]).all(1)
                & (before.phi == after.phi[a]).flatten(1).all(1))
        if any_set(same):
            origin[a] = int(same.nonzero()[0])
    return origin


def _box_floor(objects: ObjectTable, row: int, grow: float = 1.1) -> Tensor:
    """``(4, 3)`` camera-frame corners of an object's bottom face, grown by ``grow``."""
    l, _, w = objects.dims[row].tolist()
    c = objects.location[row].double()
    corners = torch.tensor([[1, 1], [1, -1], [-1, -1], [-1, 1]], dtype=torch.float64) * 0.5 * grow
    local = torch.stack([corners[:, 0] * l, torch.zeros(4, dtype=torch.float64), corners[:, 1] * w], 1)
    return local @ roty(objects.ry[row].double()).T + c


def _contact_shadow(objects: ObjectTable, rows: list[int], K: Tensor, size: tuple[int, int]) -> Tensor:
    """``(H, W)`` float soft footprint in [0, 1] of the objects' bottom faces (their new contact shadows)."""
    canvas = np.zeros(size, np.float32)
    for row in rows:
        uv, front = _project(_box_floor(objects, row), K)
        if not bool(front.all()) or not bool(torch.isfinite(uv).all()):
            continue
        poly = uv.numpy()
        if np.abs(poly).max() > 1e5:
            continue
        span = max(float(poly[:, 1].max() - poly[:, 1].min()), 2.0)
        _splat_blurred_hull(canvas, poly, max(0.6, 0.25 * span))
    return torch.from_numpy(canvas)


def _splat_blurred_hull(canvas: np.ndarray, points: np.ndarray, sigma: float) -> None:
    """Raise ``canvas (H, W)`` float32 in place to the convex hull of ``points (P, 2)`` (pixels), anti-aliased at a
    quarter pixel and blurred by ``sigma``, on a window around it (:func:`_blur_window`; nothing where the hull lies
    outside the picture, whose blur is 0 everywhere)."""
    import cv2

    hull = cv2.convexHull(np.round(points * 4).astype(np.int32))
    window = _blur_window(hull, sigma, canvas.shape)
    if window is None:
        return
    y0, y1, x0, x1 = window
    layer = np.zeros((y1 - y0, x1 - x0), np.float32)
    cv2.fillConvexPoly(layer, hull - np.array([4 * x0, 4 * y0], np.int32), 1.0, lineType=cv2.LINE_AA, shift=2)
    crop = canvas[y0:y1, x0:x1]
    np.maximum(crop, cv2.GaussianBlur(layer, (0, 0), sigma), out=crop)


def _blur_window(hull: np.ndarray, sigma: float, size: tuple[int, int]) -> tuple[int, int, int, int] | None:
    """``(y0, y1, x0, x1)`` of the canvas a Gaussian blur (``sigma``) of the polygon ``hull`` (2 fractional bits)
    changes, padded so that the blur of that crop equals the whole canvas's blur there bit for bit: by twice the
    kernel's radius (what the crop's mirrored border brings in is zero), left edges on multiples of 64 columns and
    64 spare columns on the right (OpenCV's vector lanes fall on the same pixels); the canvas's edge where it is
    near (mirrored the same way). None: the polygon misses the canvas."""
    height, width = size
    radius = (int(round(sigma * 8 + 1)) | 1) // 2 + 2  # OpenCV's float kernel size, 2 pixels more
    lo = hull.reshape(-1, 2).min(0) // 4 - 2
    hi = hull.reshape(-1, 2).max(0) // 4 + 3
    if lo[0] >= width or lo[1] >= height or hi[0] <= 0 or hi[1] <= 0:
        return None
    x0 = max(int(lo[0]) - 2 * radius, 0) // 64 * 64
    y0 = max(int(lo[1]) - 2 * radius, 0)
    x1 = min(int(hi[0]) + 2 * radius + 64, width)
    y1 = min(int(hi[1]) + 2 * radius + 64, height)
    return y0, y1, x0, x1



def _polygon_mask(points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """``(H, W)`` uint8 filled convex hull of image points ``points (N, 2)``."""
    import cv2

    canvas = np.zeros(size, np.uint8)
    points = np.clip(points, -4 * max(size), 4 * max(size))
    cv2.fillConvexPoly(canvas, cv2.convexHull(np.round(points).astype(np.int32)), 1)
    return canvas


def _effects_regions(objects: ObjectTable, rows: list[int], K: Tensor, size: tuple[int, int],
                     light: LightEstimate | None, max_reach: float = 2.0) -> tuple[Tensor, Tensor]:
    """``(search (H, W), road part (H, W))`` bool of removed objects ``rows``: where each one's shadow can lie (its
    box's footprint, grown, and the box's top corners cast along ``light``'s direction onto its ground plane, at
    most ``max_reach`` of its length away; without a light, the footprint grown by half) and the part of the picture
    that is road below its footprint's far edge (the footprint's hull carried down to the bottom edge)."""
    height, width = size
    search = np.zeros(size, np.uint8)
    road = np.zeros(size, np.uint8)
    for row in rows:
        floor = _box_floor(objects, row, 1.15)
        if light is not None and float(light.direction[1]) < -0.1:
            d = light.direction.double()
            top = floor.clone()
            top[:, 1] -= float(objects.dims[row, 1])
            reach = (float(objects.dims[row, 1]) / -float(d[1])) * d
            reach_len = float(reach[[0, 2]].norm())
            cap = max_reach * float(objects.dims[row].max())
            if reach_len > cap:
                reach = reach * (cap / reach_len)
            cast = top - reach
            cast[:, 1] = floor[0, 1]
            ground = torch.cat([floor, cast])
        else:
            ground = _box_floor(objects, row, 1.5)
        uv, front = _project(ground, K)
        if not bool(front.all()) or not bool(torch.isfinite(uv).all()):
            continue
        search |= _polygon_mask(uv.numpy(), size)
        fuv, ffront = _project(floor, K)
        if bool(ffront.all()):
            f = fuv.numpy()
            down = np.stack([f[:, 0], np.full(4, height + 4.0)], 1)
            road |= _polygon_mask(np.concatenate([f, down]), size)
    return torch.from_numpy(search > 0), torch.from_numpy(road > 0)


def _shadow_context(image: Tensor, hole: Tensor, objects_px: Tensor, before: ObjectTable, rows: list[int], K: Tensor,
                    light: LightEstimate | None,
                    lab: PictureLab | None = None) -> tuple[Tensor, Tensor, Tensor, Tensor | None]:
    """``(search, road part, ring, road Lab or None)`` of objects ``rows`` of ``before`` (:func:`_effects_regions`;
    the ring: pixels 6 to 30 pixels around the search region and ``hole``, on no object; the road: its colour,
    :func:`~sdn3d.editing.photo.road.road_colours`, from ``lab``, ``image``'s Lab, when given)."""
    search, road_part = _effects_regions(before, rows, K, tuple(hole.shape), light)
    around = dilate_square(search | hole, 6)
    ring = dilate_square(search | hole, 30) & ~around & ~objects_px
    return search, road_part, ring, road_colours(image, ring, lab=lab)


def _relight_around(image: Tensor, search: Tensor, hole: Tensor, objects_px: Tensor, ring: Tensor,
                    road: Tensor) -> tuple[Tensor, Tensor]:
    """``(image, relit (H, W) matte)``: the shadow found in ``search`` (grown by 3 px) relit outside ``hole`` and the
    objects' pixels ``objects_px`` (:func:`~sdn3d.editing.photo.fill.relight_shadow`, lit road from ``ring``)."""
    return relight_shadow(image, dilate_square(search, 3) & ~hole & ~objects_px, ring, road)


def _relight_removed(image: Tensor, hole: Tensor, objects_px: Tensor, before: ObjectTable, rows: list[int], K: Tensor,
                     light: LightEstimate | None) -> tuple[Tensor, Tensor]:
    """``(image, relit (H, W) matte)``: the shadows of objects ``rows`` that left their place relit outside
    ``hole`` (:func:`~sdn3d.editing.photo.fill.relight_shadow`)."""
    search, _, ring, road = _shadow_context(image, hole, objects_px, before, rows, K, light)
    if road is None:
        return image, torch.zeros(tuple(hole.shape), dtype=torch.float32)
    return _relight_around(image, search, hole, objects_px, ring, road)


def _remove_with_effects(image: Tensor, hole: Tensor, objects_px: Tensor, before: ObjectTable, gone_rows: list[int],
                         K: Tensor, light: LightEstimate | None, settings: PhotoSettings,
                         vanishing: tuple[float, float] | None = None,
                         lab: PictureLab | None = None) -> tuple[Tensor, Tensor]:
    """``(filled image, relit (H, W) matte)``: step 2 with ``delete_effects`` (module doc): the removed objects'
    shadows relit (:func:`~sdn3d.editing.photo.fill.relight_shadow`), then the road part of ``hole`` filled by
    PatchMatch from road-like pixels only, then the rest of it by ``settings.fill`` from everything but
    ``objects_px`` (``fill='rays'``: all of it along the rays from ``vanishing``, after the relight); ``lab``:
    ``image``'s :class:`~sdn3d.editing.photo.road.PictureLab` for the road tests (None: converted where needed)."""
    size = tuple(hole.shape)
    # rays: the shadow is looked for on the footprint grown by half, whatever the light (the same PSNR on the tuning
    # tree's deletes as with the fitted light's cast region, without the light's fit: docs/results/.../deletes/)
    search, road_part, ring, road = _shadow_context(image, hole, objects_px, before, gone_rows, K,
                                                    None if settings.fill in RAY_FILLS else light, lab)
    matte = torch.zeros(size, dtype=torch.float32)
    if road is None:
        return fill_hole(image, hole, settings, objects_px, vanishing=vanishing, lab=lab), matte
    if settings.fill in RAY_FILLS:
        return _rays_with_effects(image, hole, objects_px, search, ring, road, settings, vanishing,
                                  _ground_row(road_part, K), lab)
    if settings.delete_shadow:
        image, matte = _relight_around(image, search, hole, objects_px, ring, road)
    road_hole = hole & road_part
    out = image
    if any_set(road_hole):
        ys, xs = nonzero_yx(road_hole)
        reach = (int(ys.max() - ys.min()) + int(xs.max() - xs.min())) // 2 + 4 * settings.inpaint_radius + 16
        near = dilate_square(road_hole, reach)  # covers the fill's crop (fill._inpaint_part's margin)
        avoid = objects_px | ~road_like(image, road, min_light=0.8, within=near)  # lit road and markings only
        out = inpaint(out, road_hole, "patchmatch" if settings.fill != "telea" else "telea",
                      settings.inpaint_radius, keep_out=avoid, max_side=ROAD_FILL_MAX_SIDE)
    rest = hole & ~road_hole
    if any_set(rest):
        out = inpaint(out, rest, settings.fill, settings.inpaint_radius, keep_out=objects_px,
                      max_side=ROAD_FILL_MAX_SIDE)
    return out, matte


def _rays_with_effects(image: Tensor, hole: Tensor, objects_px: Tensor, search: Tensor, ring: Tensor, road: Tensor,
                       settings: PhotoSettings, vanishing: tuple[float, float] | None,
                       ground_row: float | None = None, lab: PictureLab | None = None) -> tuple[Tensor, Tensor]:
    """``(filled image, relit (H, W) matte)`` of :func:`_remove_with_effects` with ``fill='rays'``: shadowed road
    (:func:`~sdn3d.editing.photo.road.shadowed_road`) is no source of the rays; with ``delete_shadow`` the removed
    objects' shadow there (inside ``search``) joins the hole (``shadow_mode='fill'``; the matte is -1 there, and on
    the pieces that run on past it, :func:`~sdn3d.editing.photo.fill.shadow_pieces`, filled after it) or is relit
    first (``'relight'``); ``road (3,)`` and ``ground_row`` (:func:`_ground_row`) tell the rays' road from a
    verge on the ground near the car (``photo.ray_verge``); ``lab``: ``image``'s
    :class:`~sdn3d.editing.photo.road.PictureLab` (not the relit picture's)."""
    from sdn3d.editing.photo.road import road_shade, shadowed_road

    ys, xs = nonzero_yx(search | hole)
    reach = max(int(ys.max() - ys.min()), int(xs.max() - xs.min())) + 8
    near = dilate_square(search | hole, reach)
    lit = near & ~dilate_square(search | hole, 3) & ~objects_px
    dark = shadowed_road(image, road, near, lit, settings.shadow_light, lab=lab) & ~objects_px
    matte = torch.zeros(tuple(hole.shape), dtype=torch.float32)
    pieces = torch.zeros_like(hole)
    if settings.delete_shadow and settings.shadow_mode == "relight":
        image, matte = _relight_around(image, search, hole, objects_px, ring, road)
        lab = None  # of the picture before the relight
        dark = shadowed_road(image, road, near, lit, settings.shadow_light) & ~objects_px
    elif settings.delete_shadow:
        own = dark & dilate_square(search, 3) & ~hole
        hole = hole | own
        # The search region comes from the fitted box: where it sits off the car, the shadow runs on past the hole
        # outside it (the real frame's red car: its shadow's tip beside the rear wheel stayed). Those pieces are
        # filled after the hole, by Telea from the filled picture around them: in the hole they changed its rays'
        # sources and fits, and with them hundreds of fill pixels (a predicted delete on the seed-33 tuning tree lost
        # 0.4 dB; docs/results/2026-11-30_cpu/session21/shade/).
        pieces = shadow_pieces(dark, hole, settings.shadow_reach, SHADOW_GROUND)
        matte = -(own | pieces).float()  # filled, not relit: render_photo marks these pixels fill
        if settings.faint_light > 0:
            # The shadow's faint edge (lighter than shadow_light) stays a grey halo around the hole and darkens the
            # rays' sources beside it: relit first, in the region the shadow was looked for, on its ground rows.
            zone = _ground_rows(dilate_square(search, 3) & ~hole & ~pieces & ~objects_px, hole, SHADOW_GROUND)
            # Shade against the darker of the row's lit road and the lit road beside it along the row: a pixel is
            # faint shadow only when darker than both, and is relit to the darker.
            beside = FAINT_REFERENCE * float(_rows_spanned(hole))
            shade = road_shade(image, road, zone, lit, lab=lab, luma=True, local=beside)
            image, gain = relight_faint_shadow(image, shade, zone, hole | pieces, settings.faint_light,
                                               settings.shadow_light)
            if bool((gain > 1).any()):
                lab = None  # of the picture before the relight
                matte = torch.where(gain > 1, gain - 1, matte)
    keep_out = objects_px | _ground_rows(dark, hole, SHADOW_GROUND)
    out = fill_hole(image, hole, settings, keep_out, vanishing=vanishing, road=road, ground_row=ground_row, lab=lab)
    if any_set(pieces):
        out = inpaint(out, pieces, "telea", settings.inpaint_radius)
    return out, matte


#: :func:`_rays_with_effects`: the faint shadow is road darker than its row's lit road and than the lit road beside it
#: along the row, weighted by a Gaussian of this share of the hole's height (:func:`~sdn3d.editing.photo.road.
#: road_shade`'s ``local``). Against the row's alone, the real frame's red car's delete relit the road beyond its
#: shadow, darker there across the whole road, into a lighter patch with an edge; against the road beside it alone,
#: lit road next to the shadow, lighter than the road under it in the exact render, relit the tuning cf33's deletes
#: past it (-0.07 dB; docs/results/2026-11-30_cpu/session27/shadow41/).
FAINT_REFERENCE = 0.5


def _rows_spanned(mask: Tensor) -> int:
    """How many rows from the first to the last that hold a pixel of ``mask (H, W)`` (0: none)."""
    rows = any_along(mask, 1).nonzero().flatten()
    return int(rows[-1] - rows[0] + 1) if len(rows) else 0


#: :func:`_ground_row`: the ground near a removed car reaches this many times the distance of its footprint's far edge.
#: On the real frame's black car the verge behind it that blended into the far lane lay at 1 to 2.4 times; on the
#: seed-31 tuning deletes, a car in front of trees and a grey facade had them from 2.4 times on, up to the horizon.
GROUND_REACH = 2.5


def _ground_row(road_part: Tensor, K: Tensor) -> float | None:
    """The picture row from which the hole's pixels are taken for ground near the removed cars (None: no footprint):
    where the road plane of a level camera lies :data:`GROUND_REACH` times as far as the far edge of their footprints
    (the top row of ``road_part (H, W)``, :func:`_effects_regions`; depth on the road plane goes as one over the rows
    below the horizon ``K[1, 2]``). Above it, a ray's sides are as likely upright things (trees, facades) as ground."""
    rows = any_along(road_part, 1).nonzero().flatten()
    if not len(rows):
        return None
    horizon = float(K[1, 2])
    return horizon + max(float(rows[0]) - horizon, 0.0) / GROUND_REACH


#: :func:`_rays_with_effects`: shadowed road is no ray's source only from this share of the hole's height down (the
#: ground a removed car's shadow lies on). Higher up, dark road-coloured pixels are what the hole's upper part truly
#: shows (far road in a building's shade, shaded walls): kept out, they cost the seed-33 tuning deletes 0.2 dB
#: (docs/results/2026-11-28_cpu/session5/deletes/).
SHADOW_GROUND = 0.5


def _ground_rows(mask: Tensor, hole: Tensor, share: float) -> Tensor:
    """``mask (H, W)`` in the rows from ``share`` of ``hole``'s height (from its top row) down, False above."""
    rows = any_along(hole, 1).nonzero().flatten()
    if not len(rows):
        return mask
    cut = int(rows[0]) + int(share * float(rows[-1] - rows[0]))
    return mask & (torch.arange(mask.shape[0]) >= cut)[:, None]


def _cast_shadows(objects: ObjectTable, rows: list[int], verts: dict[int, Tensor], K: Tensor, size: tuple[int, int],
                  light: LightEstimate, blur: float = 1.0, max_reach: float = 2.0) -> Tensor:
    """``(H, W)`` float matte in [0, 1] of the shadows objects ``rows`` cast on their ground planes: each posed
    mesh's vertices ``verts[row] (V, 3)`` carried along ``light``'s direction down to the object's floor (at most
    ``max_reach`` of its largest dimension away), their convex hull projected, anti-aliased and blurred by ``blur``
    pixels (the penumbra). Zero without a light from above."""
    canvas = np.zeros(size, np.float32)
    d = light.direction.double()
    if float(d[1]) >= -0.1:
        return torch.from_numpy(canvas)
    for row in rows:
        v = verts[row].double()
        floor_y = float(objects.location[row, 1])
        reach = (floor_y - v[:, 1]).clamp(min=0) / -float(d[1])  # along -d down to the floor
        cap = max_reach * float(objects.dims[row].max()) / max(float(d[[0, 2]].norm()), 1e-6)
        ground = v - reach.clamp(max=cap)[:, None] * d
        ground[:, 1] = floor_y
        uv, front = _project(ground, K)
        if not bool(front.all()) or not bool(torch.isfinite(uv).all()) or float(uv.abs().max()) > 1e5:
            continue
        _splat_blurred_hull(canvas, uv.numpy(), blur)
    return torch.from_numpy(canvas)


def _grow(own: Tensor, before: ObjectTable, after: ObjectTable, origin: Tensor, stays: Tensor,
          transform: PixelFrame, raster_ids: Tensor | None = None, vis_ids: Tensor | None = None,
          min_seen: int = 0) -> tuple[Tensor, list[int]]:
    """``(own, grown rows)``: ``own (H_in, W_in)`` with the freed pixels each object that stays now covers (its mask
    gained them: amodal completion) given to it, the first such object in table order where several do.

    Two kinds of gained pixel are left to the fill instead (the photo cannot draw them; on the seed-33 tuning deletes
    they doubled the error of the fill there, docs/results/2026-11-28_cpu/session4/deletes/):

    - where ``raster_ids (H_in, W_in)`` (the source's fitted silhouettes) shows the object itself: the input saw the
      removed object there, so nothing of this one was in front of it; its fitted shape overshoots its true outline
      (a nearer car's template reaching into the deleted car behind it);
    - all of an object with fewer than ``min_seen`` pixels in ``vis_ids (H_in, W_in)``: the input never showed it,
      so its colour, and in fog its haze, would be a guess (a default-coloured car, dark and unhazed).

    ``min_seen`` 0 keeps every gained pixel (the behaviour before both rules)."""
    rows = stays.nonzero().flatten()
    if not len(rows):
        return own, []
    gained = after.mask[rows] & ~before.mask[origin[rows]]  # (S, h, w)
    grew = gained.flatten(1).any(1)
    if vis_ids is not None and min_seen > 0 and any_set(grew):
        seen = id_counts(vis_ids, after.instance_id[rows])
        grew &= seen >= min_seen
    if not any_set(grew):
        return own, []
    rows, gained = rows[grew], gained[grew]
    first = _first_true(gained)  # the first object (in table order) that gained each pixel
    labels = torch.where(any_along(gained, 0), after.instance_id[rows][first], torch.zeros_like(first))
    # Looked at in the input pixels of the labels' box alone: the upsampled labels are 0 outside it, where nothing
    # is given (the same map, without passes over the whole picture).
    window = input_window(transform, tuple(int(v) for v in mask_boxes(labels[None] != 0)[0]))
    if window is None:
        return own.clone(), []
    x0, y0, x1, y1 = window
    up = upsample_ids(labels.to(after.instance_id.dtype), transform, window)
    if raster_ids is not None and min_seen > 0:  # its own fitted shape in front of what the input showed there
        up = torch.where(raster_ids[y0:y1, x0:x1] == up, torch.zeros_like(up), up)
    here = own[y0:y1, x0:x1]
    new = (up != 0) & (here == 0)
    grown = own.clone()
    grown[y0:y1, x0:x1] = torch.where(new, up.to(own.dtype), here)
    drawn = torch.isin(after.instance_id[rows], up[new].unique())
    return grown, rows[drawn].tolist()


def _first_true(masks: Tensor) -> Tensor:
    """``(...)`` long index of the first True along the first dimension of ``masks (S, ...)`` bool, 0 where none is
    (``masks.to(torch.uint8).argmax(0)``, which reduces a strided dimension slowly): the masks written in reverse
    order, each over the later ones."""
    first = torch.zeros(masks.shape[1:], dtype=torch.long)
    for k in range(len(masks) - 1, -1, -1):
        first[masks[k]] = k
    return first


def _pixels_of(ids: Tensor, wanted: Tensor):
    """``lookup(i) -> (P,)`` ascending flat indices of the pixels of ``ids (H, W)`` equal to ``i`` (one of
    ``wanted``): one scan of the picture for all of them."""
    flat = ids.view(-1)
    pix = flat_nonzero(isin_ids(flat, wanted))
    at = flat[pix]
    return lambda i: pix[at == i]


def _recolor(out: Tensor, source: Tensor, owner: Tensor, recolor: Mapping[int, tuple[float, float, float]],
             objects: dict[int, dict], warnings: list[str], parts: Tensor | None = None) -> tuple[Tensor, Tensor]:
    """Step 5: each object of ``recolor`` repainted in ``out (3, H, W)`` where ``owner (H, W)`` holds its id.
    Given ``parts (H, W)`` (an object with geometry), the fitted mesh's body part sets the paint
    (:func:`~sdn3d.editing.photo.recolor.body_paint`): a coloured paint is repainted on every pixel of the object
    whose hue and chroma are the paint's, whatever part the template puts there (windows, tyres, lamps, plates and
    road are not of its hue); a grey paint (whose test grey road and glass pass too) on the body part, less the road
    its mask took in, lit or in the car's shadow (:func:`ground_in_mask` on the input's own pixels, which a fitted
    mesh looser than the car calls body); a light one there only where it is not much darker than its paint (a
    template's body over a van's rear glass), and also on the pixels of its lamp and plate faces
    (:data:`END_FACE_PARTS`) that are its paint in shade (:func:`_grey_paint_like`). ``source`` says
    :data:`RECOLORED` where a pixel of the input changed."""
    pixels_of = _pixels_of(owner, torch.tensor([int(i) for i in recolor], dtype=owner.dtype))
    flat = out.permute(1, 2, 0).reshape(-1, 3).clone()
    codes = source.view(-1).clone()
    for iid, rgb in recolor.items():
        pix = pixels_of(int(iid))
        body_part = parts is not None and len(pix) > 0 and bool((parts.view(-1)[pix] >= 0).any())
        reference = None
        if body_part:
            body_pix = pix[parts.view(-1)[pix] == int(Part.BODY)]
            coloured = len(body_pix) >= 8 and body_paint(srgb_to_lab(flat[body_pix].double()))[1]
            if coloured:
                # A coloured paint's hue tells paint from the rest on every pixel of the car: a template's lamp, plate
                # or glass faces that lie over paint (its front end covering a car's whole front) are repainted, and
                # the grey road and shadow the mask took in are left without being told apart (that test took a
                # coloured car's shaded lower body for road).
                reference = flat[body_pix]
            else:  # a grey paint: the body part, less the road the mask took in (grey too), and the end faces' paint
                ends = pix[torch.isin(parts.view(-1)[pix].long(), torch.tensor(END_FACE_PARTS))]
                pix = body_pix
                road = None
                if bool((codes[pix] == INPUT).any()):
                    picture = flat.view(*owner.shape, 3).permute(2, 0, 1)
                    road = ground_in_mask(picture, (owner == int(iid)) & (source == INPUT)).view(-1)
                    pix, ends = pix[~road[pix]], ends[~road[ends]]
                body_lab = srgb_to_lab(flat[pix].double())
                light = _light_paint(body_lab)
                if light is not None:  # a light paint: its body part and its end faces where they are its colour
                    pix = torch.cat([pix[_grey_paint_like(body_lab, light)],
                                     ends[_grey_paint_like(srgb_to_lab(flat[ends].double()), light)]])
                elif len(body_lab) >= 8:  # a dark paint: its whole body part less its tyres where the picture has them
                    pix = _dark_body(flat, owner == int(iid), parts, pix, float(body_lab[:, 0].median()), road)
        if not len(pix):
            warnings.append(f"recolor: object {iid} has no pixels in the picture")
            continue
        colors = flat[pix]
        new, body, stats = recolor_pixels(colors, tuple(rgb), body_part=body_part, reference=reference)
        flat[pix] = new
        repainted = pix[(new != colors).any(1)]
        codes[repainted] = torch.where(codes[repainted] == INPUT, RECOLORED, codes[repainted]).to(torch.uint8)
        objects.setdefault(int(iid), {}).update({"recolor": {"color": [round(float(c), 4) for c in rgb], **stats}})
    height, width = owner.shape
    return flat.view(height, width, 3).permute(2, 0, 1), codes.view(height, width)


def _dark_body(flat: Tensor, car: Tensor, parts: Tensor, pix: Tensor, paint_light: float,
               road: Tensor | None = None) -> Tensor:
    """Flat pixel indices of a dark paint (:func:`_recolor`): ``pix`` (its body part's, less the road) less the
    tyres the picture shows (:func:`_tyres_in_picture` on ``car (H, W)``, the picture ``flat (H * W, 3)`` sRGB,
    ``parts (H, W)``), plus the template tyre pixels they freed (paint where the template's wheel was misplaced) that
    are not ``road (H * W,)`` (:func:`ground_in_mask`; None: none). Black rubber is as dark as black paint: without
    this the black car of the real frame in ``tests/data`` got blue tyres."""
    height, width = car.shape
    at_tyre, gained, _, _ = _tyres_in_picture(flat, car, parts, paint_light)
    if road is not None:
        gained &= ~road.view(height, width)
    return torch.cat([pix[~at_tyre.view(-1)[pix]], flat_nonzero(gained)])


def _tyres_in_picture(flat: Tensor, car: Tensor, parts: Tensor,
                      paint_light: float) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """``(tyres (H, W) bool, freed (H, W) bool, wheel_at (H, W, 2), wheels (N, 4))``: a dark car's tyres where the
    picture ``flat (H * W, 3)`` sRGB shows them, its fitted template's tyre pixels they left, where each moved template
    tyre pixel's point lies on the real wheel (picture pixel coordinates ``(x, y)``, NaN elsewhere) and the real
    tyres' ellipses ``(x, y, semi-axis x, semi-axis y)`` (
    :func:`~sdn3d.editing.photo.recolor.registered_tyres` of the template's tyre pixels of ``parts (H, W)`` on its
    pixels ``car (H, W)``, paint of median CIE L* ``paint_light``), in the car's box."""
    height, width = car.shape
    at_tyre = torch.zeros_like(car)
    freed = torch.zeros_like(car)
    wheel_at = torch.full((height, width, 2), math.nan, dtype=torch.float64)
    if not any_set(car):
        return at_tyre, freed, wheel_at, torch.zeros(0, 4, dtype=torch.float64)
    x0, y0, x1, y1 = (int(v) for v in mask_boxes(car[None])[0])
    lab = srgb_to_lab(flat.view(height, width, 3)[y0:y1, x0:x1].reshape(-1, 3).double()).view(y1 - y0, x1 - x0, 3)
    window = car[y0:y1, x0:x1]
    tyres, gained, at, wheels = registered_tyres(lab, window, window & (parts[y0:y1, x0:x1] == int(Part.TYRE)),
                                                 paint_light)
    at_tyre[y0:y1, x0:x1] = tyres
    freed[y0:y1, x0:x1] = gained
    corner = torch.tensor([x0, y0], dtype=torch.float64)
    wheel_at[y0:y1, x0:x1] = at + corner
    wheels[:, :2] += corner
    return at_tyre, freed, wheel_at, wheels


def _dark_car_tyres(image: Tensor, ids: Tensor, parts: Tensor,
                    iid: int) -> tuple[Tensor, Tensor, Tensor, Tensor, Tensor] | None:
    """``(tyres, freed, moved, moved_at (M, 2), wheels (N, 4))``: flat pixel indices of car ``iid`` of the instance map
    ``ids (H, W)`` where its fitted template's part map ``parts (H * W,)`` is wrong about its wheels: its tyres where
    the picture ``image (3, H, W)`` shows them, the template tyre pixels they left, and the template tyre pixels moved
    onto a real wheel with the ``(x, y)`` where each one's point lies on it; the real tyres' ellipses
    (:func:`_tyres_in_picture`); None for a car that is not a dark paint, whose template keeps its wheels. A dark
    paint is the body part's pixels' median CIE L* under :data:`~sdn3d.editing.photo.recolor.DARK_PAINT_L`, not
    coloured (:func:`~sdn3d.editing.photo.recolor.body_paint`,
    as :func:`_recolor` tells it)."""
    # The car's pixels found by one pass over the picture, the rest looked at in its box alone: its pixels there in
    # row order are the picture's in its order (the same values, without four more passes and a copy of the picture
    # per car).
    height, width = ids.shape
    car_pix = flat_nonzero(ids.view(-1) == iid)
    body_pix = car_pix[parts[car_pix] == int(Part.BODY)]
    if len(body_pix) < 8:
        return None
    body_lab = srgb_to_lab(image.reshape(3, -1)[:, body_pix].T.contiguous().double())  # (N, 3) rows, as gathered
    paint_light = float(body_lab[:, 0].median())
    if paint_light >= DARK_PAINT_L or body_paint(body_lab)[1]:
        return None
    y0, y1 = int(car_pix[0]) // width, int(car_pix[-1]) // width + 1
    cols = car_pix % width
    x0, x1 = int(cols.min()), int(cols.max()) + 1
    car = ids[y0:y1, x0:x1] == iid
    box_flat = image[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3)
    tyres, freed, wheel_at, wheels = _tyres_in_picture(box_flat, car, parts.view(height, width)[y0:y1, x0:x1],
                                                       paint_light)

    def in_picture(mask: Tensor) -> Tensor:  # flat picture indices of a box's mask, in the picture's order
        ys, xs = mask.nonzero(as_tuple=True)
        return (ys + y0) * width + (xs + x0)

    corner = torch.tensor([x0, y0], dtype=torch.float64)  # the box's points in picture coordinates
    moved = torch.isfinite(wheel_at[..., 0])
    wheels[:, :2] += corner  # _tyres_in_picture's own tensor
    return in_picture(tyres), in_picture(freed), in_picture(moved), wheel_at[moved] + corner, wheels


#: Parts whose template faces often lie over a car's paint (a template's lamp band and plate cover much of a real
#: car's front or back): :func:`_recolor` repaints their pixels of a light grey paint's colour.
END_FACE_PARTS = (int(Part.FRONT_LIGHTS), int(Part.TAIL_LIGHTS), int(Part.PLATE))
#: :func:`_grey_paint_like`: an end face's pixel is a light grey paint's when its CIE L* is at least this share of the
#: paint's median and its chroma under :data:`GREY_PAINT_CHROMA` (a dark grille or a red lamp is not; a white car's
#: front in its own shade is 0.7 of its lit top, L* 62 against 88, on the seed-35 tuning tree).
GREY_END_LIGHTNESS = 0.6
#: :func:`_grey_paint_like`'s chroma bound (CIE76 a*b*), as :func:`~sdn3d.editing.photo.recolor.body_paint`'s grey
#: test (1.5 x its ``min_chroma``).
GREY_PAINT_CHROMA = 15.0


def _light_paint(body_lab: Tensor) -> Tensor | None:
    """The median CIE L* of a grey paint's body part pixels ``body_lab (Q, 3)`` CIE Lab; None where the paint is dark
    (under :data:`~sdn3d.editing.photo.recolor.DARK_PAINT_L`: its colour is the grille's, the tyres' and the glass')
    or there are fewer than 8 pixels."""
    if len(body_lab) < 8:
        return None
    light = body_lab[:, 0].median()
    return None if float(light) < DARK_PAINT_L else light


def _grey_paint_like(lab: Tensor, light: Tensor) -> Tensor:
    """``(P,)`` bool: which of ``lab (P, 3)`` CIE Lab colours (an end face's, or the body part's own) are a light grey
    paint of median lightness ``light`` (:func:`_light_paint`): not much darker than it (:data:`GREY_END_LIGHTNESS`),
    and grey."""
    return (lab[:, 0] >= GREY_END_LIGHTNESS * light) & (lab[:, 1:].norm(dim=1) < GREY_PAINT_CHROMA)


def render_photo(original: Tensor, transform: PixelFrame, scene: SceneCode, edited: SceneCode,
                 bank: MeshBank | None = None, settings: PhotoSettings | None = None,
                 recolor: Mapping[int, tuple[float, float, float]] | None = None,
                 generated: Tensor | None = None, source: PhotoSource | None = None) -> PhotoResult:
    """Draw the edit of ``scene`` into ``edited`` with the input's own pixels (module doc).

    Args:
        original: ``(3, H_in, W_in)`` the input at its resolution, uint8 or float in [0, 1].
        transform: how the input became the scenes' working image.
        scene, edited: the de-rendered scene and its edit (:func:`~sdn3d.editing.apply.apply_edits`).
        bank: the objects' template meshes (default: the 8 templates).
        recolor: ``{instance id: sRGB paint}`` of objects to repaint (``recolor`` ops with a named colour).
        generated: ``(3, h, w)`` the generator's edited picture at the working size, for ``fill='generator'``.
        source: what a previous call on the same ``original``, ``scene``, ``transform`` and ``settings`` computed from
            the unedited scene alone (:class:`PhotoSource`; the result is the same bit for bit); None: made here.

    Returns:
        :class:`PhotoResult`; pixels no edit touches are the input's, bit for bit.
    """
    settings = settings or PhotoSettings()
    bank = bank or default_bank()
    recolor = dict(recolor or {})
    w_in, h_in = transform.input_size
    if tuple(original.shape) != (3, h_in, w_in):
        raise ValueError(f"original {tuple(original.shape)} is not (3, H, W) of the transform's input size "
                         f"{tuple(transform.input_size)}")
    if settings.fill == "generator" and generated is None:
        raise PhotoSettingsError("photo.fill=generator needs the generator's picture (the textural branch)")
    size = (h_in, w_in)
    if source is None:
        source = PhotoSource(original, transform, scene, bank, settings, max_fills=0)
    source.check(original, scene, transform, settings)
    photo_source = source
    image, K = source.image, source.K
    before, after = scene.objects, edited.objects
    warnings: list[str] = []

    # Which objects stay, move, go, grow (step 1).
    origin = _origins(before, after)
    stays = torch.zeros(len(after), dtype=torch.bool)
    has = origin >= 0
    same_id = has & (after.instance_id == before.instance_id[origin.clamp(min=0)])
    if any_set(same_id):
        ra = same_id.nonzero().flatten()
        stays[ra] = _same_pose(before, after, origin[ra], ra)
    moved = ~stays & has & after.has_geometry
    gone_ids = before.instance_id[~torch.isin(before.instance_id, after.instance_id[stays])]
    src_ids, vis_ids = source.src_ids, source.vis_ids
    staying = isin_ids(src_ids, after.instance_id[stays])  # input pixels of the objects that stay
    own = torch.where(staying, src_ids, torch.zeros_like(src_ids))
    # Freed pixels an object that stays now covers (amodal completion in apply_edits).
    own, grown_rows = _grow(own, before, after, origin, stays, transform, source.outline_ids,
                            source.vis_ids, settings.grow_min_seen)

    src = source.raster
    src_row_to_mesh = source.row_to_mesh

    # Light (step 4): visible pixels of every source object with geometry; only when something is drawn.
    light = None
    src_normals = None
    gone_rows = [int(b) for b in torch.isin(before.instance_id, gone_ids).nonzero().flatten().tolist()
                 if bool(before.has_geometry[b])]
    # fill='rays' always takes a removed car's effects (its fitted silhouette and shadow): it was tuned with them.
    effects = ((settings.delete_effects or settings.fill in RAY_FILLS) and bool(gone_rows)
               and settings.fill != "generator")
    moved_rows = moved.nonzero().flatten().tolist()
    casts = settings.cast_shadow and bool(moved_rows)
    lit_effects = effects and settings.fill not in RAY_FILLS  # rays find the shadow by its darkness: no light needed
    if (settings.relight or lit_effects or casts) and len(src.rows) and (any_set(moved) or grown_rows
                                                                          or lit_effects):
        src_normals, light = source.light()
    shade = light.shade if light is not None and settings.relight else None

    # Input pixels no object's mask reaches (with the masks' erosion as a margin): no template point is there.
    covered = src_ids != 0
    background = ~dilate_square(covered, photo_source.erode)
    # Vacated pixels (step 2); the source pixels of the objects that stay are kept.
    keep = covered & staying
    hole = vacated_hole(src_ids, gone_ids, keep, settings)
    if effects:  # the removed objects' fitted silhouettes join the hole (their shadows: _remove_with_effects)
        fitted = isin_ids(photo_source.outline_ids, gone_ids)
        if settings.silhouette == "carved":  # the template where the input's masks rule it out is not the car
            fitted &= ~background
        hole = hole | (dilate_square(fitted, settings.hole_dilate_px) & ~keep)
    # With cast_shadow, a moved object's old shadow is relit (as a deleted one's with delete_effects).
    moved_from = {int(origin[a]) for a in moved_rows}
    relight_rows = [b for b in gone_rows if b in moved_from] if casts and light is not None and not effects else []
    hole_of_masks = hole
    if any_set(hole):  # thin things in front are put back over the fill: they are no source of it
        hole = hole | photo_source.in_front

    def removal() -> Tensor:
        """``(5, H, W)``: the filled picture, the relit matte (0 where nothing is relit) and the leftovers, kept
        together (the source state's fills; all three depend only on which objects left and which stayed)."""
        # The removal's 2D parts, shared with the 2D baselines: what of the removed objects neither their masks nor
        # their silhouettes took (a side mirror), filled after the hole, and the road's vanishing point (ray fills)
        # from the picture's edges around the removed objects, else the first removed car's fitted yaw.
        guides = removal_guides(image, K, photo_source.lab(), hole_of_masks, src_ids, gone_ids,
                                keep | photo_source.in_front, settings,
                                float(before.ry[gone_rows[0]]) if gone_rows else None)
        vp = guides.vanishing
        relit = torch.zeros(size, dtype=torch.float32)
        if settings.fill == "generator":
            filled = fill_hole(image, hole, settings, src_ids != 0, working_to_input(generated, transform))
        elif effects:  # the removed objects' shadows are relit or filled with the hole
            filled, relit = _remove_with_effects(image, hole, (src_ids != 0) & ~hole, before, gone_rows, K, light,
                                                 settings, vp, photo_source.lab())
        elif relight_rows:
            relit_image, relit = _relight_removed(image, hole, (src_ids != 0) & ~hole, before, relight_rows, K, light)
            filled = fill_hole(relit_image, hole, settings, src_ids != 0, vanishing=vp)
        else:
            filled = fill_hole(image, hole, settings, src_ids != 0, vanishing=vp, lab=photo_source.lab())
        filled = guides.fill_leftovers(filled, settings)
        return torch.cat([filled, relit[None].to(filled.dtype), guides.leftovers[None].to(filled.dtype)])

    if settings.fill == "generator":  # the generator's picture changes with every edit: nothing to keep
        removed_state = removal()
    else:  # the hole, its fill and its leftovers depend only on which objects left and which stayed
        stay_ids = after.instance_id[stays]
        removed_state = source.fill((tuple(sorted(gone_ids.tolist())), tuple(sorted(stay_ids.tolist()))), removal)
    out, matte, leftovers = removed_state[:3], removed_state[3], removed_state[4] > 0.5
    hole = hole | leftovers
    source = torch.where(hole, FILL, INPUT).to(torch.uint8)
    source = torch.where((matte > 0.02) & ~hole, RELIT, source).to(torch.uint8)
    source = torch.where(matte < 0, FILL, source).to(torch.uint8)  # a shadow filled with the hole

    # Cast shadows of moved objects at their new places: the fitted light's shadow of each posed mesh on its ground
    # plane, darkened by the gain measured on its shadow in the input (none found: no cast shadow).
    posed = None
    if casts and light is not None:
        posed = posed_meshes(after, bank)
        verts = {int(r): v.cpu() for r, v in zip(posed[0].tolist(), posed[1], strict=True)}
        objects_px = (src_ids != 0) & ~hole
        darken = torch.ones((3, *size), dtype=out.dtype)
        for a in moved_rows:
            b = int(origin[a])
            if a not in verts or not bool(before.has_geometry[b]):
                continue
            search, _, ring, road = _shadow_context(image, hole, objects_px, before, [b], K, light)
            gain = None if road is None else shadow_gain(image, dilate_square(search, 3) & ~hole & ~objects_px, ring,
                                                         road)
            if gain is None:
                continue
            cast = _cast_shadows(after, [a], verts, K, size, light, settings.cast_blur)
            cast = torch.where(own != 0, torch.zeros_like(cast), cast)
            darken = torch.minimum(darken, 1 + cast[None] * (1 / gain.float()[:, None, None] - 1))
            source = torch.where((cast > 0.02) & (source == INPUT), SHADOW, source).to(torch.uint8)
        out = out * darken

    # Contact shadows of moved objects, on the road only (drawn objects cover the rest below).
    if settings.contact_shadow > 0 and moved_rows:
        soft = _contact_shadow(after, moved_rows, K, size)
        soft = torch.where(own != 0, torch.zeros_like(soft), soft)
        out = out * (1 - settings.contact_shadow * soft)[None]
        source = torch.where((soft > 0.02) & (source == INPUT), SHADOW, source).to(torch.uint8)

    # Part of each pixel: the source's where an object stays at its place and shows there (drawn objects: _draw).
    # (the fitted outline's id at each pixel, where a mesh covers it, is the source's outline_ids; it is 0 where none
    # does, so an object's id there says a mesh covers the pixel)
    shows = (own.view(-1) != 0) & (own.view(-1) == photo_source.outline_ids.view(-1))
    parts_out = torch.where(shows, photo_source.parts, -1).to(torch.int8).view(size)
    # The recolour paints by the loft's face labels: a real car's pillars and roof rails above its belt are paint,
    # which the greenhouse's glass of parts_out (the transfer's, the generator's rule) would leave unpainted.
    recolor_parts = (torch.where(shows, photo_source.face_parts(), -1).to(torch.int8).view(size)
                     if recolor and settings.recolor_parts else None)

    # Target rasterization of the drawn objects (moved ones, and the ones that grew) at their poses.
    draw_rows = torch.tensor(sorted(set(moved_rows) | set(grown_rows)), dtype=torch.long)
    objects: dict[int, dict] = {}
    drawn_depth = torch.full(size, math.inf, dtype=torch.float64)
    if len(draw_rows):
        tgt_all_rows, tgt_verts, tgt_faces = posed if posed is not None else posed_meshes(after, bank)
        keep = torch.isin(tgt_all_rows.cpu(), draw_rows)
        tgt = _rasterize(tgt_all_rows.cpu()[keep], tgt_verts.cpu()[keep], tgt_faces.cpu()[keep], K, size)
        drawn_depth = tgt.frags.in_image(tgt.frags.depth, math.inf)[0].double()
        sources = origin[draw_rows]
        drawn_ids = before.instance_id[sources[sources >= 0]].tolist()  # the cars whose input pixels are drawn
        out, source, objects = _draw(out, source, photo_source.flat_image(), own, src, tgt, before, after, origin,
                                     moved, src_row_to_mesh, src_ids, vis_ids, K, settings, shade, src_normals,
                                     warnings, bank, photo_source.parts, parts_out, background, photo_source.pyramid,
                                     photo_source.registered_parts(drawn_ids), photo_source.visible_pixels,
                                     photo_source.part_examples, photo_source.clear_air, photo_source.lamp_air,
                                     recolor_parts,
                                     photo_source.registered_wheels(drawn_ids), photo_source.real_wheels,
                                     predicted_masks(scene.meta, after.instance_id), photo_source.seen_air)
        if settings.silhouette == "carved" and settings.mask_view_deg > 0:
            out, source = _paste_near_views(out, source, own, before, after, origin, moved_rows, src_ids,
                                            photo_source.work_ids, transform, photo_source.outline_ids, K, settings,
                                            objects, photo_source.pyramid)
        for a in moved_rows:
            if int(after.instance_id[a]) not in objects:
                uv, front = _project(_box_floor(after, a, 1.0), K)
                inside = bool((front & (uv[:, 0] >= 0) & (uv[:, 0] < w_in) & (uv[:, 1] >= 0)
                               & (uv[:, 1] < h_in)).any())
                why = "is hidden behind nearer objects" if inside else "lies outside the picture"
                warnings.append(f"object {int(after.instance_id[a])}: after the edit it {why} (nothing drawn)")

    # Recolour (step 5): the object's pixels in the result.
    final_own = own.clone()
    for iid, info in objects.items():
        final_own.view(-1)[info.pop("_pixels")] = iid
    if recolor:
        out, source = _recolor(out, source, final_own, recolor, objects, warnings, recolor_parts)
    # Thin things in front of a car stay in front of what the edit drew there, unless a car now stands nearer than
    # the one they hid (their depth is at most that car's).
    if any_set(photo_source.in_front):  # (none found: nothing to put back)
        src_depth = src.frags.in_image(src.frags.depth, math.inf)[0].double()
        front = photo_source.in_front & (source != INPUT) & ~(drawn_depth < src_depth - 0.5)
        out = torch.where(front[None], image, out)
        source = torch.where(front, IN_FRONT, source).to(torch.uint8)
    return PhotoResult(_into_original(out, source != INPUT, original), source, light, objects, warnings, parts_out)


def _into_original(out: Tensor, changed: Tensor, original: Tensor) -> Tensor:
    """``(3, H, W)`` ``original`` with its ``changed (H, W)`` pixels taken from ``out (3, H, W)`` float, clamped to
    [0, 1] (and rounded to uint8 for a uint8 original); only the box of the changed pixels is converted."""
    result = original.clone()
    rows, cols = any_along(changed, 1).nonzero().flatten(), any_along(changed, 0).nonzero().flatten()
    if not len(rows):
        return result
    y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
    box = out[:, y0:y1, x0:x1].clamp(0, 1)
    if original.dtype == torch.uint8:
        box = (box * 255 + 0.5).floor().clamp(0, 255).to(torch.uint8)
    else:
        box = box.to(original.dtype)
    result[:, y0:y1, x0:x1] = torch.where(changed[y0:y1, x0:x1][None], box, original[:, y0:y1, x0:x1])
    return result


def _shares(codes: Tensor) -> dict[str, float]:
    """Shares of an object's drawn pixels by their :data:`SOURCE_NAMES` ``codes (P,)``: ``photo``, ``mirror``,
    ``part`` and flat paint (``fallback``: :data:`FLAT_CODES`), rounded to 4 places."""
    flat = torch.isin(codes, torch.tensor(FLAT_CODES, dtype=codes.dtype))
    return {"photo": round(float((codes == PHOTO).double().mean()), 4),
            "mirror": round(float((codes == MIRROR).double().mean()), 4),
            "part": round(float((codes == PART).double().mean()), 4), "fallback": round(float(flat.double().mean()), 4)}


def _view_change(before: ObjectTable, after: ObjectTable, b: int, a: int) -> float:
    """Radians the camera's view of an object turned between its rows ``b`` of ``before`` and ``a`` of ``after`` (its
    yaw against the line of sight, the KITTI observation angle): 0 for a pure move along the line of sight."""
    def alpha(t: ObjectTable, r: int) -> Tensor:
        c = t.center[r].double()
        return observation_angle(t.ry[r].double(), c[0], c[2])
    return abs(float(wrap_angle(alpha(after, a) - alpha(before, b))))


def _paste_near_views(out: Tensor, source: Tensor, own: Tensor, before: ObjectTable,
                      after: ObjectTable, origin: Tensor, moved_rows: list[int], src_ids: Tensor, work_ids: Tensor,
                      transform: PixelFrame, template_ids: Tensor, K: Tensor, settings: PhotoSettings,
                      objects: dict[int, dict], pyramid_of: Callable[[int], list[Tensor]]) -> tuple[Tensor, Tensor]:
    """Each moved object whose view hardly changed (at most ``settings.mask_view_deg``) and whose fitted outline
    ``template_ids (H, W)`` (:func:`_raster_ids` of the input) overlaps its mask in ``src_ids`` at an IoU of at most
    ``settings.paste_max_iou`` takes its input mask's pixels
    moved by the 2D affine map its 3D box makes between its poses, each sampled where that map takes it (code
    ``photo``), over its drawn template's pixels and onto pixels no object covers: when the view stays, the input's
    own outline and pixels are nearer the truth than a template's that does not match them (the parts the mask never
    showed stay the template's), sampled from the input's pyramid ``pyramid_of(levels)`` (:meth:`PhotoSource.pyramid`).
    ``objects`` gains ``outline_iou`` for each object under the view limit and, where pasted, the added pixels
    (``_pixels``, ``pixels``, shares, ``mask``: the pasted share)."""
    height, width = own.shape
    drawn = torch.zeros(height * width, dtype=torch.bool)
    for info in objects.values():
        drawn[info["_pixels"]] = True
    free = ~drawn & (own.view(-1) == 0)
    pyramid = None
    flat_out = out.permute(1, 2, 0).reshape(-1, 3).clone()
    source = source.clone()
    for a in moved_rows:
        b = int(origin[a])
        name = int(after.instance_id[a])
        if b < 0 or name not in objects or _view_change(before, after, b, a) > math.radians(settings.mask_view_deg):
            continue
        mine = src_ids == before.instance_id[b]
        outline = template_ids == before.instance_id[b]
        iou = float((mine & outline).sum()) / max(float((mine | outline).sum()), 1.0)
        objects[name]["outline_iou"] = round(iou, 4)
        if iou > settings.paste_max_iou:
            continue
        ends = []
        for table, r in ((after, a), (before, b)):
            corners = box_corners(table.dims[r:r + 1].double(), table.ry[r:r + 1].double(),
                                  table.center[r:r + 1].double())[0]
            uv, front = _project(torch.cat([corners, table.center[r:r + 1].double()]), K)
            ends.append((uv, bool(front.all())))
        (uv_a, ok_a), (uv_b, ok_b) = ends
        if not (ok_a and ok_b):
            continue
        # Target pixel -> input pixel: least squares over the box's corners and centre (exact for a pure 2D move).
        design = torch.cat([uv_a, torch.ones(len(uv_a), 1, dtype=torch.float64)], 1)
        affine = torch.linalg.lstsq(design, uv_b).solution  # (3, 2)
        ys, xs = nonzero_yx(mine)
        if not len(ys):
            continue
        # The window: the input mask's box carried to the target (the inverse map).
        box = torch.tensor([[xs.min(), ys.min()], [xs.max(), ys.min()], [xs.min(), ys.max()], [xs.max(), ys.max()]],
                           dtype=torch.float64)
        ends_q = torch.linalg.solve(affine[:2].T, (box - affine[2]).T).T
        lo = ends_q.amin(0).floor().clamp(min=0)
        hi = ends_q.amax(0).ceil() + 2
        x0, y0 = int(lo[0]), int(lo[1])
        x1, y1 = min(int(hi[0]), width), min(int(hi[1]), height)
        if x1 <= x0 or y1 <= y0:
            continue
        v, u = torch.meshgrid(torch.arange(y0, y1, dtype=torch.float64), torch.arange(x0, x1, dtype=torch.float64),
                              indexing="ij")
        q = torch.stack([u.flatten(), v.flatten(), torch.ones(u.numel(), dtype=torch.float64)], 1)
        p = q @ affine
        inside, _ = _nearest_pixel(p[:, :2], torch.ones(len(p), dtype=torch.bool), (height, width))
        flat_q = (v.flatten().long() * width + u.flatten().long())
        info = objects[name]
        this = torch.zeros(height * width, dtype=torch.bool)
        this[info["_pixels"]] = True
        # The mask's coverage sampled bilinearly at the working size, where the mask was made: a mask enlarged (by the
        # input's size, and by a zoom) keeps a smooth outline where it covers half, not a staircase of working pixels.
        uv_work = (p[:, :2] + 0.5) * torch.tensor(transform.scale, dtype=torch.float64) - 0.5 - torch.tensor(
            transform.offset, dtype=torch.float64)
        coverage = (work_ids == before.instance_id[b]).float()[None, None]
        cover = _sample([coverage], uv_work, torch.zeros(len(p), dtype=torch.float64))[:, 0].double()
        hit = inside & (cover >= 0.5) & (free | this)[flat_q]
        if not any_set(hit):
            continue
        if pyramid is None:
            pyramid = pyramid_of(settings.max_level)
        shrink = float(torch.linalg.det(affine[:2]).abs().sqrt())  # input pixels per target pixel
        level = torch.full((int(hit.sum()),), max(math.log2(max(shrink, 1e-6)), 0.0), dtype=torch.float64)
        pasted = flat_q[hit]
        flat_out[pasted] = _sample(pyramid, p[hit, :2], level).float()
        codes = source.view(-1)
        codes[pasted] = PHOTO
        free[pasted] = False
        added = pasted[~this[pasted]]
        info["_pixels"] = torch.cat([info["_pixels"], added])
        total = info["pixels"] + len(added)
        info.update(_shares(codes[info["_pixels"]]), pixels=total, mask=round(len(pasted) / total, 4))
    return flat_out.view(height, width, 3).permute(2, 0, 1), source


def _source_light(src: _Raster, vis_ids: Tensor, before: ObjectTable,
                  image: Tensor) -> tuple[Tensor, LightEstimate | None]:
    """``(normals (H*W, 3) float64 of the source rasterization, the light fitted to the visible car pixels or
    None)`` (step 4 of the module doc: the unedited scene alone decides both)."""
    normals = normal_map(src.frags, src.verts, src.faces).permute(0, 2, 3, 1)  # (1, h, w, 3) of the box
    src_normals = src.frags.in_image(normals, 0.0)[0].reshape(-1, 3).double()
    # the covered pixels whose mesh is the object the eroded mask shows there
    pix = src.frags.covered()
    mesh_at = src.frags.mesh_at(pix)
    vis = vis_ids.view(-1)[pix] == before.instance_id[src.rows[mesh_at]]
    pix, mesh_at = pix[vis], mesh_at[vis]
    pixels = image.permute(1, 2, 0).reshape(-1, 3)
    body = body_pixels(pixels[pix], mesh_at)
    pix, mesh_at = pix[body], mesh_at[body]
    if len(pix) > 6000:  # evenly spread: plenty for four numbers and the albedos
        spread = torch.linspace(0, len(pix) - 1, 6000).long()
        pix, mesh_at = pix[spread], mesh_at[spread]
    light = fit_light(pixels[pix], src_normals[pix], mesh_at)
    if light is not None and light.gain < 0.05:
        light = None  # no better than constant shading: do not re-shade
    return src_normals, light


def _draw(out: Tensor, source: Tensor, img_flat: Tensor, own: Tensor, src: _Raster, tgt: _Raster,
          before: ObjectTable, after: ObjectTable, origin: Tensor, moved: Tensor, src_row_to_mesh: Tensor,
          src_ids: Tensor, vis_ids: Tensor, K: Tensor, settings: PhotoSettings, shade, src_normals: Tensor | None,
          warnings: list[str], bank: MeshBank, parts_src: Tensor, parts_out: Tensor,
          background: Tensor, pyramid_of: Callable[[int], list[Tensor]], registered: Tensor,
          visible_of: Callable[[int], Tensor], examples_of: Callable[[int], tuple[_PartExamples, Tensor]],
          clear_air: Callable[[int], bool], lamp_air: Callable[[int], LampAir],
          face_parts_out: Tensor | None = None, wheels: Tensor | None = None,
          real_wheels: Callable[[int], Tensor | None] | None = None,
          predicted: Tensor | None = None,
          seen_air: Callable[[int], LampAir] | None = None) -> tuple[Tensor, Tensor, dict[int, dict]]:
    """Steps 1 and 3 of the module doc for the objects of ``tgt``: who wins each pixel, then transfer.
    ``img_flat (H * W, 3)``: the input's pixels row by row (:meth:`PhotoSource.flat_image`).
    ``background (H, W)``: input pixels no object's mask reaches (with a margin): a template point that projects
    there is not the object's (``silhouette='carved'``); ``pyramid_of(levels)``: the input's pyramid
    (:meth:`PhotoSource.pyramid`); ``registered (H * W,)``: the input's part map with dark cars' tyres where it shows
    them (:meth:`PhotoSource.registered_parts`): a point whose input pixel the registration relabelled (a template's
    body over the car's real wheel, its tyre over paint) is not drawn from that pixel; ``wheels (H * W, 2)`` (None:
    none moved; :meth:`PhotoSource.registered_wheels`): where a moved template tyre's pixels lie on the real wheel,
    which a tyre point read there is drawn from (:func:`_on_real_wheel`); ``real_wheels(instance id)`` (None: none):
    a car's real wheels where the input shows them (:meth:`PhotoSource.real_wheels`), which a wheel face the input
    never showed is drawn from (:func:`_from_real_wheels`). ``visible_of(instance id)``, ``examples_of(row of
    before)``, ``clear_air(row of before)`` and ``lamp_air(row of before)``: a car's eroded mask pixels, its part
    examples with all its visible colours, whether it is seen through clear air and the air its lamps are read
    through (:meth:`PhotoSource.visible_pixels`, :meth:`PhotoSource.part_examples`, :meth:`PhotoSource.clear_air`,
    :meth:`PhotoSource.lamp_air`: made once per source). ``parts_out`` gets the
    drawn pixels' parts, ``face_parts_out`` (None: none) their loft face labels (the recolour's). ``predicted (N,)``
    bool over ``after``'s rows (None: none): objects whose masks are predictions; one that stays draws none of its
    freed pixels when they would be more than :attr:`PhotoSettings.grow_predicted_share` times its mask's pixels in
    ``src_ids`` (the fill keeps them). ``seen_air(row of before)`` (None: read off its colours at each lookup): the
    air a car is seen through, as its part lookups' defaults take it (:meth:`PhotoSource.seen_air`)."""
    height, width = own.shape
    covered = tgt.frags.covered()
    at_tgt, at_src = tgt.frags.locate(covered), src.frags.locate(covered)
    row = tgt.rows[tgt.frags.mesh_at(at_tgt)]  # row in `after`
    iid = after.instance_id[row]
    own_flat = own.view(-1)[covered]
    is_moved = moved[row]
    # Depth of what stays at each pixel: its rendered source depth where the source shows it, else its centre's.
    stay_row = torch.searchsorted(before.instance_id.sort().values, own_flat.clamp(min=0))
    order = before.instance_id.argsort()
    stay_b = order[stay_row.clamp(max=max(len(order) - 1, 0))] if len(order) else stay_row
    src_mesh_here = src.frags.mesh_at(at_src)
    stay_depth = torch.where(src_mesh_here == src_row_to_mesh[stay_b], src.frags.depth_at(at_src).double(),
                             before.center[stay_b, 2].double())
    t_depth = tgt.frags.depth_at(at_tgt).double()
    # A moved object wins where nothing stays or it is nearer; one that grew draws only the pixels it gained.
    gained = (own_flat == iid) & (src_ids.view(-1)[covered] != iid)
    wins = torch.where(is_moved, (own_flat == 0) | (t_depth < stay_depth), gained)
    pix, row, iid, is_moved, z_t = covered[wins], row[wins], iid[wins], is_moved[wins], t_depth[wins]
    if not len(pix):
        return out, source, {}
    mesh, vid, bary, normal_t, tri_t, point_t = _surface_points(tgt, pix)
    b_row = origin[row]
    s_mesh = src_row_to_mesh[b_row]
    has_src = s_mesh >= 0
    s_mesh_c = s_mesh.clamp(min=0)
    tri_s = src.verts[s_mesh_c[:, None], vid] if len(src.rows) else torch.zeros(len(pix), 3, 3, dtype=torch.float64)
    point_s = sum3(bary[..., None] * tri_s, 1)
    # Mirror across the vehicle's left-right plane (local z = 0).
    rot = roty(before.ry.double())[b_row.clamp(min=0)]  # (P, 3, 3): each row's, looked up (the same values)
    centre = before.center[b_row.clamp(min=0)].double()
    flip = torch.tensor([1.0, 1.0, -1.0], dtype=torch.float64)
    local = torch.einsum("pji,pj->pi", rot, point_s - centre) * flip
    point_m = torch.einsum("pij,pj->pi", rot, local) + centre
    if settings.silhouette == "carved" and any_set(has_src):
        # A template point the input's mask rules out (module doc, step 3) is not drawn: what shows there is the
        # picture behind the object, as in the 2D paste.
        # (an object the input does not show at all has no outline to carve by)
        shown = ids_present(src_ids, before.instance_id)[b_row.clamp(min=0)]
        inside = ~has_src | ~shown | (_in_silhouette(point_s, background, K) & _in_silhouette(point_m, background, K))
        if not bool(inside.all()):
            k = inside.nonzero().flatten()
            pix, row, iid, is_moved, mesh, vid, bary, normal_t, tri_t, point_t, z_t = (
                pix[k], row[k], iid[k], is_moved[k], mesh[k], vid[k], bary[k], normal_t[k], tri_t[k], point_t[k],
                z_t[k])
            b_row, s_mesh, has_src, s_mesh_c, tri_s, point_s, rot, centre, point_m = (
                b_row[k], s_mesh[k], has_src[k], s_mesh_c[k], tri_s[k], point_s[k], rot[k], centre[k], point_m[k])
            if not len(pix):
                return out, source, {}
    normal_s = F.normalize(torch.linalg.cross(tri_s[:, 1] - tri_s[:, 0], tri_s[:, 2] - tri_s[:, 0], dim=-1), dim=-1)
    # Same face, same winding: orient the source normal as the target one was (edits are rigid).
    raw_t = F.normalize(torch.linalg.cross(tri_t[:, 1] - tri_t[:, 0], tri_t[:, 2] - tri_t[:, 0], dim=-1), dim=-1)
    normal_s = torch.where((sum3(raw_t * normal_t) < 0)[:, None], -normal_s, normal_s)
    src_iid = before.instance_id[b_row.clamp(min=0)]
    ok_photo, uv_photo = _visible(point_s, s_mesh, src_iid, src, vis_ids, K, settings.depth_tolerance)
    # A surface seen edge-on is not stretched over a side the edit turns to face the camera; where the edit shows it
    # hardly more squarely than the input did (a move that keeps the view), it is the input's all the same.
    cos_t = _view_cos(point_t, normal_t)
    squarely = (torch.clamp(cos_t / settings.view_stretch, max=settings.min_view_cos) if settings.view_stretch > 0
                else torch.full_like(cos_t, settings.min_view_cos))
    cos_photo = _view_cos(point_s, normal_s)
    ok_photo &= has_src & (cos_photo >= squarely)
    normal_m = torch.einsum("pij,pj->pi", rot, torch.einsum("pji,pj->pi", rot, normal_s) * flip)
    ok_mirror, uv_mirror = _visible(point_m, s_mesh, src_iid, src, vis_ids, K, settings.depth_tolerance)
    cos_mirror = _view_cos(point_m, normal_m)
    t_part = _part_map(tgt, after, bank, pix)
    relabelled = registered != parts_src  # the template's wheel where the car's is not: those pixels are the other part
    if any_set(relabelled):
        no_wheel = torch.zeros(len(pix), dtype=torch.bool)
        moved_p, on_p, moved_m, on_m = no_wheel, no_wheel, no_wheel, no_wheel
        if wheels is not None:  # a tyre point read where its template's tyre lay is read off the real wheel
            tyre = t_part == int(Part.TYRE)
            uv_photo, moved_p, on_p = _on_real_wheel(uv_photo, ok_photo & tyre, wheels, registered, (height, width))
            uv_mirror, moved_m, on_m = _on_real_wheel(uv_mirror, ok_mirror & tyre, wheels, registered, (height, width))
            if real_wheels is not None and bool((moved_p | moved_m).any()):
                # its faces are drawn from the real wheel whole (_from_real_wheels): the template tyre's box mapped
                # onto the real one and the face's own offsets drew two rims, half a face each
                face = torch.zeros(len(pix), dtype=torch.bool)
                templates = after.template_id[row]
                for template in templates[moved_p | moved_m].unique().tolist():
                    k = ((moved_p | moved_m) & (templates == template)).nonzero().flatten()
                    face[k] = _wheel_faces(bank, template, vid[k], bary[k])[1]
                on_p &= ~face
                on_m &= ~face
        ok_photo &= torch.where(moved_p, on_p, ~relabelled[_nearest_pixel(uv_photo, ok_photo, (height, width))[1]])
        ok_mirror &= torch.where(moved_m, on_m, ~relabelled[_nearest_pixel(uv_mirror, ok_mirror, (height, width))[1]])
    ok_mirror &= has_src & ~ok_photo & (cos_mirror >= squarely)

    # Sampling level: how much smaller the object got here (depth ratio), only when it shrank.
    level = (z_t / point_s[:, 2].clamp(min=1e-3)).clamp(min=1.0).log2()
    pyramid = pyramid_of(settings.max_level)
    uv = torch.where(ok_photo[:, None], uv_photo, uv_mirror)
    color = _sample(pyramid, uv, level).double()
    n_src = torch.where(ok_photo[:, None], normal_s, normal_m)
    if shade is not None:
        ratio = (shade(normal_t) / shade(n_src).clamp(min=1e-3)).clamp(0.5, 2.0)
        color = color * ratio[:, None]
    seen = ok_photo | ok_mirror
    cos_src = torch.where(ok_photo, cos_photo, cos_mirror)  # the view each drawn colour was seen at

    # Fallback: the object's own body colour, de-shaded, shaded for the new normal; with unseen='parts' the same part
    # seen elsewhere on the car, where it faced the same way (_part_colors: its shading comes with it), a part never
    # seen in its default colour. Without a fitted light nothing is shaded (a guessed light from above darkened every
    # unseen side: 2-3 dB on the tuning seed's turns, docs/results/2026-11-28_cpu/session3/turns/).
    objects: dict[int, dict] = {}
    surface_shade = shade if shade is not None else _unshaded
    fallback = torch.zeros_like(color)
    codes = torch.where(ok_photo, PHOTO, torch.where(ok_mirror, MIRROR, FALLBACK)).to(torch.uint8)
    # img_flat is in the picture's dtype: the rows read are made float64 where gathered (the same values, exactly)
    by_parts = settings.unseen == "parts"
    drawn_rows = row.unique()
    drawn = torch.ones(len(pix), dtype=torch.bool)  # False: left to the fill (amodal='seen')
    flat_codes = torch.tensor(FLAT_CODES, dtype=torch.uint8)
    shown_cars = (src_row_to_mesh >= 0).nonzero().flatten().tolist()

    def wheel_for(b: int) -> tuple[Tensor, int] | None:
        """The real wheel (:meth:`PhotoSource.real_wheels`: ``(x, y, semi-axis x, semi-axis y)``, the largest) a wheel
        face of row ``b``'s car the input never showed is drawn from, and its source code: the car's own
        (:data:`PART`), else that of the car nearest in depth that shows one, both seen through clear air
        (:data:`ANOTHER_CAR`, as :func:`others_of`); None: no real wheel."""
        if real_wheels is None or b not in shown_cars:
            return None
        depth = before.center[:, 2].double().clamp(min=0.1)
        others = sorted((bb for bb in shown_cars if bb != b), key=lambda bb: abs(math.log(depth[bb] / depth[b])))
        for bb in [b] + (others if clear_air(b) else []):
            if bb != b and not clear_air(bb):
                continue
            found = real_wheels(int(before.instance_id[bb]))
            if found is not None:
                return found[(found[:, 2] * found[:, 3]).argmax()], PART if bb == b else ANOTHER_CAR
        return None

    def others_of(b: int) -> Callable[[int], _PartExamples]:
        """:func:`_part_colors`' ``others``: the examples of a part another car may lend (:func:`_lendable`) on the
        car nearest in depth to row ``b``'s that shows at least 8 of them, both cars seen through clear air
        (:func:`_clear_air`); none otherwise (in fog each car has its own air: a near car's tyres are dark where a far
        one's are grey; a lamp lent through two cars' air estimates came out too light on a fogged bus's never-seen
        tail lamps, docs/results/2026-11-30_cpu/session24/turn41/)."""
        def pool(part: int) -> _PartExamples:
            if b not in shown_cars or not clear_air(b):
                return _no_examples()
            depth = before.center[:, 2].double().clamp(min=0.1)
            # nearest first (a stable sort: ties keep table order), each car's examples made only when reached
            by_depth = sorted((bb for bb in shown_cars if bb != b), key=lambda bb: abs(math.log(depth[bb] / depth[b])))
            for bb in by_depth:
                if not clear_air(bb):
                    continue
                found = _lendable(examples_of(bb)[0], part)
                if len(found.part) >= 8:
                    return found
            return _no_examples()
        return pool

    for r in drawn_rows.tolist():
        sel = row == r
        b = int(origin[r])
        name = int(after.instance_id[r])
        visible_px = visible_of(int(before.instance_id[b])) if b >= 0 else pix[:0]
        if len(visible_px):
            colors = img_flat[visible_px].double()
            if src_normals is not None:
                s = surface_shade(src_normals[visible_px]).clamp(min=0.2)
                colors = colors / s[:, None]
            albedo = colors.median(0).values
        else:
            albedo = torch.full((3,), 0.5, dtype=torch.float64)
            warnings.append(f"object {name}: none of its surface is visible in the input; drawn in grey from its shape")
        s_new = surface_shade(normal_t[sel])
        fallback[sel] = albedo[None] * s_new[:, None]
        if settings.view_reflection > 0 and b >= 0:  # glass and paint seen from a new angle mirror more or less sky
            for part in REFLECTIVE_PARTS:
                here = sel & seen & (t_part == part)
                strength = _reflection_strength(examples_of(b)[0], part) if any_set(here) else None
                if strength is not None:
                    change = grazing(cos_t[here]) - grazing(cos_src[here])
                    color[here] += settings.view_reflection * strength[None] * change[:, None]
        if by_parts and b >= 0:
            unseen = sel & ~seen
            if any_set(unseen):
                car_examples, seen_colors = examples_of(b)
                body_albedo = albedo if len(visible_px) else None

                def lookup(points: Tensor, normals: Tensor, parts: Tensor, points_t: Tensor,
                           b: int = b, car_examples: _PartExamples = car_examples, seen_colors: Tensor = seen_colors,
                           body_albedo: Tensor | None = body_albedo) -> tuple[Tensor, Tensor, Tensor]:
                    """The part lookup (and a dark paint's reflection change) of never-seen points ``points (Q, 3)``
                    (source pose; ``points_t (Q, 3)`` at the new pose) facing ``normals (Q, 3)`` with ``parts (Q,)``:
                    ``(colour (Q, 3), code (Q,), rule (Q,))``, ``rule`` the code and the lamp band the point lies in
                    (:func:`_lamp_band`: its lamps may be drawn by another rule than its part's)."""
                    features = _part_features(before, b, points, normals)  # made once for both
                    alb, code, seen_at = _part_colors(b, car_examples, seen_colors, points, normals, parts, before,
                                                      body_albedo, others_of(b), air=lamp_air(b),
                                                      seen_air=None if seen_air is None else lambda: seen_air(b),
                                                      features=features)
                    if settings.view_reflection > 0 and PART_VIEW_REFLECTION:
                        alb = _reflect_part_colors(alb, code, seen_at, parts, points_t, normals, car_examples,
                                                   settings.view_reflection)
                    band = _lamp_band(before, b, features) if LAMP_BAND is not None else None
                    rule = code.long() * 8 + (1 + band if band is not None else 0)
                    return alb, code, rule

                alb, code, rule = lookup(point_s[unseen], normal_t[unseen], t_part[unseen], point_t[unseen])
                wheel = wheel_for(b) if bool((t_part[unseen] == int(Part.TYRE)).any()) else None
                on_wheel = (_wheel_face_points(t_part[unseen], bank, int(after.template_id[r]), vid[unseen],
                                               bary[unseen]) if wheel is not None else None)
                examples = (code == PART) | (code == ANOTHER_CAR)
                if on_wheel is not None:  # drawn from the real wheel below: their smoothing would be drawn over
                    examples[on_wheel[0]] = False
                if settings.part_smoothing and any_set(examples):
                    # each face's corners looked up with the normals of the faces around them: the colour runs on
                    # across a face edge instead of stepping to the next face's own examples (PhotoSettings)
                    m = int(mesh[unseen][0])
                    k = examples.nonzero().flatten()
                    face = tgt.frags.face_at(tgt.frags.locate(pix[unseen][k])) - m * tgt.faces.shape[1]
                    # glass and body never share a fan: the greenhouse's glass told per face (_fan_labels)
                    labels = _fan_labels(bank, int(after.template_id[r]), tgt.faces.shape[1])
                    alb = alb.clone()
                    u = unseen.nonzero().flatten()[k]
                    alb[k] = _corner_part_colors(lambda *q: lookup(*q)[::2], face, point_s[u], point_t[u], t_part[u],
                                                 rule[k], alb[k], bary[u], normal_t[u], tgt.faces[m], tgt.verts[m],
                                                 labels, settings.part_smoothing_crease_deg)
                if on_wheel is not None:
                    alb, code = _from_real_wheels(alb, code, wheel, *on_wheel, pyramid)
                # a part's examples carry their shading
                s_un = torch.where((code == PART) | (code == ANOTHER_CAR), 1.0, surface_shade(normal_t[unseen]))
                fallback[unseen] = alb * s_un[:, None]
                codes[unseen] = code
        if settings.amodal == "seen" and not bool(moved[r]):  # a staying object's freed pixels: flat ones not drawn
            drop = sel & torch.isin(codes, flat_codes)
            drawn &= ~drop
            sel &= ~drop
            if not any_set(sel):
                continue
        # A predicted mask's completion larger than a share of what the photo showed of the car rests on a blob's
        # guessed pose (PhotoSettings.grow_predicted_share): none of it is drawn, the fill stays.
        if predicted is not None and bool(predicted[r]) and not bool(moved[r]):
            shown = int(id_counts(src_ids, after.instance_id[r:r + 1])[0])
            if int(sel.sum()) > settings.grow_predicted_share * shown:
                drawn &= ~sel
                continue
        n = int(sel.sum())
        objects[name] = {"pixels": n, **_shares(codes[sel]), "moved": bool(moved[r]), "_pixels": pix[sel]}
        if len(visible_px) and n >= 50 and not any_set(seen[sel]) and bool(moved[r]):
            warnings.append(f"object {name}: none of its surface is visible in the input (behind the camera, off the "
                            "frame or hidden); drawn from its mean colour")
    color = torch.where(seen[:, None], color, fallback).clamp(0, 1)
    if not bool(drawn.all()):
        k = drawn.nonzero().flatten()
        pix, color, codes, t_part, row, z_t = pix[k], color[k], codes[k], t_part[k], row[k], z_t[k]
    if settings.outline_grow > 0:
        carved = settings.silhouette == "carved"
        near = _outline_growth(pix, row, moved, before, after, origin, own, K, settings.outline_grow,
                               settings.mask_view_deg if carved else 0.0, z_t,
                               background if carved else None, src_ids)
        if len(near):
            gained, nearest = near[:, 0], near[:, 1]
            for r in row[nearest].unique().tolist():
                info = objects[int(after.instance_id[r])]
                mine = row[nearest] == r
                info["_pixels"] = torch.cat([info["_pixels"], gained[mine]])
                info["pixels"] += int(mine.sum())
            pix, color, codes, t_part, row = (torch.cat([pix, gained]), torch.cat([color, color[nearest]]),
                                              torch.cat([codes, codes[nearest]]), torch.cat([t_part, t_part[nearest]]),
                                              torch.cat([row, row[nearest]]))
            for r in row[nearest].unique().tolist():
                info = objects[int(after.instance_id[r])]
                info.update(_shares(codes[row == r]))
    flat = out.permute(1, 2, 0).reshape(-1, 3).clone()
    flat[pix] = color.float()
    source = source.clone()
    source.view(-1)[pix] = codes
    parts_out.view(-1)[pix] = t_part.to(parts_out.dtype)
    if face_parts_out is not None:
        face_parts_out.view(-1)[pix] = _part_map(tgt, after, bank, pix, greenhouse=False).to(face_parts_out.dtype)
    return flat.view(height, width, 3).permute(2, 0, 1), source, objects


def _outline_growth(pix: Tensor, row: Tensor, moved: Tensor, before: ObjectTable, after: ObjectTable, origin: Tensor,
                    own: Tensor, K: Tensor, grow: float, min_view_deg: float, depth: Tensor | None = None,
                    background: Tensor | None = None, src_ids: Tensor | None = None) -> Tensor:
    """``(G, 2)`` long ``(gained flat pixel, index into pix)``: free pixels (no object drawn or staying there) next to a
    moved object's drawn pixels ``pix (P,)`` (rows ``row (P,)`` of ``after``) that it also covers, each with its
    nearest drawn pixel (whose colour it takes).

    A template is not the car's shape: with its true pose and size a car's outline still reaches past the
    template's (4-5 % of a turned car's pixels on the tuning pairs, a sixth to a third of their error, drawn as the
    road behind). Where it reaches in the edit is unknown (the edit's outline is what is unknown), so the drawn
    pixels grow by a share ``grow`` of the car's box's projected height, inside the box's projection (the car lies
    in its box). Only a car whose view turned by more than ``min_view_deg`` grows: for a view the input nearly
    shows, its own outline says where the car is (carving trims a template that is too large, the mask paste adds
    what one too small misses), and growing would undo it. With ``background (H, W)`` (``silhouette='carved'``) a
    gained pixel is carved as a template point is: taken at its nearest drawn pixel's depth ``depth (P,)``, carried
    back to the car's source pose, it (or its mirror image) must not land on open background in the input (the
    input's outline, seen from another side, still bounds the car: without it a fitted box larger than the car grew
    a halo of paint above a turned car's roof on the real frame)."""
    from scipy.ndimage import distance_transform_edt  # here: only a moved car with outline_grow needs it

    height, width = own.shape
    taken = own.view(-1) != 0
    taken[pix] = True
    out = []
    for r in row.unique().tolist():
        b = int(origin[r])
        if not bool(moved[r]) or b < 0:
            continue
        if _view_change(before, after, b, r) <= math.radians(min_view_deg):
            continue
        corners = box_corners(after.dims[r:r + 1].double(), after.ry[r:r + 1].double(),
                              after.center[r:r + 1].double())[0]
        uv, front = _project(corners, K)
        if not bool(front.all()) or not bool(torch.isfinite(uv).all()):
            continue
        reach = grow * float(uv[:, 1].max() - uv[:, 1].min())
        if reach < 0.5:
            continue
        x0, y0 = (max(int(math.floor(float(v))) - 1, 0) for v in uv.amin(0))
        x1 = min(int(math.ceil(float(uv[:, 0].max()))) + 2, width)
        y1 = min(int(math.ceil(float(uv[:, 1].max()))) + 2, height)
        if x1 <= x0 or y1 <= y0:
            continue
        mine = (row == r).nonzero().flatten()
        py, px = pix[mine] // width, pix[mine] % width
        at = torch.full((y1 - y0, x1 - x0), -1, dtype=torch.long)
        inside = (py >= y0) & (py < y1) & (px >= x0) & (px < x1)
        if not any_set(inside):
            continue
        at[py[inside] - y0, px[inside] - x0] = mine[inside]
        dist, (iy, ix) = distance_transform_edt((at < 0).numpy(), return_indices=True)
        hull = torch.from_numpy(_polygon_mask(uv.numpy() - np.array([x0, y0]), (y1 - y0, x1 - x0)) > 0)
        flat = torch.arange(y0, y1)[:, None] * width + torch.arange(x0, x1)[None, :]
        grow_here = hull & (torch.from_numpy(dist) <= reach) & ~taken[flat]
        if not any_set(grow_here):
            continue
        nearest = at[torch.from_numpy(iy)[grow_here], torch.from_numpy(ix)[grow_here]]
        gained = flat[grow_here]
        if background is not None and depth is not None and bool((src_ids == before.instance_id[b]).any()):
            z = depth[nearest]
            ray = torch.stack([(gained % width).double() - K[0, 2], (gained // width).double() - K[1, 2]], 1)
            point = torch.stack([ray[:, 0] / K[0, 0] * z, ray[:, 1] / K[1, 1] * z, z], 1)  # camera frame, edit
            local = (point - after.center[r].double()) @ roty(after.ry[r].double())  # rot^T (p - c) per row
            back = roty(before.ry[b].double())
            flip = torch.tensor([1.0, 1.0, -1.0], dtype=torch.float64)
            keep = (_in_silhouette(local @ back.T + before.center[b].double(), background, K)
                    & _in_silhouette((local * flip) @ back.T + before.center[b].double(), background, K))
            gained, nearest = gained[keep], nearest[keep]
            if not len(gained):
                continue
        taken[gained] = True
        out.append(torch.stack([gained, nearest], 1))
    return torch.cat(out) if out else torch.zeros((0, 2), dtype=torch.long)


#: Weight of the camera-frame normal against the car-frame position in :func:`_part_colors`' nearest examples (a unit
#: normal against positions normalised by the car's size). On the tuning seed's turns (16 pairs a bin, relight off):
#: 0 gave 22.61 / 20.51 / 19.89 / 17.98 dB at 15 / 45 / 90 / 180 degrees, 1: 24.41 / 21.70 / 20.64 / 19.63,
#: 3: 24.31 / 21.60 / 22.31 / 19.74, 5: 24.31 / 21.59 / 22.38 / 19.76.
PART_NORMAL_WEIGHT = 3.0
#: :func:`_part_features`: weight of a point's place along the car (its share of the length), against its height and
#: its distance from the middle plane (shares of theirs): parts repeat along a car, so the length matters weakly.
PART_LENGTH_WEIGHT = 0.25
#: A lamp part the input never showed is drawn from the other end's lamps and paint (:func:`_part_colors`): the two
#: ends of a car mirror each other (lamps at the corners, at the same height). On the tuning seed's 180-degree turns:
#: 20.10 dB against 19.74 with :data:`PART_DEFAULTS` lamps, and 18.69 with the other end's lamps in the default's hue
#: (a template's lamp triangles cover paint as much as lamps: that paint turned grey).
OTHER_END = {int(Part.FRONT_LIGHTS): int(Part.TAIL_LIGHTS), int(Part.TAIL_LIGHTS): int(Part.FRONT_LIGHTS)}


def _unshaded(normals: Tensor) -> Tensor:
    """``(...,)`` ones: the shading of ``normals (..., 3)`` when no light was fitted."""
    return torch.ones_like(normals[..., 0])


#: The luminance range a car's visible pixels span in clear air (tyres and glass to lit paint), the range
#: :data:`PART_DEFAULTS` are written for.
CLEAR_RANGE = (0.05, 0.85)


#: :func:`_clear_air`: the most luma of a car's darkest pixels (5 % quantile) seen through clear air (tyres and
#: glass are near black there; fog lifts them towards the air's colour).
CLEAR_DARKS = 0.15


#: :func:`_clear_air` and :func:`seen_through_the_air` read a car's air off at least this many of its visible pixels
#: (fewer: the defaults stay as they are, no other car's part is taken). At 50 a far car in rain, 30-50 visible
#: pixels, kept near-black windows and tyres on the side a turn showed (tuning trees 31 and 35, Table 1's rotate
#: kind on ground-truth masks; 16 and 30 drew the same pictures there: docs/results/2026-11-29_cpu/session9/t1rotate/).
AIR_MIN_PIXELS = 16


def _clear_air(colors: Tensor, min_pixels: int | None = None) -> bool:
    """Whether a car whose visible pixels are ``colors (Q, 3)`` is seen through clear air: its darkest pixels are
    near black (:data:`CLEAR_DARKS`); False with fewer than ``min_pixels`` (None: :data:`AIR_MIN_PIXELS`) pixels."""
    if len(colors) < (AIR_MIN_PIXELS if min_pixels is None else min_pixels):
        return False
    luma = luminance(colors)
    return float(torch.quantile(luma, 0.05)) <= CLEAR_DARKS


def seen_through_the_air(defaults: Tensor, colors: Tensor, min_pixels: int | None = None) -> Tensor:
    """``(P, 3)`` default part colours as the same car's visible pixels ``colors (Q, 3)`` show the air between it and
    the camera: fog or haze lifts the darks and compresses the range (``observed = t albedo + (1 - t) A``), so ``t``
    is the car's observed 5-95 % luminance range over :data:`CLEAR_RANGE`'s (at most 1) and the air's share is read
    off its darkest pixels. In clear air (a range as wide as the clear one, darks near black) the defaults stay as
    they are; under fog a never-seen window is drawn grey, as the fogged car's own windows look, not black. With
    fewer than ``min_pixels`` colours (None: :data:`AIR_MIN_PIXELS`) the defaults stay as they are.

    >>> clear = torch.tensor([[0.05, 0.05, 0.05]] * 60 + [[0.85, 0.85, 0.85]] * 60, dtype=torch.float64)
    >>> glass = torch.tensor([[0.10, 0.12, 0.15]], dtype=torch.float64)
    >>> seen_through_the_air(glass, clear).tolist()
    [[0.1, 0.12, 0.15]]
    >>> fog = 0.25 * clear + 0.75 * 0.6
    >>> [round(v, 3) for v in seen_through_the_air(glass, fog)[0].tolist()]
    [0.475, 0.48, 0.487]
    """
    return _through_air(defaults, _seen_air(colors, min_pixels))


def _seen_air(colors: Tensor, min_pixels: int | None = None) -> LampAir:
    """:func:`_air_terms` of a car's visible pixels ``colors (Q, 3)``; None (the defaults stay as they are) with fewer
    than ``min_pixels`` of them (None: :data:`AIR_MIN_PIXELS`)."""
    if len(colors) < (AIR_MIN_PIXELS if min_pixels is None else min_pixels):
        return None
    return _air_terms(colors)


def _through_air(defaults: Tensor, air: LampAir) -> Tensor:
    """``(P, 3)`` the colours ``defaults (P, 3)`` seen through ``air`` (:func:`_seen_air`; None: as they are)."""
    if air is None:
        return defaults
    t, offset = air
    return (t * defaults + offset[None]).clamp(0, 1)


def _air_terms(colors: Tensor) -> tuple[float, Tensor]:
    """``(t, offset (3,))`` of the air a car whose visible pixels are ``colors (Q, 3)`` is seen through, as
    :func:`seen_through_the_air` reads it: ``observed = t clear + offset``."""
    luma = luminance(colors)
    lo, hi = torch.quantile(luma, torch.tensor([0.05, 0.95], dtype=colors.dtype))
    t = float(((hi - lo) / (CLEAR_RANGE[1] - CLEAR_RANGE[0])).clamp(0.05, 1.0))
    dark = torch.quantile(colors, 0.05, dim=0)  # per channel: the air's colour shows in the darks
    return t, dark - t * CLEAR_RANGE[0]


#: The air a car is seen through where it is not clear (:func:`_lamp_air`): ``(t, offset (3,))``, ``observed = t
#: clear + offset``; None: clear air (or too few pixels to tell), colours are read as they are.
LampAir = tuple[float, Tensor] | None


def _lamp_air(colors: Tensor, clear: bool) -> LampAir:
    """The air a car whose visible pixels are ``colors (Q, 3)`` is seen through, for reading its lamps' colours
    (:func:`_lamp_coloured`): None where ``clear`` (its :func:`_clear_air`) or with fewer than
    :data:`AIR_MIN_PIXELS` pixels, else :func:`_air_terms` (fog lifts a red lamp to a pink that no red test passes:
    a fogged car's tail lamps were never told, so its never-seen front kept the default white shaded as paint)."""
    return None if clear else _seen_air(colors)


def _out_of_air(colors: Tensor, air: LampAir) -> Tensor:
    """``colors (E, 3)`` seen through ``air`` (:func:`_lamp_air`) as they would be in clear air."""
    if air is None:
        return colors
    return ((colors - air[1][None]) / air[0]).clamp(0, 1)


class _PartExamples(NamedTuple):
    """A car's visible pixels usable as examples of its parts (:func:`_part_examples`): ``part (E,)``,
    ``color (E, 3)`` sRGB, ``feature (E, 6)`` (:func:`_part_features`), ``cos (E,)`` the view cosine each was
    seen at (:func:`_view_cos`) and ``reach (E,)`` uint8 which of the car's never-seen surfaces each may draw
    (:data:`REACH_ALL`, :data:`REACH_ENDS`, :data:`REACH_SIDES`, :data:`REACH_LAMPS`)."""

    part: Tensor
    color: Tensor
    feature: Tensor
    cos: Tensor
    reach: Tensor


#: :func:`_part_examples`: the largest share of a car's body examples on the road its mask took in for the paint told
#: without them to draw its sides: a car most of whose body is road is a mask of the road (small cars of the predicted
#: source scene on the seed-33 and seed-39 tuning trees, 74-81 %; the real frame's red wagon 22 %,
#: docs/results/2026-11-30_cpu/session22/side2/).
ROAD_MAX_SHARE = 0.5
#: :func:`_ground_examples`: the parts whose examples on the road a car's mask took in stay examples: a tyre stands on
#: the road, and its rubber is as dark as the shadow there (:data:`TYRE_QUANTILE` tells tyres from the rest).
ON_GROUND_PARTS = (int(Part.TYRE),)


def _ground_examples(parts: Tensor, on_road: Tensor) -> Tensor:
    """``(E,)`` bool: the examples of parts ``parts (E,)`` that are the road and shadow under the car, not the car:
    ``on_road (E,)`` (:func:`~sdn3d.editing.photo.recolor.ground_in_mask`) on any part but :data:`ON_GROUND_PARTS`.
    Read where the road told the car's ends a grey paint its sides do not have (:func:`_part_examples`): kept there,
    the road's shadow drew the lower half of the real frame's red wagon turned 180 degrees, its bumper, plate and head
    lamps, as a dark smear (54 % of its end examples were road; docs/results/2026-11-30_cpu/session25/back41/)."""
    return on_road & ~torch.isin(parts, torch.tensor(ON_GROUND_PARTS))


#: :attr:`_PartExamples.reach`: an example any never-seen surface of its car may be drawn from.
REACH_ALL = 0
#: An example only the car's ends (beyond :data:`LAMP_END` of its length from the middle) may be drawn from: a body
#: example the paint told by the examples off the lamps' heights keeps, where the road under the car told that paint
#: (:func:`_part_examples`): a car's end drawn from its other end takes that end's bumper and glass as they were.
REACH_ENDS = 1
#: An example only the car's sides may be drawn from: a body example of the paint told without the road under the car
#: (:func:`_part_examples`): a side is paint down to its sills.
REACH_SIDES = 2
#: An example only a never-seen end's lamps may be drawn from (:func:`_other_end_lamps`): a copy of a car's pixel
#: where cars have an end's lamps, in that lamp's colour, whatever the template calls it (:func:`_part_examples`).
#: Only :func:`_part_colors` reads it, and only for that: kept out of the body's examples, a red lamp close to a
#: brown paint's hue changed the body's view-reflection fit and the pixels drawn from the photo at 15-90 degrees
#: (held-out seed 2219, docs/results/2026-11-30_cpu/session23/front/).
REACH_LAMPS = 3


#: :func:`_part_features`' first normal column: examples seen on one template face share their normal's three
#: (:func:`~sdn3d.editing.photo.nearest.nearest_examples`' grouped scan).
FEATURE_NORMAL = 3


def _part_features(before: ObjectTable, b: int, points: Tensor, normals: Tensor) -> Tensor:
    """``(P, 6)`` where ``points (P, 3)`` lie on the car of ``before`` row ``b`` and which way ``normals (P, 3)``
    face: its own frame normalised by its size (height, distance from the middle plane and, weakly, along the car),
    then the camera-frame normal weighted by :data:`PART_NORMAL_WEIGHT`. Comparable between cars."""
    rot = roty(before.ry[b].double())
    centre = before.center[b].double()
    size = before.dims[b].double()  # (l, h, w)
    local = (points.double() - centre) @ rot  # rot^T (p - c) per row
    # each column written in place: the same quotients and products as made apart and stacked, without the copies
    features = torch.empty(len(points), 6, dtype=torch.float64)
    torch.div(PART_LENGTH_WEIGHT * local[:, 0], size[0], out=features[:, 0])
    torch.div(local[:, 1], size[1], out=features[:, 1])
    torch.div(local[:, 2].abs(), size[2], out=features[:, 2])
    torch.mul(normals.double(), PART_NORMAL_WEIGHT, out=features[:, 3:])
    return features


def _part_examples(b: int, s_mesh: int, visible_px: Tensor, before: ObjectTable, src: _Raster, parts_src: Tensor,
                   img_flat: Tensor, road: Tensor | None, settings: PhotoSettings,
                   air: LampAir = None) -> tuple[_PartExamples, Tensor]:
    """The examples of the car of ``before`` row ``b`` (source mesh ``s_mesh``) among its ``visible_px``, and the
    colours of all its ``visible_px`` (the air it is seen through, :func:`seen_through_the_air` and
    :func:`_clear_air`: fog lifts every pixel of the car, whichever way it faces and whatever the template covers;
    the examples alone left a small far car, 30-50 of them, under those functions' 50 and its unseen windows and
    tyres near black in rain). Kept as examples: pixels seen squarely enough (``min_view_cos``); body examples that
    are paint (:func:`~sdn3d.editing.photo.recolor.body_paint`: a tail lamp or a window that a loosely fitted mesh
    calls body painted a red or black stripe along a whole new side), the paint told by the body examples off the
    lamps' heights at the car's ends (:func:`_lamp_band` across the width: a lamp band has paint above and below it,
    so it does not decide the paint however much of the end it covers); where those tell a grey paint and those not
    on ``road (H * W,)`` bool (None: none), the road and shadow the car's mask took in
    (:func:`~sdn3d.editing.photo.recolor.ground_in_mask`, the caller's, in clear air only), tell a coloured one, the
    coloured paint's examples draw the car's sides and the grey one's its ends (:attr:`_PartExamples.reach`), and the
    road's pixels are examples of no part but tyres (:func:`_ground_examples`): a box's
    mask takes in the road below a car seen from behind, where the template's end cap reaches (on the real frame's red
    wagon 43 % of the examples off the lamps' heights; its paint was judged black and its turned side drawn black
    below), while an end drawn from the other end keeps that end's bumper and glass (the paint's examples alone drew
    worse 180-degree turns on the tuning trees, docs/results/2026-11-30_cpu/session22/side2/); on a coloured paint,
    glass examples of the
    paint's hue and chroma are the body's (a real car whose belt line lies above the fitted template's: its paint
    there drew dark-red side windows); body examples where cars have an end's lamps (:func:`_lamp_band` at the
    corners) in that lamp's colour (:func:`_lamp_coloured`) are also, as copies, examples of that lamp that only a
    never-seen end's lamps read (:data:`REACH_LAMPS`, :func:`_other_end_lamps`), unless the paint of the car's ends
    or sides is itself of that colour (the generator draws its lamps there, where the templates' lamp faces, lower on
    the end caps, do not reach); tyre examples darker
    than most of the car (:data:`TYRE_QUANTILE`). ``img_flat (H * W, 3)``: the input's pixels, in any float dtype
    (the colours are float64 from the rows read on); ``air``: the air the car is seen through, its lamp colours read
    out of it (:func:`_lamp_air`, :meth:`PhotoSource.lamp_air`; None: clear air)."""
    seen_colors = img_flat[visible_px].double()
    ex = visible_px[(src.frags.mesh_at(visible_px) == s_mesh) & (parts_src[visible_px] >= 0)]
    if not len(ex):
        return _no_examples(), seen_colors
    _, vid, bary, normal = _surface(src, ex)
    tri = src.verts[torch.full((len(ex),), s_mesh, dtype=torch.long)[:, None], vid]
    point = sum3(bary[..., None] * tri, 1)
    cos = _view_cos(point, normal)
    good = cos >= settings.min_view_cos
    ex, point, normal, cos = ex[good], point[good], normal[good], cos[good]
    colors = img_flat[ex].double()
    ex_part = parts_src[ex]
    feature = _part_features(before, b, point, normal)
    keep = torch.ones(len(ex), dtype=torch.bool)
    reach = torch.full((len(ex),), REACH_ALL, dtype=torch.uint8)
    lamp_ex, lamp_part_of = ex[:0], ex[:0]  # indices into ex of the lamp examples (REACH_LAMPS), and their lamps
    body_ex = (ex_part == int(Part.BODY)).nonzero().flatten()
    if len(body_ex) >= 8:
        lab = srgb_to_lab(colors[body_ex].float())
        band = _lamp_band(before, b, feature[body_ex], corners=False) if LAMP_BAND is not None else None
        beside = band is None or int((band < 0).sum()) < 8  # too few examples off the lamps' heights: all decide
        told = torch.ones(len(body_ex), dtype=torch.bool) if beside else band < 0
        on_road = torch.zeros(len(body_ex), dtype=torch.bool) if road is None else road[ex[body_ex]]
        tell = told & ~on_road  # the road under the car tells no paint
        paint, coloured = body_paint(lab, reference=lab[told])
        side_paint = paint
        if (not coloured and 8 <= int(tell.sum()) < int(told.sum())
                and float(on_road.double().mean()) <= ROAD_MAX_SHARE):  # the road told a grey paint: is it the car's?
            without_road, side_coloured = body_paint(lab, reference=lab[tell])
            if side_coloured:  # the sides are the coloured paint; the ends keep what they showed, less the road
                side_paint = without_road
                reach[body_ex[paint & ~side_paint]] = REACH_ENDS
                reach[body_ex[side_paint & ~paint]] = REACH_SIDES
                keep &= ~_ground_examples(ex_part, road[ex])
        keep[body_ex[~(paint | side_paint)]] = False
        corners = _lamp_band(before, b, feature[body_ex]) if LAMP_BAND is not None else None
        if corners is not None and any_set(paint):  # lamps where cars have them that the template calls body
            # the paint of its ends and that of its sides (they differ where the road told the ends' paint)
            paints = torch.stack([colors[body_ex[p]].median(0).values for p in (paint, side_paint) if any_set(p)])
            for lamp_part in OTHER_END:
                if bool(_lamp_coloured(paints, lamp_part, air).any()):
                    continue  # a red car's tail lamps are not told from its paint
                lit = body_ex[(corners == lamp_part) & _lamp_coloured(colors[body_ex], lamp_part, air)]
                lamp_ex = torch.cat([lamp_ex, lit])
                lamp_part_of = torch.cat([lamp_part_of, torch.full_like(lit, lamp_part)])
        glass_ex = (ex_part == int(Part.GLASS)).nonzero().flatten()
        if coloured and len(glass_ex):  # a coloured car's paint above the template's belt line is body, not glass
            glass_paint, _ = body_paint(srgb_to_lab(colors[glass_ex].float()), reference=lab[told])
            ex_part[glass_ex[glass_paint]] = int(Part.BODY)
    tyre_ex = (ex_part == int(Part.TYRE)).nonzero().flatten()
    if TYRE_QUANTILE < 1 and len(tyre_ex):  # tyre examples lighter than most of the car are road or paint
        luma = luminance(colors)
        keep[tyre_ex[luma[tyre_ex] > torch.quantile(luma, TYRE_QUANTILE)]] = False
    # the lamp examples are copies, added after the others: every other reader sees the examples as they were
    kept = _PartExamples(torch.cat([ex_part[keep], lamp_part_of]), torch.cat([colors[keep], colors[lamp_ex]]),
                         torch.cat([feature[keep], feature[lamp_ex]]), torch.cat([cos[keep], cos[lamp_ex]]),
                         torch.cat([reach[keep], torch.full((len(lamp_ex),), REACH_LAMPS, dtype=torch.uint8)]))
    return kept, seen_colors


def _no_examples() -> _PartExamples:
    """No examples at all (a car none of whose surface is seen)."""
    return _PartExamples(torch.zeros(0, dtype=torch.long), torch.zeros(0, 3, dtype=torch.float64),
                         torch.zeros(0, 6, dtype=torch.float64), torch.zeros(0, dtype=torch.float64),
                         torch.zeros(0, dtype=torch.uint8))


def _examples_of_part(examples: _PartExamples, part: int) -> _PartExamples:
    """The examples of ``part`` among ``examples``."""
    keep = examples.part == part
    return _PartExamples(*(field[keep] for field in examples))


#: Parts whose colour drawn from the photo or its mirror image changes with the view (``photo.view_reflection``):
#: glass and clear-coated paint mirror the sky more the more edge-on they are seen
#: (:func:`~sdn3d.editing.photo.light.grazing`). A part drawn from the car's examples elsewhere is changed only on a
#: dark paint's body (:data:`PART_VIEW_REFLECTION`): elsewhere its examples are chosen by the direction they faced,
#: which brings their reflection along, and the fit takes shading for reflection (docs/results/2026-11-28_cpu/
#: session7/lead/, docs/results/2026-11-29_cpu/session15/sides/).
REFLECTIVE_PARTS = (int(Part.GLASS), int(Part.BODY))
#: Whether a dark car's body drawn from its own examples elsewhere (:func:`_part_colors`) takes the change of its sky
#: reflection from the examples' view to its own (:func:`_reflect_part_colors`).
PART_VIEW_REFLECTION = True


def _reflection_strength(examples: _PartExamples, part: int) -> Tensor | None:
    """``(3,)`` the reflection strength of ``part`` of one car fitted on its examples
    (:func:`~sdn3d.editing.photo.light.fit_reflection`); None where it cannot be told."""
    mine = examples.part == part
    return fit_reflection(examples.color[mine], examples.cos[mine])


#: :func:`_part_colors`: how many nearest examples a never-seen point of these parts takes the mean of where its
#: nearest example faced the camera otherwise than it now does (:data:`SAME_PANEL_DEG`; elsewhere, and for the other
#: parts, its ``k``). A window is one material whose pixels differ by the sky they mirror and by the frames and
#: pillars a template's greenhouse takes in: a window point that faces the camera as no window example did is matched
#: by position alone, and its 4 nearest are often an end's outer columns, its pillars (a bus turned 90 degrees on the
#: seed-31 tuning tree drew its side windows in light streaks from them; that side faced the camera as the windscreen
#: had, so this rule leaves it as it was; docs/results/2026-11-29_cpu/session15/sides/).
PART_EXAMPLES_K = {int(Part.GLASS): 16}
#: :data:`PART_EXAMPLES_K` applies where a point's nearest example faced the camera more than this many degrees away
#: from the way the point now faces it; within it (a windscreen drawn from a rear window that faced the camera as it
#: now does) the ``k`` nearest keep their shading and reflections where they were (the mean of 16 everywhere lost
#: 0.15 dB on the seed-33 tuning tree's 180-degree turns, docs/results/2026-11-29_cpu/session15/sides/).
SAME_PANEL_DEG = 30.0
#: Parts a car that never showed them takes from another car of the photo (:func:`_part_colors`): tyres and rims
#: look alike from car to car, and a car seen from behind shows none. The body, glass, lamps and plate are the
#: car's own (paint and tint differ; a lamp comes from the car's other end; the lamps where cars have them may come
#: from another car's, :data:`LAMPS_FROM_ANOTHER_CAR`).
SHARED_PARTS = (int(Part.TYRE),)


def _lendable(examples: _PartExamples, part: int) -> _PartExamples:
    """The examples of ``part`` among one car's ``examples`` that another car of the photo may draw the same part
    from (:func:`_part_colors`' ``others``): a lamp's are the pixels told as that lamp where cars have it
    (:data:`REACH_LAMPS`: lamp-coloured, on a paint that is not; a template's lamp faces lie lower on the end cap, on
    bumper and paint), any other part's all of them."""
    keep = examples.part == part
    if part in OTHER_END:
        keep &= examples.reach == REACH_LAMPS
    return _PartExamples(*(field[keep] for field in examples))


def _part_colors(b: int, own: _PartExamples, seen_colors: Tensor, points: Tensor, normals: Tensor, parts: Tensor,
                 before: ObjectTable, body: Tensor | None, others: Callable[[int], _PartExamples] | None = None,
                 max_examples: int = 1500, k: int = 4, air: LampAir = None,
                 seen_air: Callable[[], LampAir] | None = None,
                 features: Tensor | None = None) -> tuple[Tensor, Tensor, Tensor]:
    """``(colour (P, 3), source code (P,), seen at (P,))`` of unseen surface points ``points (P, 3)`` (camera frame,
    at the source pose of ``before`` row ``b``) with camera-frame unit normals at their new pose ``normals (P, 3)``
    and parts ``parts (P,)``; ``own``: the car's examples and ``seen_colors`` all its visible colours
    (:func:`_part_examples`). ``seen at``: the mean :func:`~sdn3d.editing.photo.light.grazing` term of the views the
    examples each colour came from were seen at (NaN: no examples, a default colour).

    Where the input showed the part: the mean colour of the ``k`` (:data:`PART_EXAMPLES_K` for its parts) nearest
    input pixels of the same part of the same car, code :data:`PART`. Nearest in the car's own frame and by
    camera-frame normal (:func:`_part_features`): an example that faced the camera as the new surface does carries its
    shading (no light model: a side of the car turned towards the camera takes the colour of the surfaces that faced
    it, its reflection included). Body points at the car's ends (beyond :data:`LAMP_END` of its
    length from the middle) are drawn from the examples that may reach them and the others from those that may reach
    the sides (:attr:`_PartExamples.reach`, :func:`_part_examples`: where the road under a car told its paint).

    A lamp part it never showed (the front of a car seen from behind) takes the other end's lamps and paint the
    same way (:data:`OTHER_END`), its lamps in this end's colour (:data:`LAMP_HUES`), code :data:`PART`. A
    :data:`SHARED_PARTS` part it never showed takes the same part of the other cars of the photo, ``others(part)``,
    the same way, code :data:`ANOTHER_CAR`. Any other part it never showed: the body's albedo ``body`` for the body
    (:data:`FALLBACK`), else :data:`PART_DEFAULTS` seen through the car's air (:func:`seen_through_the_air`,
    :data:`DEFAULT`); the caller shades these. Where an end's lamps were never seen, the points where cars have them
    (:func:`_lamp_band`; not glass, tyres or plates) are lamps in :data:`LAMP_DEFAULTS` seen through the car's air,
    code :data:`DEFAULT`, unless they are head lamps and the photo showed the tail lamps (:func:`_other_end_lamps`):
    then the tail lamps and what lies between them, nearest first, the lamps in white as bright as they were, code
    :data:`PART`, unshaded (a lamp's brightness is its own, not the paint's shading); else, with
    :data:`LAMPS_FROM_ANOTHER_CAR`, the same lamps of another car (``others(part)``, :func:`_lendable`: the pixels
    told as that lamp), nearest first, code :data:`ANOTHER_CAR`, unshaded. A lamp colour is read with the car's
    ``air`` taken out (:func:`_lamp_air`; None: clear air). ``seen_air()``: :func:`_seen_air` of ``seen_colors``
    where the caller keeps it (:meth:`PhotoSource.seen_air`; None: read off them here). ``features (P, 6)``: the
    points' :func:`_part_features` where the caller has them (None: made here)."""
    if seen_air is None:
        seen_air = lambda: _seen_air(seen_colors)  # noqa: E731
    lamp = own.reach == REACH_LAMPS  # read only by the never-seen lamps' rule, below
    own, lamps = _PartExamples(*(f[~lamp] for f in own)), _PartExamples(*(f[lamp] for f in own))
    albedo = torch.tensor(PART_DEFAULTS, dtype=torch.float64)[parts.clamp(min=0)]
    codes = torch.full((len(points),), DEFAULT, dtype=torch.uint8)
    seen_at = torch.full((len(points),), math.nan, dtype=torch.float64)
    if body is not None:
        is_body = parts <= int(Part.BODY)
        albedo[is_body] = body
        codes[is_body] = FALLBACK
    default = (codes == DEFAULT) & (parts >= 0)
    if any_set(default) and len(seen_colors):  # seen_through_the_air, a colour a part: each row's as it would be
        seen = _through_air(torch.tensor(PART_DEFAULTS, dtype=torch.float64), seen_air())
        albedo = torch.where(default[:, None], seen[parts.clamp(min=0)], albedo)
    q_feat = _part_features(before, b, points, normals) if features is None else features
    at_ends = own.reach != REACH_SIDES  # the examples a car's ends are drawn from (the lamps lie at the ends)
    paint = own.color[(own.part == int(Part.BODY)) & at_ends]
    end = q_feat[:, 0].abs() > PART_LENGTH_WEIGHT * LAMP_END
    split = any_set(own.reach != REACH_ALL)
    groups = []  # (points, the examples they may be drawn from)
    for part in parts.unique().tolist():
        here = parts == part
        if split and part == int(Part.BODY):  # the ends and the sides each from their own examples
            groups += [(here & end, at_ends), (here & ~end, own.reach != REACH_ENDS)]
        else:
            groups.append((here, at_ends))
    for here, usable in groups:
        q = here.nonzero().flatten()
        if not len(q):
            continue
        part = int(parts[q[0]])
        have = ((own.part == part) & usable).nonzero().flatten()
        source, feature, code, cos = own.color, own.feature, PART, own.cos
        if len(have) < 2 * k and part in OTHER_END:  # a lamp never seen: the other end's lamps and paint
            have = (torch.isin(own.part, torch.tensor([OTHER_END[part], int(Part.BODY)])) & usable).nonzero().flatten()
            if LAMP_HUES:
                source = _lamps_of_this_end(own.color, part, paint, air)
        if len(have) < 2 * k and part in SHARED_PARTS and others is not None:  # never seen: another car's
            pool = others(part)
            have = torch.arange(len(pool.part))
            source, feature, code, cos = pool.color, pool.feature, ANOTHER_CAR, pool.cos
        if len(have) < 2 * k:
            continue
        if len(have) > max_examples:
            have = have[torch.linspace(0, len(have) - 1, max_examples).long()]
        more = PART_EXAMPLES_K.get(part, k)
        near = nearest_examples(q_feat[q], feature[have], max(k, more), shared_from=FEATURE_NORMAL)  # nearest first
        panel = None  # per row: whether its nearest example faced the camera as it now does (the k nearest alone)
        if more > k and PART_NORMAL_WEIGHT > 0:
            facing = (q_feat[q, 3:] * feature[have][near[:, 0], 3:]).sum(1) / PART_NORMAL_WEIGHT**2
            panel = facing >= math.cos(math.radians(SAME_PANEL_DEG))
        codes[q] = code
        # gathered channel-first: the same products and sums as over (P, K, 3) rows, 1.4-2.6x faster (k 16-4); by
        # index_select and take, the same values as indexing by `near` in a third to a half of its time, and weighted
        # in place (the same products; a new (3, P, K) tensor to write cost as much again at k 16). In place cannot
        # promote: colours or view terms in float32 are first made float64 as the weighting's promotion made them.
        # GATHER_ROWS rows at a time: each row's products and sums are its own, and the block's (3, rows, K) stays in
        # the processor's cache and the allocator's reach instead of a fresh (3, P, K) to write and read back; a
        # channel at a time by `take` into the one block's buffer (the same values as index_select along the
        # examples, in half its time).
        colors_t, seen_terms = source[have].T.contiguous(), grazing(cos[have])
        first_k = (torch.arange(near.shape[1]) < k).double()
        buffer = torch.empty(3 * min(len(q), GATHER_ROWS) * near.shape[1], dtype=colors_t.dtype)
        for start in range(0, len(q), GATHER_ROWS):
            rows, block = q[start:start + GATHER_ROWS], near[start:start + GATHER_ROWS]
            if panel is None:
                weight = torch.ones(block.shape, dtype=torch.float64)
            else:
                weight = torch.where(panel[start:start + GATHER_ROWS, None], first_k, 1.0)
            weight = weight / weight.sum(1, keepdim=True)
            picked = buffer[:3 * block.numel()].view(3, *block.shape)
            for colour, into in zip(colors_t, picked, strict=True):
                torch.take(colour, block, out=into)
            albedo[rows] = picked.to(weight.dtype).mul_(weight).sum(2).T
            seen_at[rows] = seen_terms.take(block).to(weight.dtype).mul_(weight).sum(1)
    # The lamps of an end the photo never showed, where cars have them (:func:`_lamp_band`): the template's lamp faces
    # lie lower, on the end cap, and took the other end's paint there.
    band = _lamp_band(before, b, q_feat) if LAMP_BAND is not None else None
    if band is not None:
        own_band = _lamp_band(before, b, own.feature) if len(own.part) else band[:0]
        lamps_band = _lamp_band(before, b, lamps.feature) if len(lamps.part) else band[:0]
        for lamp_part in OTHER_END:
            here = (band == lamp_part) & ~torch.isin(parts, torch.tensor(LAMPLESS_PARTS))
            if int((own.part == lamp_part).sum()) >= 2 * k or not any_set(here):
                continue  # that end was seen: its lamps are the photo's
            q = here.nonzero().flatten()
            lit, code = _other_end_lamps(own, own_band, lamps, lamps_band, lamp_part, k, air), PART
            if lit is None and others is not None and LAMPS_FROM_ANOTHER_CAR:  # this lamp as another car shows it
                pool = others(lamp_part)
                lit, code = (pool.color, pool.feature, pool.cos) if len(pool.part) >= k else None, ANOTHER_CAR
            if lit is not None:  # the lamps as the photo shows them, in this end's hue, unshaded (they glow)
                source, feature, cos = lit
                near = nearest_examples(q_feat[q], feature, k, shared_from=FEATURE_NORMAL)
                albedo[q] = source[near].mean(1)
                codes[q] = code
                seen_at[q] = grazing(cos[near]).mean(1)
                continue
            lamp = torch.tensor(LAMP_DEFAULTS[lamp_part], dtype=albedo.dtype).expand(len(q), 3)
            albedo[q] = _through_air(lamp, seen_air())  # too few colours: the lamp as it is
            codes[q] = DEFAULT
            seen_at[q] = math.nan
    return albedo, codes, seen_at


#: :func:`_other_end_lamps`: the ends whose never-seen lamps are drawn from the other end's lamps as the photo shows
#: them. A head lamp is the tail lamp's brightness in white (both are lit glass, as bright whatever the light on the
#: paint: the default white shaded as paint drew the fronts of cars seen from behind in grey lamps); a tail lamp's red
#: is not told by a white head lamp (drawn from it, the tuning trees' tail lamps came out too deep a red, and in fog
#: without the air's haze: docs/results/2026-11-30_cpu/session23/front/).
LAMPS_FROM_OTHER_END = (int(Part.FRONT_LIGHTS),)
#: :func:`_part_colors`: an end's lamps the photo never showed, not drawn from the car's other end
#: (:func:`_other_end_lamps`: tail lamps, or head lamps where the tail lamps were not seen or not told from the
#: paint), are drawn from the same lamps of the car nearest in depth that shows them, both seen through clear air
#: (``others``, :func:`_lendable`), code :data:`ANOTHER_CAR`, unshaded: lit lamps look alike from car to car, and the
#: default red shaded as paint drew the tail lamps of cars seen from the front too deep a red (MSE 0.02-0.07 against
#: the tuning trees' targets; docs/results/2026-11-30_cpu/session24/turn41/). False: :data:`LAMP_DEFAULTS` there.
LAMPS_FROM_ANOTHER_CAR = True


def _other_end_lamps(own: _PartExamples, own_band: Tensor, lamps: _PartExamples, lamps_band: Tensor, part: int,
                     k: int, air: LampAir = None) -> tuple[Tensor, Tensor, Tensor] | None:
    """``(colours (E, 3), features (E, 6), view cosines (E,))`` to draw the never-seen lamps ``part`` of a car from:
    its examples ``own`` (:data:`REACH_LAMPS` ones left out) in the other end's lamp band (``own_band (E_o,)``,
    :func:`_lamp_band` of their features), what lies between the lamps, and its lamp examples ``lamps`` there
    (``lamps_band``), the lamp-coloured ones in ``part``'s hue (:func:`_lamps_of_this_end`); the nearest of them by
    :func:`_part_features` to a point of this end's band draw it, unshaded (a lamp glows: its brightness is the other
    end's lamps', not the paint's shading). None (the caller's :data:`LAMP_DEFAULTS`): ``part`` not in
    :data:`LAMPS_FROM_OTHER_END`, fewer than ``2 k`` such examples, fewer than ``k`` of them lamp-coloured
    (:func:`_lamp_coloured`: the other end's lamps not seen), or the car's paint itself of that lamp colour, the
    paint its ends are drawn from or that of its sides (:attr:`_PartExamples.reach`; a red car's tail lamps are not
    told from its paint)."""
    if part not in LAMPS_FROM_OTHER_END:
        return None
    other = OTHER_END[part]
    have = ((own_band == other) & ~torch.isin(own.part, torch.tensor(LAMPLESS_PARTS))).nonzero().flatten()
    lit = (lamps_band == other).nonzero().flatten()
    colours = torch.cat([own.color[have], lamps.color[lit]])
    if len(colours) < 2 * k or int(_lamp_coloured(colours, other, air).sum()) < k:
        return None
    body = own.part == int(Part.BODY)
    for reach in (REACH_SIDES, REACH_ENDS):  # the ends' paint (all but the sides'), then the sides'
        paint = own.color[body & (own.reach != reach)]
        if len(paint) and bool(_lamp_coloured(paint.median(0).values[None], other, air)[0]):
            return None
    return (_lamps_of_this_end(colours, part, own.color[body & (own.reach != REACH_SIDES)], air),
            torch.cat([own.feature[have], lamps.feature[lit]]), torch.cat([own.cos[have], lamps.cos[lit]]))


def _reflect_part_colors(colors: Tensor, codes: Tensor, seen_at: Tensor, parts: Tensor, points: Tensor,
                         normals: Tensor, own: _PartExamples, scale: float) -> Tensor:
    """``(P, 3)`` the colours ``colors`` :func:`_part_colors` took from a car's own examples (code :data:`PART`) for
    its body points ``parts (P,)``, changed by the sky reflection their new view adds or takes away, where the paint
    is dark (its body examples' median CIE L* below :data:`~sdn3d.editing.photo.recolor.DARK_PAINT_L`, the
    recolour's dark paint): a point ``points (P, 3)`` facing ``normals (P, 3)`` (camera frame), seen at their view
    cosine (:func:`_view_cos`, read only where a point is changed), whose examples were seen at
    :func:`~sdn3d.editing.photo.light.grazing` ``seen_at (P,)`` takes
    ``scale`` times the body's reflection strength (:func:`_reflection_strength`) times the change of the grazing
    term, as a photo pixel at a new view does. A dark paint's colour is mostly the sky it mirrors (its diffuse shading
    is small), so the strength fitted on its examples is its reflection; on a lighter paint the fit takes shading
    for reflection. A black car's side never seen, drawn from its rear seen at a more grazing view, was too light."""
    here = (codes == PART) & (parts == int(Part.BODY)) & torch.isfinite(seen_at)
    body = own.part == int(Part.BODY)
    if not any_set(here) or int(body.sum()) < 2:
        return colors
    if float(srgb_to_lab(own.color[body].float())[:, 0].median()) >= DARK_PAINT_L:
        return colors
    strength = _reflection_strength(own, int(Part.BODY))
    if strength is None:
        return colors
    out = colors.clone()
    cos = _view_cos(points[here], normals[here])
    out[here] += scale * strength[None] * (grazing(cos) - seen_at[here])[:, None]
    return out


#: :func:`_corner_groups`: glass faces join a fan only across edges whose normals lie within this many degrees (or
#: ``photo.part_smoothing_crease_deg`` where less). A window's lookup changes with the way it faces more than paint's
#: (:data:`PART_EXAMPLES_K`: a window facing the camera as none of its examples did takes 16 of them, by position): on
#: the real frame's turned red car the windscreen's tip, drawn light from the rear window's examples, spread at 35
#: degrees over the front side window as a beige haze; at 30 it stays on the windscreen, and the two cars' face-edge
#: steps are 2.3 times those within a face (35: 2.1, 25: 2.6, no glass smoothing: 3.7; session30/gouraud30/).
GLASS_CREASE_DEG = 30.0


def _fan_labels(bank: MeshBank, template: int, n_faces: int) -> Tensor:
    """``(n_faces,)`` long: the part each face of ``template`` in ``bank`` smooths with (:func:`_corner_groups`' labels;
    padding faces beyond the template's: -1). Its loft label, with the greenhouse's glass told per face as
    :func:`_greenhouse_glass` tells it per point (:func:`~sdn3d.meshes.parts.greenhouse_glass` at the face's three
    corners' canonical heights): a body face wholly above the belt line (its corners on or above it) smooths with the
    glass, one wholly below with the body, and one that the belt line crosses (an end cap's fan triangle, a few side
    faces of some templates) with no other face (a label of its own: its pixels keep their own lookup, as with
    ``part_smoothing`` off). Body and glass faces told apart so: a corner on the belt line mixed the body's lookup
    with the greenhouse's normals (the window band faded into the paint, no crisp belt line) and the windscreen's
    with the bonnet's (session30/gouraud30/)."""
    known = bank.face_parts.cpu()[template].long()[:n_faces]
    labels = torch.full((n_faces,), -1, dtype=torch.long)
    if not len(known):
        return labels
    tri = bank.verts.cpu()[template][bank.faces.cpu()[template][:len(known)].long()].double()  # (F, 3, 3) canonical
    normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
    belt = float(_bank_belts(bank)[template])
    height = tri[..., 1]  # canonical y, down
    # (F, 3) each corner as a point would be told: glass on or above the line (one on it, in float32, goes either
    # way), and glass above it
    glass = greenhouse_glass(known[:, None], height, -normal[:, 1:2], belt + 1e-6)
    over = greenhouse_glass(known[:, None], height, -normal[:, 1:2], belt - 1e-6)
    above = glass.all(1) & over.any(1)
    crossed = over.any(1) & ~glass.all(1)
    labels[:len(known)] = torch.where(above, int(Part.GLASS), known)
    own = torch.arange(len(known)) + int(max(Part)) + 1  # a label no part has: joins no other face
    labels[:len(known)] = torch.where(crossed, own, labels[:len(known)])
    return labels


def _corner_groups(faces: Tensor, unit: Tensor, labels: Tensor, crease_deg: float) -> Tensor:
    """``(F, 3)`` long: a group id for each face corner of ``faces (F, 3)`` (unit normals ``unit (F, 3)`` in their
    winding, part labels ``labels (F,)``, :func:`_fan_labels`). Corners of one vertex share a group where their
    faces are joined, edge to edge around the vertex, by edges whose two faces are of the same part with normals
    within ``crease_deg`` (glass faces: within :data:`GLASS_CREASE_DEG` where that is less; a smoothing group's fan):
    a corner colour averaged over its group is the same on both sides of every such edge, and a crease or a part
    boundary splits the fan."""
    n_face = len(faces)
    f = faces.long()
    # each face's three edges (corner k to corner k + 1), as sorted vertex pairs
    a, b = f, f.roll(-1, 1)
    lo, hi = torch.minimum(a, b), torch.maximum(a, b)
    key = (lo * (int(f.max()) + 1) + hi).reshape(-1)
    order = key.argsort(stable=True)
    same = key[order][1:] == key[order][:-1]  # neighbours in the sorted list sharing an edge
    e1, e2 = order[:-1][same], order[1:][same]  # flat (face * 3 + k) edge ids
    f1, f2 = e1 // 3, e2 // 3
    crease = torch.where(labels[f1] == int(Part.GLASS), min(crease_deg, GLASS_CREASE_DEG), crease_deg)
    smooth = (sum3(unit[f1] * unit[f2]) >= torch.cos(torch.deg2rad(crease.double()))) & (labels[f1] == labels[f2])
    smooth &= (unit[f1].norm(dim=-1) > 0) & (unit[f2].norm(dim=-1) > 0)
    e1, e2, f1, f2 = e1[smooth], e2[smooth], f1[smooth], f2[smooth]
    # the joined corners: each edge's two vertices, on either face (the corner of face f2 at that vertex)
    v1, w1 = f.reshape(-1)[e1], f.reshape(-1)[(e1 // 3) * 3 + (e1 % 3 + 1) % 3]
    corner_of = lambda face, v: face * 3 + (f[face] == v[:, None]).long().argmax(1)  # noqa: E731
    src = torch.cat([e1 // 3 * 3 + e1 % 3, corner_of(f1, w1)])
    dst = torch.cat([corner_of(f2, v1), corner_of(f2, w1)])
    group = torch.arange(3 * n_face)
    if len(src):
        # connected components by minimum-label propagation (a fan is a short chain: a few rounds)
        for _ in range(3 * n_face):
            new = group.clone()
            new.scatter_reduce_(0, src, group[dst], "amin")
            new.scatter_reduce_(0, dst, group[src], "amin")
            new = new[new]  # pointer jumping: halves the rounds
            if torch.equal(new, group):
                break
            group = new
    return group.view(n_face, 3)


def _members(group: Tensor) -> Tensor:
    """``(G, D)`` long: for each group id ``0..G-1`` of ``group (C,)`` the flat ids of its members, padded with -1."""
    order = group.argsort(stable=True)
    counts = torch.bincount(group, minlength=len(group))
    start = counts.cumsum(0) - counts
    rank = torch.arange(len(group)) - start[group[order]]
    table = torch.full((len(group), max(int(counts.max()), 1)), -1, dtype=torch.long)
    table[group[order], rank] = order
    return table


def _corner_fan_faces(group: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """For each face of ``group (F, 3)`` (:func:`_corner_groups`' corner groups): ``(faces (F, M) long, times (F, M,
    3) long, sizes (F, 3) long)``: the distinct faces of its three corners' fans, ascending, padded with -1; how many
    times each is a member of each corner's fan (0 for the padding); and each corner's fan size (at least 1). A
    face's table, made once, serves each of its pixels (:func:`_corner_part_colors`)."""
    fans = _members(group.reshape(-1))  # (3F, D) flat corner ids of each fan
    fan_faces = torch.where(fans >= 0, fans // 3, -1)[group]  # (F, 3, D)
    sizes = (fan_faces >= 0).sum(2).clamp(min=1)
    ordered, at = fan_faces.flatten(1).sort(1)  # (F, 3 D), the padding first; at // D: the corner
    member = ordered >= 0
    distinct = member.clone()
    distinct[:, 1:] &= ordered[:, 1:] != ordered[:, :-1]
    rank = distinct.cumsum(1) - 1  # each member's place in its face's table (a repeated face: its first's)
    row = torch.arange(len(group))[:, None].expand_as(ordered)
    table = torch.full((len(group), max(int(distinct.sum(1).max()), 1)), -1, dtype=torch.long)
    table[row[distinct], rank[distinct]] = ordered[distinct]
    times = torch.zeros(*table.shape, 3, dtype=torch.long)
    times.index_put_((row[member], rank[member], at[member] // fan_faces.shape[2]), torch.ones(1, dtype=torch.long),
                     accumulate=True)
    return table, times, sizes


def _corner_part_colors(lookup: Callable[[Tensor, Tensor, Tensor, Tensor], tuple[Tensor, Tensor]], face: Tensor,
                        points_s: Tensor, points_t: Tensor, parts: Tensor, rules: Tensor, own: Tensor, bary: Tensor,
                        normals: Tensor, faces: Tensor, verts_t: Tensor, labels: Tensor, crease_deg: float) -> Tensor:
    """``(P, 3)`` colours of never-seen pixels of one car drawn from examples, Gouraud-style
    (:attr:`PhotoSettings.part_smoothing`). Pixel ``p`` shows the surface point ``points_s[p]`` (source pose; at the
    new one ``points_t[p]``) of face ``face[p]`` of ``faces (F, 3)`` (vertices ``verts_t (V, 3)`` at the new pose;
    fan labels ``labels (F,)``, :func:`_fan_labels`) at barycentrics ``bary (P, 3)``, facing ``normals (P, 3)`` (its
    face's, turned to the camera), of part ``parts (P,)``; its own lookup gave it colour ``own (P, 3)`` by rule
    ``rules (P,)``. Each of its face's corners stands for the mean of ``lookup(points at the source pose, normals,
    parts, points at the new pose) -> (colour, rule)`` at the pixel's own point with the normal of each face of the
    corner's smoothing fan (:func:`_corner_groups`: the faces around the vertex joined by edges of one label within
    ``crease_deg``; the face's own among them), and the pixel takes the barycentric mix of its three corners; only
    colours of the pixel's own rule count (none: its own colour). On an edge between two faces of one fan the mix is
    the same from either side (the same corners' fans, the same barycentrics, the same point), so the colour runs on
    across the edge instead of stepping to the next face's examples; a part boundary, a lamp band's edge or a crease
    keeps its step. Looked up at the pixel's own point, not at the vertices: a corner's colour carried along a long
    face (a bus's side, an end cap's fan) drew one end's examples across the whole face. Each face keeps its own
    normal's examples among its corners'. The lookup runs once per distinct (pixel, face of its corners' fans), the
    pixel's own face left out: its lookup is ``own``'s (it was 16 % of them on the real frame's turns)."""
    tri = verts_t[faces.long()]  # (F, 3, 3)
    raw = torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1)
    unit = raw / raw.norm(dim=-1, keepdim=True).clamp_min(1e-300)  # padding faces: a zero normal, joined to none
    # the side the pixel's face was turned to (its winding's normal or the opposite), given to its fans' faces
    side = torch.where(sum3(unit[face] * normals) < 0, -1.0, 1.0).double()
    fan_faces, times, sizes = _corner_fan_faces(_corner_groups(faces, unit, labels, crease_deg))
    near = fan_faces[face]  # (P, M) the faces of the pixel's corners' fans, ascending, -1: none
    # each fan face's share of the pixel: its corner's barycentric over the fan's size, summed over the corners in
    # their order, once each time the face is a member of the corner's fan (adding 0 where it is not changes no sum)
    per_corner = bary.double() / sizes[face]  # (P, 3)
    share = torch.zeros(near.shape, dtype=torch.float64)
    for c in range(3):
        for r in range(int(times[..., c].max())):
            share += torch.where((times[:, :, c] > r)[face], per_corner[:, c:c + 1], 0.0)
    # the (pixel, face) pairs, by pixel then face: one lookup each
    pair = (near >= 0).view(-1).nonzero().flatten()
    q_pix, q_face, weight = pair // near.shape[1], near.view(-1)[pair], share.view(-1)[pair]
    q_normal = side[q_pix, None] * unit[q_face]
    # the pixel's own face: the lookup the caller made (the same point, normal and part; each row's lookup is its own)
    color, rule = own.double()[q_pix], rules[q_pix].clone()
    ask = (q_normal != normals.double()[q_pix]).any(1).nonzero().flatten()
    if len(ask):
        asked, asked_rule = lookup(points_s[q_pix[ask]], q_normal[ask], parts[q_pix[ask]], points_t[q_pix[ask]])
        color[ask], rule[ask] = asked.double(), asked_rule.to(rule.dtype)
    weight = weight * (rule == rules[q_pix]).double()
    total = torch.zeros(len(face), dtype=torch.float64).index_add_(0, q_pix, weight)
    mixed = torch.zeros(len(face), 3, dtype=torch.float64).index_add_(0, q_pix, color.double() * weight[:, None])
    return torch.where((total > 0)[:, None], mixed / total.clamp_min(1e-300)[:, None], own.double())


def _lamp_band(before: ObjectTable, b: int, features: Tensor, corners: bool = True) -> Tensor | None:
    """``(P,)`` the lamp part (:data:`~sdn3d.meshes.parts.Part` ``FRONT_LIGHTS`` or ``TAIL_LIGHTS``, -1: neither)
    whose lamp each point of the car of ``before`` row ``b`` lies on, from its :func:`_part_features` ``features (P,
    6)``: at either end (beyond :data:`LAMP_END` of the length from the middle), in the band :data:`LAMP_BAND` below
    the template's belt line and outside :data:`LAMP_CORNER` of the width from the middle plane (the layout the
    generator draws, ``data.synth.appearance._car``, and where a car's lamps are); ``corners=False``: across the
    whole width (the lamps' heights at either end). None for a template without a belt line."""
    template = int(before.template_id[b])
    if not 0 <= template < len(TEMPLATE_NAMES):
        return None
    belt = canonical_belt(TEMPLATE_SPECS[TEMPLATE_NAMES[template]])
    x, y, z = features[:, 0] / PART_LENGTH_WEIGHT, features[:, 1], features[:, 2]
    inside = (y > belt + LAMP_BAND[0]) & (y < belt + LAMP_BAND[1]) & ((z > LAMP_CORNER) | (not corners))
    out = torch.full((len(features),), -1, dtype=torch.long)
    out[inside & (x > LAMP_END)] = int(Part.FRONT_LIGHTS)
    out[inside & (x < -LAMP_END)] = int(Part.TAIL_LIGHTS)
    return out


#: :func:`_part_colors`: the rows whose nearest examples' colours are gathered and weighted at a time ((3, rows, 16)
#: float64 at most: 1.5 MB).
GATHER_ROWS = 4096
#: :func:`_part_colors`: a tyre example lighter than this quantile of the car's visible pixels' luma is not a tyre
#: (a template's wheel where the car has paint, or a mask that took in the road below the car, drew grey or red
#: wheels); 1: every tyre example is kept.
TYRE_QUANTILE = 0.75
#: A lamp drawn from the other end's (:data:`OTHER_END`) takes its own end's colour: head lamps are white, tail
#: lamps red (:func:`_lamps_of_this_end`). False: the other end's colours as they are (red head lamps).
LAMP_HUES = True
#: :func:`_lamp_band`: canonical heights (``y`` down, the box from -0.5 to 0.5) of the lamps below the belt line, and
#: the shares of the length and width beyond which they lie (``|x| > LAMP_END``, ``|z| > LAMP_CORNER``): the
#: generator's layout (``data.synth.appearance._car``). None: no lamps drawn there (the template's lamp faces alone).
LAMP_BAND: tuple[float, float] | None = (0.04, 0.20)
LAMP_END = 0.47
LAMP_CORNER = 0.28
#: sRGB colour of an end's lamps the photo never showed (:func:`_lamp_band`; shaded by the caller): head lamps white,
#: tail lamps bright red (lit lamps are the brightest thing on a car's end; on the tuning trees' 180-degree turns
#: white beat a light grey, and this red :data:`PART_DEFAULTS`' darker one:
#: docs/results/2026-11-29_cpu/session9/realparts/).
LAMP_DEFAULTS = {int(Part.FRONT_LIGHTS): (1.0, 1.0, 0.95), int(Part.TAIL_LIGHTS): (0.9, 0.1, 0.08)}
#: Parts that never carry a lamp (:func:`_lamp_band`): windows, wheels and plates keep their own colours.
LAMPLESS_PARTS = (int(Part.GLASS), int(Part.TYRE), int(Part.PLATE))


def _lamp_coloured(colors: Tensor, part: int, air: LampAir = None) -> Tensor:
    """``(E,)`` bool: which ``colors (E, 3)`` sRGB look like lamp ``part``'s light, as they are or, seen through
    ``air`` (:func:`_lamp_air`; None: clear air, as they are alone), as they would be in clear air (a car whose
    darkest pixels are its paint, with no dark glass or tyres shown, reads as fogged: its red paint taken out of that
    air is no red, yet it is): saturated red for tail lamps (as :func:`~sdn3d.geometric.lamps.red_lamps` reads
    them), near-white for head lamps, told as the colour is seen whatever the air (fog turns a red lamp pink but
    leaves a white one near-white; out of the air, a fogged light grey paint passed for white, and a never-seen
    template tail-lamp face was drawn red from it: held-out seed 2229's car 12006 of world 0020 turned 90 degrees,
    -0.37 dB, docs/results/2026-11-30_cpu/session24/turn41/)."""
    if air is not None and part == int(Part.TAIL_LIGHTS):
        return _lamp_coloured(colors, part) | _lamp_coloured(_out_of_air(colors, air), part)
    r, g, b = colors.unbind(-1)
    if part == int(Part.TAIL_LIGHTS):
        return (r > 0.25) & (r > 2 * g) & (r > 2 * b)
    return (colors.amin(-1) > 0.55) & (colors.amax(-1) - colors.amin(-1) < 0.15)


def _lamps_of_this_end(colors: Tensor, part: int, paint: Tensor, air: LampAir = None) -> Tensor:
    """``(E, 3)`` ``colors`` of the other end's examples for drawing lamp ``part``: the pixels in the other end's
    lamp colour (:func:`_lamp_coloured`) take ``part``'s own hue (its :data:`PART_DEFAULTS` colour scaled to their
    brightest channel: a red tail lamp becomes a white head lamp as bright); unchanged where the car's ``paint
    (Q, 3)`` (its median) is itself of that colour (a red car's tail lamps are not told from its paint)."""
    other = OTHER_END[part]
    if len(paint) and bool(_lamp_coloured(paint.median(0).values[None], other, air)[0]):
        return colors
    lamp = _lamp_coloured(colors, other, air)
    if not any_set(lamp):
        return colors
    hue = torch.tensor(PART_DEFAULTS[part], dtype=colors.dtype)
    out = colors.clone()
    out[lamp] = (colors[lamp].amax(-1, keepdim=True) * hue / hue.max()).clamp(0, 1)
    return out
