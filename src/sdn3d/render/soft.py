"""SoftRas-style soft silhouettes, one per mesh (differentiable w.r.t. vertices and intrinsics).

For pixel ``p`` and face ``j`` (projected to screen space), ``d(p, j)`` is the distance from
the pixel centre to the triangle in **pixels**, ``delta = +1`` inside, ``-1`` outside and

    D_j(p) = sigmoid(delta * d^2 / sigma),   A(p) = 1 - prod_j (1 - D_j(p)).

``log(1 - D) = -softplus(delta * d^2 / sigma)`` exactly, so the product is accumulated as a
sum in log space with no clamping and no ``log(0)``: ``A = 1 - exp(sum_j -softplus(x_j))``.

Culling (never a dense pixels x faces tensor): a face only reaches pixels outside it within
``r`` with ``r^2 = sigma * log(1 / cull_eps - 1)``, where ``D_j = cull_eps``. The (face, pixel)
pairs of each face's bounding box grown by ``r`` are enumerated as dense windows: faces are
sorted by box size and processed in chunks of equal padded window ``(Hb, Wb)``, laid out
``(Hb, Wb, faces)`` with faces innermost, so pairs need no gathers and rows and columns enter
the distance computation separately; the terms are summed per pixel with ``scatter_add``.
Pairs outside the grown box are never evaluated: each such term is below ``cull_eps``, so the
result is within a few ``cull_eps`` of the dense sum (up to ~10 ``cull_eps`` where many small
faces lie just beyond ``r``, e.g. large ``sigma``). Pairs in the box corners beyond ``r`` are
kept (masking them costs more than it saves); window padding is placed ``3 r + 1`` away.

The backward pass is analytic (:class:`_SoftSilhouetteFunction`, not twice differentiable):
``dA/dx_j = (1 - A) D_j``; with ``q`` the closest boundary point on edge ``(a, b)``,
``q = a + t (b - a)``, the envelope theorem gives ``d(d^2)/da = -2 (1 - t)(p - q)`` and
``d(d^2)/db = -2 t (p - q)``; autograd carries the screen-space gradient through the
projection to the vertices (and ``K``).

Computation runs in the vertices' dtype (float32 or float64; half precision is upcast to
float32).

Culled faces (padding, zero area, any vertex non-finite or at ``z < near``) contribute
nothing, so a mesh whose vertices are all NaN renders an all-zero silhouette and gets zero
(not NaN) gradients; other meshes and faces are unaffected.
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

import torch
import torch.nn.functional as tnf
from torch import Tensor
from torch.autograd.function import once_differentiable

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
from sdn3d.render._native import soft_kernel
from sdn3d.render.settings import SoftSilhouetteSettings

__all__ = ["soft_silhouette", "soft_silhouette_dense", "kernel_threads"]

#: Threads of the fused kernel where :func:`kernel_threads` set them (None: torch's intra-op count).
_KERNEL_THREADS: ContextVar[int | None] = ContextVar("sdn3d_soft_kernel_threads", default=None)


@contextmanager
def kernel_threads(threads: int) -> Iterator[None]:
    """Run the fused kernel on ``threads`` threads inside the block, whatever torch's intra-op count: a caller that
    keeps torch's small operations on one thread (:func:`sdn3d.geometric.fit.fit_to_masks`) still splits the kernel's
    meshes over its cores. The kernel's result does not depend on its thread count (``soft_kernel.cpp``)."""
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
        raise ValueError(f"kernel threads must be a positive integer, got {threads!r}")
    token = _KERNEL_THREADS.set(threads)
    try:
        yield
    finally:
        _KERNEL_THREADS.reset(token)

#: Per-chunk overhead (about 50 tensor ops) expressed in (face, pixel) pairs, for chunking. 4096 drew a fit
#: (docs/results/2026-11-28_cpu/session6/cost) about 9 % faster than 8192 (less window padding, more chunks).
_CHUNK_COST = 4096
#: dtypes the fused kernel is built for (its function-name suffix).
_KERNEL_DTYPES = {torch.float32: "f32", torch.float64: "f64"}


def _screen_triangles(
    verts: Tensor, faces: Tensor, K: Tensor, near: float, cull_backfaces: bool = False
) -> tuple[Tensor, Tensor, int, int]:
    """Counter-clockwise screen triangles ``(N * F, 3, 2)`` and their validity ``(N * F,)`` (with
    ``cull_backfaces`` a face whose outward normal points away from the camera is invalid)."""
    verts = check_verts(verts)
    if verts.dtype not in (torch.float32, torch.float64):
        verts = verts.float()  # squared pixel distances overflow half precision
    num_meshes, num_verts = verts.shape[:2]
    faces = check_faces(faces, num_meshes, num_verts, verts.device)
    K = check_intrinsics(K, num_meshes, verts.dtype, verts.device, "meshes")
    screen, ok = project_vertices(verts, K, near)
    screen = face_vertices(screen, faces).reshape(-1, 3, 2)
    valid = face_vertices(ok.unsqueeze(-1), faces).reshape(-1, 3).all(-1)
    area2 = twice_area(screen)
    valid = valid & (area2.abs() > AREA_EPS)
    if cull_backfaces:
        valid = valid & faces_the_camera(face_vertices(verts.detach(), faces).reshape(-1, 3, 3))
    # Orient every face counter-clockwise so "inside" is "all edge cross products >= 0".
    swapped = screen.index_select(1, torch.tensor([0, 2, 1], device=screen.device))
    screen = torch.where((area2 < 0).view(-1, 1, 1), swapped, screen)
    return screen, valid, num_meshes, faces.shape[1]


def _edge_tables(screen: Tensor) -> tuple[Tensor, ...]:
    """Per-face edge data, each ``(3, M)`` (edge first, faces last): start ``(ax, ay)``, vector
    ``(ex, ey)`` and ``(ex, ey) / |e|^2``."""
    edge = screen.roll(-1, dims=1) - screen
    scaled = edge / (edge * edge).sum(-1, keepdim=True).clamp_min(AREA_EPS)
    return tuple(
        t.T
        for t in (screen[..., 0], screen[..., 1], edge[..., 0], edge[..., 1], scaled[..., 0], scaled[..., 1])
    )


def _nearest_edge(
    px: Tensor, py: Tensor, tables: tuple[Tensor, ...], details: bool = True
) -> tuple[Tensor, ...]:
    """Distance from a grid of pixel centres to triangles; edges on dim 0, faces last.

    Args:
        px: ``(Wb, M)`` (or broadcastable) pixel-centre columns; ``py``: ``(Hb, 1, M)`` rows.
        tables: :func:`_edge_tables` entries shaped ``(3, 1, 1, M)``.
        details: also return what the analytic backward needs.

    Returns:
        ``d2`` (squared distance to the nearest edge segment) and ``cmin`` (smallest edge cross
        product: ``>= 0`` inside a counter-clockwise triangle), each ``(Hb, Wb, M)``; with
        ``details`` also the nearest edge as two 0 / 1 float flags (edge 1 nearer than edge 0;
        edge 2 nearest), its clamped segment parameter ``t`` and ``rx, ry`` (pixel minus the
        closest point).
    """
    ax, ay, ex, ey, ex_s, ey_s = tables
    # This is the hot loop. Faces are the innermost (contiguous, vectorised) dimension, and
    # columns and rows enter separately, so only the terms mixing them are full-size tensors.
    wx, wy = px - ax, py - ay  # (3, 1, Wb, M), (3, Hb, 1, M)
    t = (wx * ex_s + wy * ey_s).clamp_(0.0, 1.0)
    rx, ry = torch.addcmul(wx, t, ex, value=-1.0), torch.addcmul(wy, t, ey, value=-1.0)
    d0, d1, d2 = torch.addcmul(rx * rx, ry, ry).unbind(0)
    c0, c1, c2 = (ex * wy - ey * wx).unbind(0)
    cmin = torch.minimum(torch.minimum(c0, c1), c2)
    nearer = torch.minimum(d0, d1)
    best = torch.minimum(nearer, d2)
    if not details:
        return best, cmin
    # The nearest edge as float flags and lerp selections: bool tensors (where, masked_fill) and
    # reductions over a size-3 dim are an order of magnitude slower on CPU than arithmetic.
    pick1 = torch.gt(d0, d1, out=torch.empty_like(d0))  # edge 1 nearer than edge 0
    pick2 = torch.gt(nearer, d2, out=torch.empty_like(d0))  # edge 2 nearest

    def pick(v: Tensor) -> Tensor:
        return torch.lerp(torch.lerp(v[0], v[1], pick1), v[2], pick2)  # exact for 0 / 1 weights

    return best, cmin, pick1, pick2, pick(t), pick(rx), pick(ry)


def _face_boxes(screen: Tensor, valid: Tensor, radius: float, height: int, width: int) -> tuple[Tensor, ...]:
    """Pixel boxes grown by ``radius``: first column / row and box width / height (0 if culled),
    and a column / row farther than ``radius`` from the face (for window padding)."""
    a, b, c = screen.unbind(1)  # elementwise over the three vertices: a quarter of amin / amax's time on CPU
    lo, hi = torch.minimum(torch.minimum(a, b), c), torch.maximum(torch.maximum(a, b), c)
    away = lo - (3.0 * radius + 1.0)  # D there is below cull_eps ** 9: negligible
    size = screen.new_tensor([width, height])
    # Clamp before the integer cast: faces near the ``near`` plane project very far away.
    first = torch.ceil((lo - radius).clamp(min=-1.0).minimum(size)).clamp(min=0).long()
    last = torch.floor((hi + radius).clamp(min=-1.0).minimum(size)).minimum(size - 1).long()
    extent = (last - first + 1).clamp(min=0) * valid.unsqueeze(1)
    return first[:, 0], first[:, 1], extent[:, 0], extent[:, 1], away[:, 0], away[:, 1]


def _window_chunks(
    box_w: Tensor, box_h: Tensor, budget: int
) -> tuple[Tensor, list[tuple[int, int, int, int]]]:
    """Group faces into chunks of padded ``(Hb, Wb)`` windows of at most ``budget`` pairs.

    Heights are binned (exact up to 8 pixels, then ~20 % apart); within a height bin faces are
    sorted by width and a chunk takes in wider faces while the padding this adds to its
    earlier faces costs less than launching another chunk (~``_CHUNK_COST`` pairs).
    Returns the face order and ``(start, stop, Hb, Wb)`` ranges over it: a chunk's pairs form a
    dense ``(Hb, Wb, faces)`` block, so they need no per-pair gathers or index arithmetic.
    """
    sizes = list(range(1, 9))
    while sizes[-1] < int(box_h.max()):
        sizes.append(math.ceil(sizes[-1] * 1.2))
    stride = int(box_w.max()) + 1
    key = torch.searchsorted(torch.tensor(sizes, device=box_h.device), box_h) * stride + box_w
    order = torch.argsort(key)
    keys, counts = torch.unique_consecutive(key[order], return_counts=True)
    groups: list[list[int]] = []  # [start, count, Hb, Wb]
    start = 0
    for k, count in zip(keys.tolist(), counts.tolist(), strict=True):
        win_h, win_w = sizes[k // stride], k % stride
        last = groups[-1] if groups else None
        if (
            last is not None
            and last[2] == win_h
            and last[1] * (win_w - last[3]) * win_h <= _CHUNK_COST
            and (last[1] + count) * win_h * win_w <= budget
        ):
            last[1], last[3] = last[1] + count, win_w
        else:
            groups.append([start, count, win_h, win_w])
        start += count
    chunks = []
    for first, count, win_h, win_w in groups:
        step = max(1, budget // (win_h * win_w))
        chunks += [
            (lo, min(lo + step, first + count), win_h, win_w) for lo in range(first, first + count, step)
        ]
    return order, chunks


def _kernel_for(screen: Tensor, settings: SoftSilhouetteSettings) -> ctypes.CDLL | None:
    """The fused kernel when the settings ask for it and it can draw ``screen`` (CPU, float32 / float64)."""
    if not settings.native_kernel or screen.device.type != "cpu" or screen.dtype not in _KERNEL_DTYPES:
        return None
    return soft_kernel()


def _call(kernel: ctypes.CDLL, direction: str, screen: Tensor, box: Tensor, faces_per_mesh: int,
          settings: SoftSilhouetteSettings, *out: Tensor) -> None:
    """Run the kernel's ``forward`` (accumulates ``-softplus(x)`` into ``out[0]``, the flat ``log_keep``) or
    ``backward`` (``out``: the per-pixel gradient factor and the ``(M, 3, 2)`` screen gradient it writes), on
    torch's intra-op thread count or :func:`kernel_threads`' (split by meshes; the result does not depend on it)."""
    height, width = settings.image_size
    fn = getattr(kernel, f"sdn3d_soft_{direction}_{_KERNEL_DTYPES[screen.dtype]}")
    threads = _KERNEL_THREADS.get()
    fn(screen.data_ptr(), box.data_ptr(), screen.shape[0], faces_per_mesh, height, width,
       1.0 / settings.sigma, AREA_EPS, *(t.data_ptr() for t in out), threads or torch.get_num_threads())


def _kernel_boxes(kernel: ctypes.CDLL, screen: Tensor, valid: Tensor, settings: SoftSilhouetteSettings) -> Tensor:
    """``(M, 4)`` int64 ``(first column, first row, width, height)`` of each face's box, width and height 0 where
    ``valid`` is False: :func:`_face_boxes`' first four, the same integers, computed by the kernel (the dozen tensor
    operations took a tenth of a fit's draws outside the kernel). ``screen`` contiguous, on the CPU."""
    height, width = settings.image_size
    box = torch.empty(screen.shape[0], 4, dtype=torch.long)
    valid = valid.contiguous()
    fn = getattr(kernel, f"sdn3d_soft_boxes_{_KERNEL_DTYPES[screen.dtype]}")
    fn(screen.data_ptr(), valid.data_ptr(), screen.shape[0], height, width, settings.cull_radius, box.data_ptr())
    return box


class _SoftSilhouetteFunction(torch.autograd.Function):
    """Screen triangles ``(M, 3, 2)`` -> flat silhouettes ``(N * H * W,)`` with an analytic backward."""

    @staticmethod
    def forward(ctx, screen: Tensor, valid: Tensor, faces_per_mesh: int, settings: SoftSilhouetteSettings):
        height, width = settings.image_size
        log_keep = screen.new_zeros(screen.shape[0] // faces_per_mesh * height * width)
        kernel = _kernel_for(screen, settings)
        if kernel is not None:  # the same pairs, fused: see soft_kernel.cpp
            screen = screen.detach().contiguous()
            box = _kernel_boxes(kernel, screen, valid, settings)
            _call(kernel, "forward", screen, box, faces_per_mesh, settings, log_keep)
            ctx.settings, ctx.kernel, ctx.faces_per_mesh = settings, kernel, faces_per_mesh
            ctx.save_for_backward(log_keep, screen, box)
            return -torch.expm1(log_keep)
        ctx.kernel = None
        col0, row0, box_w, box_h, away_u, away_v = _face_boxes(
            screen, valid, settings.cull_radius, height, width
        )
        face_ids = (box_w * box_h).nonzero().squeeze(1)
        chunks: list[tuple[int, int, int, int]] = []
        saved: list[Tensor] = []
        if face_ids.numel() > 0:
            order, chunks = _window_chunks(box_w[face_ids], box_h[face_ids], settings.max_pairs_per_chunk)
            face_ids = face_ids[order]  # faces sorted by window size: chunks are contiguous slices
            tables = tuple(tab.index_select(1, face_ids).view(3, 1, 1, -1) for tab in _edge_tables(screen))
            boxes = tuple(
                b.index_select(0, face_ids).to(screen.dtype)
                for b in (col0, row0, box_w, box_h, away_u, away_v)
            )
            base = face_ids // faces_per_mesh * (height * width)
            for lo, hi, win_h, win_w in chunks:
                saved += _forward_chunk(
                    (win_h, win_w),
                    base[lo:hi],
                    [b[lo:hi] for b in boxes],
                    [tab[..., lo:hi] for tab in tables],
                    log_keep,
                    settings,
                    ctx.needs_input_grad[0],
                )
        ctx.settings, ctx.chunks, ctx.num_faces = settings, chunks, screen.shape[0]
        ctx.save_for_backward(log_keep, face_ids, *saved)
        return -torch.expm1(log_keep)

    @staticmethod
    @once_differentiable
    def backward(ctx, grad_silhouette: Tensor):
        if ctx.kernel is not None:
            log_keep, screen, box = ctx.saved_tensors
            pixel_grad = (grad_silhouette * torch.exp(log_keep) * (-2.0 / ctx.settings.sigma)).contiguous()
            grad_screen = torch.empty_like(screen)
            _call(ctx.kernel, "backward", screen, box, ctx.faces_per_mesh, ctx.settings, pixel_grad, grad_screen)
            return grad_screen, None, None, None
        log_keep, face_ids, *saved = ctx.saved_tensors
        grad_screen = log_keep.new_zeros(ctx.num_faces, 3, 2)
        if not ctx.chunks:
            return grad_screen, None, None, None
        grad_sorted = log_keep.new_empty(face_ids.numel(), 3, 2)
        # dA/dx_j = (1 - A) D_j for x_j = delta d^2 / sigma, dx_j / d(d^2) = delta / sigma, and the
        # envelope theorem: d(d^2)/da = -2 (1 - t) r, d(d^2)/db = -2 t r with r = p - q.
        pixel_grad = grad_silhouette * torch.exp(log_keep) * (-2.0 / ctx.settings.sigma)
        for i, (lo, hi, _, _) in enumerate(ctx.chunks):
            pixel, pick1, pick2, t, rx, ry, x = saved[7 * i : 7 * i + 7]  # (window, faces)
            coef = pixel_grad.index_select(0, pixel.view(-1)).view_as(x).mul_(torch.sigmoid(x).copysign_(x))
            end = coef * t  # weight of the nearest edge's end vertex; its start gets coef - end
            start = coef - end
            # One-hot of the nearest edge from the two flags (arithmetic, no bool tensors).
            not2 = 1.0 - pick2
            on1 = pick1 * not2
            on = (not2 - on1, on1, pick2)
            grads = []
            for v in range(3):  # vertex v starts edge v and ends edge v - 1
                weight = torch.addcmul(on[v] * start, on[v - 1], end)
                grads.append(torch.stack([(weight * rx).sum(0), (weight * ry).sum(0)], -1))
            grad_sorted[lo:hi] = torch.stack(grads, 1)
        grad_screen.index_copy_(0, face_ids, grad_sorted)
        return grad_screen, None, None, None


def _forward_chunk(
    window: tuple[int, int],
    base: Tensor,
    boxes: list[Tensor],
    tables: list[Tensor],
    log_keep: Tensor,
    settings: SoftSilhouetteSettings,
    for_backward: bool,
) -> list[Tensor]:
    """One dense ``(Hb, Wb, faces)`` block of (face, pixel) pairs; accumulates ``-softplus(x)``.

    Returns what the backward needs (nothing unless ``for_backward``), each ``(Hb * Wb, faces)``:
    pixel index, the nearest-edge flags, ``t``, ``rx``, ``ry`` of that edge and ``x``.
    """
    height, width = settings.image_size
    col0, row0, box_w, box_h, away_u, away_v = boxes  # (faces,)
    dc = torch.arange(window[1], dtype=col0.dtype, device=col0.device).view(-1, 1)
    dr = torch.arange(window[0], dtype=col0.dtype, device=col0.device).view(-1, 1, 1)
    col, row = col0 + dc, row0 + dr  # (Wb, faces), (Hb, 1, faces)
    # Padding columns / rows beyond a face's box are moved 3 r + 1 away from the face, so their
    # terms are ~0 (below cull_eps ** 9); their clamped pixel index stays valid.
    px, py = torch.where(dc < box_w, col, away_u), torch.where(dr < box_h, row, away_v)
    pixel = (base + row.clamp(max=height - 1).long() * width) + col.clamp(max=width - 1).long()
    d2, cmin, *details = _nearest_edge(px, py, tuple(tables), details=for_backward)
    x = torch.copysign(d2, cmin).mul_(1.0 / settings.sigma)
    # Pairs in the box but beyond the culling radius are kept (each adds less than cull_eps, and
    # masking them would cost more than it saves); padding pairs add ~0 to a valid pixel.
    log_keep.scatter_add_(0, pixel.view(-1), tnf.softplus(x).neg_().view(-1))  # faster than index_add_
    if not for_backward:
        return []
    faces = x.shape[-1]
    return [v.reshape(-1, faces) for v in (pixel, *details, x)]


def soft_silhouette(verts: Tensor, faces: Tensor, K: Tensor, settings: SoftSilhouetteSettings) -> Tensor:
    """Soft silhouette of each mesh in its own image (culled, sparse, analytic backward).

    Args:
        verts: ``(N, V, 3)`` camera-frame vertices; gradients flow to them (and to ``K``).
        faces: ``(N, F, 3)`` or shared ``(F, 3)`` vertex indices; padding faces ``(0, 0, 0)``.
        K: ``(3, 3)`` or per-mesh ``(N, 3, 3)`` intrinsics of each crop (zero skew).
        settings: crop size ``(H, W)``, ``sigma`` (pixels^2), ``cull_eps``, ``near``.

    Returns:
        ``(N, H, W)`` silhouettes in ``[0, 1]``, within a few ``cull_eps`` of
        :func:`soft_silhouette_dense` (below ``1e-3`` for the default settings).

    Faces with a vertex behind ``near`` or non-finite, and zero-area faces, are culled: a mesh
    of NaN vertices renders all zeros, and culled faces get zero (never NaN) gradients.

    Example:
        >>> import torch
        >>> from sdn3d.render import SoftSilhouetteSettings, soft_silhouette
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]], requires_grad=True)
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> silhouette = soft_silhouette(verts, faces, K, SoftSilhouetteSettings(image_size=(16, 16)))
        >>> silhouette.shape
        torch.Size([1, 16, 16])
        >>> round(silhouette[0, 6, 7].item(), 3), round(silhouette.sum().item())  # 72 px^2 + soft edges
        (1.0, 73)
        >>> silhouette.sum().backward()
        >>> verts.grad.shape
        torch.Size([1, 3, 3])
    """
    screen, valid, num_meshes, faces_per_mesh = _screen_triangles(
        verts, faces, K, settings.near, settings.cull_backfaces
    )
    height, width = settings.image_size
    if num_meshes == 0 or faces_per_mesh == 0:
        return screen.new_zeros(num_meshes, height, width)
    flat = _SoftSilhouetteFunction.apply(screen, valid, faces_per_mesh, settings)
    return flat.view(num_meshes, height, width)


def soft_silhouette_dense(
    verts: Tensor, faces: Tensor, K: Tensor, settings: SoftSilhouetteSettings
) -> Tensor:
    """Exact dense reference of :func:`soft_silhouette`: every pixel against every face, plain autograd.

    Builds ``(3, H, W, N * F)`` temporaries: for tests and benchmarks on small inputs only.
    ``cull_eps`` is ignored (no distance culling); invalid faces are culled as in
    :func:`soft_silhouette`.
    """
    screen, valid, num_meshes, faces_per_mesh = _screen_triangles(
        verts, faces, K, settings.near, settings.cull_backfaces
    )
    height, width = settings.image_size
    if num_meshes == 0 or faces_per_mesh == 0:
        return verts.new_zeros(num_meshes, height, width)
    tables = tuple(tab.view(3, 1, 1, -1) for tab in _edge_tables(screen))
    cols = torch.arange(width, dtype=screen.dtype, device=screen.device).view(-1, 1)
    rows = torch.arange(height, dtype=screen.dtype, device=screen.device).view(-1, 1, 1)
    d2, cmin = _nearest_edge(cols, rows, tables, details=False)  # (H, W, N * F)
    x = torch.copysign(d2, cmin) / settings.sigma
    log_keep = torch.where(valid, -tnf.softplus(x), x.new_zeros(()))
    log_keep = log_keep.view(height, width, num_meshes, faces_per_mesh).sum(-1)
    return -torch.expm1(log_keep).permute(2, 0, 1)
