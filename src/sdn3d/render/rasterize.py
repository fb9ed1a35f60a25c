"""Hard z-buffer rasterizer in pure PyTorch (batched; the same code on CPU and CUDA).

Algorithm (no Python loop over faces or pixels; a loop over chunks bounds memory):

1. Gather and project all faces at once; cull faces with a vertex behind ``near`` or
   non-finite, faces beyond ``far``, zero-area faces (padding), faces outside the image and,
   optionally, back faces.
2. Scanline enumeration: each face's pixel rows are enumerated with ``repeat_interleave``;
   on each row the barycentric coordinates are linear in ``u``, so the exact span of pixel
   centres inside the triangle is solved for directly (an inclusive test with a 1e-9
   barycentric tolerance, so pixel centres on a shared edge are never dropped by both
   faces; the z-buffer settles who wins). Only covered pixels are then enumerated.
3. Perspective-correct depth from ``1/z``, which is affine in screen space.
4. z-buffer: the float32 depth's bit pattern (monotonic for positive floats) is packed above
   the face index into one int64 key and reduced with ``scatter_reduce('amin')``: one pass
   gives the nearest face, ties broken by the lower face index (deterministic).
5. Depth and perspective-correct barycentrics of the winners are recomputed in float64.

Per-face set-up and spans are float64: vertices close to ``near`` project far outside the
image, and single precision would shift the edges of such large faces (a ground plane).

With ``crop=True`` the maps hold only the box of the pixels some (face, row) span covers
(:attr:`Fragments.box`): the z-buffer and the outputs are that box's, not the image's. Every
face's set-up, span and pixel coordinate stays the image's (no shifted camera), so each pixel
of the box gets the very values of the whole image's maps, and every pixel outside it is empty.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import torch
from torch import Tensor

from sdn3d.math3d.sums import sum3
from sdn3d.render._common import (
    AREA_EPS,
    check_faces,
    check_intrinsics,
    check_verts,
    face_vertices,
    faces_the_camera,
    project_vertices,
    twice_area,
)
from sdn3d.render.settings import RasterSettings

__all__ = ["Fragments", "PixelIndex", "rasterize_meshes"]

#: Inclusive inside test tolerance, in barycentric units.
_INSIDE_EPS = 1e-9


class PixelIndex(NamedTuple):
    """Image pixels found in a :class:`Fragments`' window (:meth:`Fragments.locate`), for several lookups.

    Attributes:
        index: ``(P,)`` int64 flat index of each pixel in the window's maps (0 outside the window).
        inside: ``(P,)`` bool, which pixels lie in the window; None where all do.
    """

    index: Tensor
    inside: Tensor | None


@dataclass
class Fragments:
    """Per-pixel output of :func:`rasterize_meshes` for ``B`` images of ``H x W``, held in the window
    ``box`` of each image (the whole image unless the rasterizer cropped), ``h x w`` pixels.

    Attributes:
        pix_to_face: ``(B, h, w)`` int64 packed face index ``n * F + f`` of the visible face
            (``F`` = padded faces per mesh), ``-1`` where empty.
        pix_to_mesh: ``(B, h, w)`` int64 mesh index ``n = pix_to_face // F``, ``-1`` where empty.
        depth: ``(B, h, w)`` camera-frame z of the visible surface (the vertices' dtype),
            ``+inf`` where empty (:func:`sdn3d.render.depth_map` gives 0 there).
        bary: ``(B, h, w, 3)`` perspective-correct barycentric coordinates of the visible face's
            vertices ``faces[n, f]`` (non-negative, sum to 1), zeros where empty.
        image_size: ``(H, W)`` of the images.
        box: ``(x0, y0, x1, y1)`` half-open, the window of each image the maps hold (``w = x1 - x0``,
            ``h = y1 - y0``); every pixel outside it is empty. The map functions of
            :mod:`sdn3d.render.maps` give the window's maps.

    The ``*_at`` lookups take image pixels as flat indices ``b * H * W + y * W + x`` (what
    ``.view(-1)`` of whole-image maps indexes), or their :meth:`locate` (found once for several
    lookups), and give the empty values outside the window.
    """

    pix_to_face: Tensor
    pix_to_mesh: Tensor
    depth: Tensor
    bary: Tensor
    image_size: tuple[int, int]
    box: tuple[int, int, int, int]

    @property
    def mask(self) -> Tensor:
        """``(B, h, w)`` bool, true where some face is visible."""
        return self.pix_to_face >= 0

    @property
    def whole(self) -> bool:
        """True where the window is the whole image."""
        height, width = self.image_size
        return self.box == (0, 0, width, height)

    def covered(self) -> Tensor:
        """``(P,)`` int64 flat image indices of the pixels some face covers, in increasing order (the
        whole-image mask's ``nonzero()``)."""
        local = self.mask.view(-1).nonzero().flatten()
        return local if self.whole else self._to_image(local)

    def _to_image(self, local: Tensor) -> Tensor:
        """Flat window indices ``(P,)`` as flat image indices."""
        height, width = self.image_size
        x0, y0, x1, y1 = self.box
        w, hw = x1 - x0, (x1 - x0) * (y1 - y0)
        single = self.pix_to_face.shape[0] == 1  # one image: the flat index is the pixel's
        rest = local if single else local % hw
        y = rest // w
        flat = (y + y0) * width + (rest - y * w) + x0
        return flat if single else flat + local // hw * (height * width)

    def locate(self, flat: Tensor) -> PixelIndex:
        """The flat image pixels ``flat (P,)`` found in the window (:class:`PixelIndex`)."""
        if self.whole:
            return PixelIndex(flat, None)
        height, width = self.image_size
        x0, y0, x1, y1 = self.box
        single = self.pix_to_face.shape[0] == 1  # one image: the flat index is the pixel's
        rest = flat if single else flat % (height * width)
        y = rest // width
        x = rest - y * width
        inside = (y >= y0) & (y < y1) & (x >= x0) & (x < x1)
        index = (y - y0) * (x1 - x0) + (x - x0)
        if not single:
            index += flat // (height * width) * ((y1 - y0) * (x1 - x0))
        if bool(inside.all()):  # (covered pixels: no empty value to put in)
            return PixelIndex(index, None)
        return PixelIndex(torch.where(inside, index, 0), inside)

    def _at(self, values: Tensor, pixels: Tensor | PixelIndex, empty: float) -> Tensor:
        """``values`` (a ``(B, h, w, ...)`` map) at ``pixels``: ``(P,)`` flat image pixels or their
        :meth:`locate`; ``empty`` outside the window."""
        where = pixels if isinstance(pixels, PixelIndex) else self.locate(pixels)
        table = values.reshape(-1, *values.shape[3:])
        if where.inside is None:
            return table[where.index]
        if not len(table):
            return values.new_full((len(where.index), *values.shape[3:]), empty)
        found = table[where.index]
        keep = where.inside.view(-1, *([1] * (values.dim() - 3)))
        return torch.where(keep, found, found.new_full((), empty))

    def face_at(self, pixels: Tensor | PixelIndex) -> Tensor:
        """``(P,)`` :attr:`pix_to_face` at ``pixels`` (flat image pixels ``(P,)`` or their :meth:`locate`; -1
        outside the window)."""
        return self._at(self.pix_to_face, pixels, -1)

    def mesh_at(self, pixels: Tensor | PixelIndex) -> Tensor:
        """``(P,)`` :attr:`pix_to_mesh` at ``pixels`` (as :meth:`face_at`; -1 outside the window)."""
        return self._at(self.pix_to_mesh, pixels, -1)

    def depth_at(self, pixels: Tensor | PixelIndex) -> Tensor:
        """``(P,)`` :attr:`depth` at ``pixels`` (as :meth:`face_at`; +inf outside the window)."""
        return self._at(self.depth, pixels, float("inf"))

    def bary_at(self, pixels: Tensor | PixelIndex) -> Tensor:
        """``(P, 3)`` :attr:`bary` at ``pixels`` (as :meth:`face_at`; zeros outside the window)."""
        return self._at(self.bary, pixels, 0.0)

    @classmethod
    def empty(cls, batch: int, image_size: tuple[int, int], dtype: torch.dtype, device: torch.device,
              box: tuple[int, int, int, int] | None = None) -> Fragments:
        """Empty fragments of ``batch`` images of ``image_size (H, W)``, held in the window ``box`` (default: the
        whole images): ``(batch, h, w)`` maps of the box, ``depth`` and ``bary`` in ``dtype``."""
        height, width = image_size
        box = (0, 0, width, height) if box is None else box
        shape = (batch, box[3] - box[1], box[2] - box[0])
        return cls(
            pix_to_face=torch.full(shape, -1, dtype=torch.long, device=device),
            pix_to_mesh=torch.full(shape, -1, dtype=torch.long, device=device),
            depth=torch.full(shape, float("inf"), dtype=dtype, device=device),
            bary=torch.zeros(*shape, 3, dtype=dtype, device=device),
            image_size=(height, width),
            box=box,
        )

    def in_image(self, values: Tensor, empty: float) -> Tensor:
        """``values (B, h, w, ...)``, a map of the window, as the ``(B, H, W, ...)`` map of the whole
        images, ``empty`` outside the window."""
        if self.whole:
            return values
        height, width = self.image_size
        x0, y0, x1, y1 = self.box
        out = values.new_full((values.shape[0], height, width, *values.shape[3:]), empty)
        out[:, y0:y1, x0:x1] = values
        return out



def _check_mesh_to_image(
    mesh_to_image: Tensor | None, batch_size: int | None, num_meshes: int, device: torch.device
) -> tuple[Tensor, int]:
    if mesh_to_image is None:
        if batch_size is not None and int(batch_size) < num_meshes:
            raise ValueError(
                f"batch_size={batch_size} is below the {num_meshes} meshes; pass mesh_to_image to share images"
            )
        return torch.arange(num_meshes, device=device), num_meshes if batch_size is None else int(batch_size)
    if not isinstance(mesh_to_image, Tensor) or mesh_to_image.shape != (num_meshes,):
        shape = (
            tuple(mesh_to_image.shape) if isinstance(mesh_to_image, Tensor) else type(mesh_to_image).__name__
        )
        raise ValueError(f"mesh_to_image must be a ({num_meshes},) tensor of image indices, got {shape}")
    if mesh_to_image.is_floating_point() or mesh_to_image.dtype == torch.bool:
        raise ValueError(f"mesh_to_image must be an integer tensor, got dtype {mesh_to_image.dtype}")
    index = mesh_to_image.to(device=device, dtype=torch.long)
    top = int(index.max()) + 1 if num_meshes > 0 else 0
    batch = top if batch_size is None else int(batch_size)
    if num_meshes > 0 and (int(index.min()) < 0 or top > batch):
        raise ValueError(
            f"mesh_to_image values must lie in [0, batch_size={batch}), got [{int(index.min())}, {top - 1}]"
        )
    return index, batch


def _barycentric_planes(screen: Tensor, area2: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Coefficients of ``l_k(u, v) = A_k u + B_k v + C_k`` for ``(M, 3, 2)`` triangles; each ``(M, 3)``."""
    u, v = screen[..., 0], screen[..., 1]
    u1, u2 = u.roll(-1, dims=1), u.roll(-2, dims=1)
    v1, v2 = v.roll(-1, dims=1), v.roll(-2, dims=1)
    inv = 1.0 / area2.unsqueeze(1)
    return (v1 - v2) * inv, (u2 - u1) * inv, (u1 * v2 - u2 * v1) * inv


def _row_spans(a: Tensor, b: Tensor, c: Tensor, rows: Tensor, width: int) -> tuple[Tensor, Tensor]:
    """First column and count of the pixel centres inside each (face, row) pair.

    On row ``v`` the inside test ``A_k u + B_k v + C_k >= -eps`` bounds ``u`` from below
    (``A_k > 0``), above (``A_k < 0``) or is constant in ``u`` (``A_k == 0``).
    """
    rhs = -_INSIDE_EPS - b * rows.unsqueeze(1) - c  # A_k u >= rhs
    flat = a == 0
    bound = rhs / torch.where(flat, torch.ones_like(a), a)
    # the three edges' bounds combined column by column (an amax over a dimension of 3 is a slow reduction)
    low = bound.masked_fill(~(a > 0), float("-inf"))
    high = bound.masked_fill(~(a < 0), float("inf"))
    lower = torch.maximum(torch.maximum(low[:, 0], low[:, 1]), low[:, 2]).clamp_(-1.0, width)
    upper = torch.minimum(torch.minimum(high[:, 0], high[:, 1]), high[:, 2]).clamp_(-1.0, width)
    out = flat & ~(rhs <= 0)
    feasible = ~(out[:, 0] | out[:, 1] | out[:, 2])
    first = torch.ceil(lower).clamp_(min=0).long()
    last = torch.floor(upper).clamp_(max=width - 1).long()
    count = (last - first + 1).clamp_(min=0) * feasible
    return first, count


def rasterize_meshes(
    verts: Tensor,
    faces: Tensor,
    K: Tensor,
    settings: RasterSettings,
    mesh_to_image: Tensor | None = None,
    batch_size: int | None = None,
    crop: bool = False,
) -> Fragments:
    """Rasterize padded meshes into ``B`` images with a z-buffer (no gradients).

    Args:
        verts: ``(N, V, 3)`` camera-frame vertices (x right, y down, z forward).
        faces: ``(N, F, 3)`` or shared ``(F, 3)`` int vertex indices; padding faces ``(0, 0, 0)``.
        K: ``(3, 3)`` or per-image ``(B, 3, 3)`` intrinsics (zero skew), pixel centres at integers.
        settings: image size, near / far planes, back-face culling, chunk size.
        mesh_to_image: ``(N,)`` image index of each mesh; default ``arange(N)`` (one mesh per image).
        batch_size: number of images ``B``; default ``mesh_to_image.max() + 1`` (``N`` without it).
        crop: hold only the box of the pixels some face's rows span, the same box in every image
            (module doc); ``(0, 0, 0, 0)`` where none. The box's values are the whole image's.

    Returns:
        :class:`Fragments` of ``(B, H, W)`` maps, or of the box's ``(B, h, w)`` with ``crop``;
        ``pix_to_face`` indexes the packed face list ``n * F + f``.

    Example:
        >>> import torch
        >>> from sdn3d.render import RasterSettings, rasterize_meshes
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]])  # 5 m ahead
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> fragments = rasterize_meshes(verts, faces, K, RasterSettings(image_size=(16, 16)))
        >>> fragments.pix_to_face.shape, fragments.bary.shape
        (torch.Size([1, 16, 16]), torch.Size([1, 16, 16, 3]))
        >>> int(fragments.mask.sum())  # pixel centres inside the 12 x 12 px triangle
        72
        >>> fragments.pix_to_face[0, 6, 7].item(), fragments.depth[0, 6, 7].item()
        (0, 5.0)
    """
    verts = check_verts(verts)
    device, dtype = verts.device, verts.dtype
    num_meshes, num_verts = verts.shape[:2]
    faces = check_faces(faces, num_meshes, num_verts, device)
    image_of_mesh, batch = _check_mesh_to_image(mesh_to_image, batch_size, num_meshes, device)
    K = check_intrinsics(K, batch, torch.float64, device, "images")
    height, width = settings.image_size

    def empty() -> Fragments:  # made only where nothing is drawn: the maps of a whole image are costly to allocate
        return Fragments.empty(batch, (height, width), dtype, device, (0, 0, 0, 0) if crop else None)

    num_faces = faces.shape[1]
    if num_meshes == 0 or num_faces == 0 or batch == 0:
        return empty()
    if num_meshes * num_faces >= 2**31:
        raise ValueError(f"too many faces to pack: N * F = {num_meshes * num_faces} must stay below 2**31")

    with torch.no_grad():
        verts64 = verts.detach().to(torch.float64)
        screen, ok = project_vertices(verts64, K[image_of_mesh], settings.near)
        fverts = face_vertices(verts64, faces).reshape(-1, 3, 3)
        screen = face_vertices(screen, faces).reshape(-1, 3, 2)
        valid = face_vertices(ok.unsqueeze(-1), faces).reshape(-1, 3).all(-1)
        depth_v = fverts[..., 2]
        area2 = twice_area(screen)
        valid &= area2.abs() > AREA_EPS
        valid &= (depth_v <= settings.far).any(1)
        if settings.cull_backfaces:
            valid &= faces_the_camera(fverts)
        umin, umax = screen[..., 0].amin(1), screen[..., 0].amax(1)
        first_row = torch.ceil(screen[..., 1].amin(1).clamp(-1.0, height)).clamp(min=0).long()
        last_row = torch.floor(screen[..., 1].amax(1).clamp(-1.0, height)).clamp(max=height - 1).long()
        valid &= (umax >= 0) & (umin <= width - 1) & (last_row >= first_row)
        face_ids = valid.nonzero().squeeze(1)
        if face_ids.numel() == 0:
            return empty()

        # Per-face planes: barycentrics and 1/z are affine in (u, v).
        screen, area2, depth_v = screen[face_ids], area2[face_ids], depth_v[face_ids]
        a, b, c = _barycentric_planes(screen, area2)
        inv_z = 1.0 / depth_v
        az, bz, cz = sum3(a * inv_z, 1), sum3(b * inv_z, 1), sum3(c * inv_z, 1)
        rows_per_face = last_row[face_ids] - first_row[face_ids] + 1

        # (face, row) pairs and their spans of covered pixel centres.
        pair_face = torch.repeat_interleave(rows_per_face)  # index into face_ids
        row_start = torch.cumsum(rows_per_face, 0) - rows_per_face
        rows = (
            first_row[face_ids][pair_face]
            + torch.arange(pair_face.numel(), device=device)
            - row_start[pair_face]
        )
        first_col, cols = _row_spans(a[pair_face], b[pair_face], c[pair_face], rows.to(torch.float64), width)
        keep = cols > 0
        if not bool(keep.any()):
            return empty()
        pair_face, rows, first_col, cols = pair_face[keep], rows[keep], first_col[keep], cols[keep]
        if crop:  # the box of the spans: every candidate pixel
            x0, y0 = int(first_col.min()), int(rows.min())
            x1, y1 = int((first_col + cols).max()), int(rows.max()) + 1
        else:
            x0, y0, x1, y1 = 0, 0, width, height
        box_h, box_w = y1 - y0, x1 - x0
        packed_face = face_ids[pair_face]
        # flat index into the box's maps, less the column: image, then the row's start, column 0 at x0
        pixel_base = image_of_mesh[packed_face // num_faces] * (box_h * box_w) + (rows - y0) * box_w - x0
        inv_z_row = bz[pair_face] * rows + cz[pair_face]
        slope = az[pair_face]

        zbuf = torch.full(
            (batch * box_h * box_w,), torch.iinfo(torch.int64).max, dtype=torch.long, device=device
        )
        # Chunk boundaries over (face, row) pairs so each chunk covers <= max_pairs pixels.
        ends = torch.cumsum(cols, 0)
        bounds = torch.searchsorted(
            ends,
            torch.arange(1, int(ends[-1]) // settings.max_pairs_per_chunk + 1, device=device)
            * settings.max_pairs_per_chunk,
        )
        edges = [0, *bounds.tolist(), cols.numel()]
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            if hi <= lo:
                continue
            ccols = cols[lo:hi]
            owner = torch.repeat_interleave(ccols)  # (P,) index into this chunk's (face, row) pairs
            start = torch.cumsum(ccols, 0) - ccols
            col = first_col[lo:hi][owner] + torch.arange(owner.numel(), device=device) - start[owner]
            inv_depth = inv_z_row[lo:hi][owner] + slope[lo:hi][owner] * col
            depth32 = (1.0 / inv_depth).to(torch.float32)
            ok = (inv_depth > 0) & (depth32 <= settings.far)
            key = (depth32.view(torch.int32).to(torch.long) << 32) | packed_face[lo:hi][owner]
            pixel = pixel_base[lo:hi][owner] + col
            zbuf.scatter_reduce_(0, pixel[ok], key[ok], reduce="amin")

        # Decode winners and recompute depth / perspective-correct barycentrics in float64.
        hit = (zbuf != torch.iinfo(torch.int64).max).nonzero().squeeze(1)
        winner = zbuf[hit] & 0xFFFFFFFF
        local = torch.searchsorted(face_ids, winner)  # row of the winner in the per-face tables
        pix_in_box = hit % (box_h * box_w)
        u = (pix_in_box % box_w + x0).to(torch.float64).unsqueeze(1)
        v = (pix_in_box // box_w + y0).to(torch.float64).unsqueeze(1)
        lam = (a[local] * u + b[local] * v + c[local]).clamp(min=0)
        weights = lam * inv_z[local]
        depth = 1.0 / sum3(weights, 1)
        bary = weights * depth.unsqueeze(1)
        bary = bary / sum3(bary, 1, keepdim=True)

        out = Fragments.empty(batch, (height, width), dtype, device, (x0, y0, x1, y1))
        out.pix_to_face.view(-1)[hit] = winner
        out.pix_to_mesh.view(-1)[hit] = winner // num_faces
        out.depth.view(-1)[hit] = depth.to(dtype)
        out.bary.view(-1, 3)[hit] = bary.to(dtype)
    return out
