"""A bank of M meshes as padded tensors, indexed by mesh id in batched code."""

from __future__ import annotations

import functools
import hashlib
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import torch
from torch import Tensor

from sdn3d.io import atomic_write, cache_dir
from sdn3d.math3d.ffd import bernstein_basis
from sdn3d.meshes.parts import Part
from sdn3d.meshes.templates import TEMPLATE_NAMES, normalize_to_unit_box, template_arrays, template_parts
from sdn3d.meshes.vehicle_family import FAMILY_NAMES, VEHICLE_SHAPE_NAMES, family_arrays, family_parts

if TYPE_CHECKING:  # imported where a Trimesh is read or built: the edit path never loads trimesh
    import trimesh

__all__ = ["MeshBank", "default_bank"]


class MeshBank:
    """M meshes padded to common sizes so that a batch of mesh ids gathers with one index.

    Attributes:
        verts: ``(M, Vmax, 3)`` float32 canonical vertices; padding vertices are zero.
        faces: ``(M, Fmax, 3)`` long; padding faces are ``(0, 0, 0)``, degenerate (zero area), which
            the renderers cull. They refer to vertex 0, a real vertex, so every index is valid.
        num_verts: ``(M,)`` long, real vertex counts.
        num_faces: ``(M,)`` long, real face counts.
        face_mask: ``(M, Fmax)`` bool, True for real faces.
        ffd_basis: ``(M, Vmax, 64)`` float32 cubic Bernstein weights of the 4x4x4 FFD lattice
            (:func:`sdn3d.math3d.ffd.bernstein_basis`); rows of padding vertices are zero so
            that ``verts + ffd_basis @ phi`` keeps padding at zero.
        names: the M mesh names.
        face_parts: ``(M, Fmax)`` long :class:`~sdn3d.meshes.parts.Part` of every real face (the templates' and
            the family's from their loft; :attr:`Part.BODY <sdn3d.meshes.parts.Part.BODY>` on every face of a
            mesh given without labels, e.g. a ShapeNet one); ``-1`` on padding faces. Index it like ``faces``:
            the FFD moves vertices only, so a face keeps its part through any deformation.
    """

    def __init__(self, verts: Tensor, faces: Tensor, num_verts: Tensor, num_faces: Tensor,
                 names: Sequence[str], face_parts: Tensor | None = None) -> None:
        m = verts.shape[0]
        if verts.dim() != 3 or verts.shape[-1] != 3:
            raise ValueError(f"verts must have shape (M, Vmax, 3), got {tuple(verts.shape)}")
        if faces.dim() != 3 or faces.shape[0] != m or faces.shape[-1] != 3:
            raise ValueError(f"faces must have shape (M={m}, Fmax, 3), got {tuple(faces.shape)}")
        if num_verts.shape != (m,) or num_faces.shape != (m,):
            raise ValueError(f"num_verts and num_faces must have shape ({m},), got "
                             f"{tuple(num_verts.shape)} and {tuple(num_faces.shape)}")
        if len(names) != m:
            raise ValueError(f"names must have {m} entries, got {len(names)}")
        self.verts = verts.float()
        self.faces = faces.long()
        self.num_verts = num_verts.long()
        self.num_faces = num_faces.long()
        self.names = list(names)
        self.face_mask = torch.arange(self.faces.shape[1], device=faces.device) < self.num_faces[:, None]
        if face_parts is None:
            face_parts = torch.full(self.faces.shape[:2], int(Part.BODY), dtype=torch.long, device=faces.device)
        elif face_parts.shape != self.faces.shape[:2]:
            raise ValueError(f"face_parts must have shape {tuple(self.faces.shape[:2])}, got {tuple(face_parts.shape)}")
        self.face_parts = torch.where(self.face_mask, face_parts.long().to(faces.device), -1)
        vert_mask = torch.arange(self.verts.shape[1], device=verts.device) < self.num_verts[:, None]
        self.ffd_basis = bernstein_basis(self.verts) * vert_mask[..., None]

    # -- constructors -------------------------------------------------------------------------

    @classmethod
    def from_trimeshes(cls, meshes: Sequence[trimesh.Trimesh], names: Sequence[str]) -> MeshBank:
        """Pad ``meshes`` (taken as given: canonical frame, not re-normalised) into a bank (every face ``BODY``)."""
        return cls.from_arrays([m.vertices for m in meshes], [m.faces for m in meshes], names)

    @classmethod
    def from_arrays(cls, vertices: Sequence[np.ndarray], faces: Sequence[np.ndarray], names: Sequence[str],
                    parts: Sequence[np.ndarray] | None = None) -> MeshBank:
        """Pad meshes given as ``vertices[i] (V_i, 3)`` and ``faces[i] (F_i, 3)`` (canonical frame) into a bank;
        ``parts[i] (F_i,)``: each face's :class:`~sdn3d.meshes.parts.Part` (default: every face ``BODY``)."""
        if len(vertices) == 0:
            raise ValueError("meshes must not be empty")
        if len(names) != len(vertices) or len(faces) != len(vertices):
            raise ValueError(f"names and faces must have one entry per mesh ({len(vertices)}), got {len(names)} "
                             f"and {len(faces)}")
        if len(set(names)) != len(names):
            raise ValueError(f"names must be unique, got {list(names)}")
        vs = [np.asarray(v, dtype=np.float32) for v in vertices]
        fs = [np.asarray(f, dtype=np.int64) for f in faces]
        for name, v, f in zip(names, vs, fs, strict=True):
            if len(v) == 0 or len(f) == 0:
                raise ValueError(f"mesh {name!r} is empty ({len(v)} vertices, {len(f)} faces)")
            if not np.all(np.isfinite(v)):
                raise ValueError(f"mesh {name!r} has non-finite vertices")
            if f.min() < 0 or f.max() >= len(v):
                raise ValueError(f"mesh {name!r} has face indices outside [0, {len(v)})")
        m, vmax, fmax = len(vs), max(len(v) for v in vs), max(len(f) for f in fs)
        verts = np.zeros((m, vmax, 3), dtype=np.float32)
        faces = np.zeros((m, fmax, 3), dtype=np.int64)
        labels = np.full((m, fmax), int(Part.BODY), dtype=np.int64)
        if parts is not None and len(parts) != m:
            raise ValueError(f"parts must have one entry per mesh ({m}), got {len(parts)}")
        for i, (v, f) in enumerate(zip(vs, fs, strict=True)):
            verts[i, : len(v)] = v
            faces[i, : len(f)] = f
            if parts is not None:
                p = np.asarray(parts[i], dtype=np.int64)
                if p.shape != (len(f),) or (len(p) and not np.isin(p, [int(x) for x in Part]).all()):
                    raise ValueError(f"parts of mesh {names[i]!r} must be {len(f)} Part labels, got shape {p.shape}")
                labels[i, : len(f)] = p
        return cls(torch.from_numpy(verts), torch.from_numpy(faces),
                   torch.tensor([len(v) for v in vs]), torch.tensor([len(f) for f in fs]), names,
                   torch.from_numpy(labels))

    @classmethod
    def templates(cls) -> MeshBank:
        """The 8 procedural templates, mesh id = index in :data:`TEMPLATE_NAMES`."""
        return cls.from_arrays(*zip(*(template_arrays(n) for n in TEMPLATE_NAMES), strict=True), TEMPLATE_NAMES,
                               [template_parts(n) for n in TEMPLATE_NAMES])

    @classmethod
    def vehicle_shapes(cls) -> MeshBank:
        """Every vehicle shape: the 8 templates then the held-out family, mesh id = shape id
        (:data:`~sdn3d.meshes.vehicle_family.VEHICLE_SHAPE_NAMES`). The synthetic generator draws its
        held-out cars from it; the geometric branch never chooses from it."""
        arrays = [template_arrays(n) for n in TEMPLATE_NAMES] + [family_arrays(n) for n in FAMILY_NAMES]
        parts = [template_parts(n) for n in TEMPLATE_NAMES] + [family_parts(n) for n in FAMILY_NAMES]
        return cls.from_arrays(*zip(*arrays, strict=True), VEHICLE_SHAPE_NAMES, parts)

    @classmethod
    def from_directory(cls, path: str | Path, pattern: str = "**/model_normalized.obj",
                       max_faces: int | None = 4000) -> MeshBank:
        """ShapeNet OBJs under ``path`` (see :func:`load_mesh_directory`), sorted by name.

        ``max_faces`` bounds each mesh (vertex clustering) because every mesh is padded to the
        largest one; ``None`` keeps the full resolution.
        """
        from sdn3d.meshes.shapenet import load_mesh_directory

        loaded = load_mesh_directory(path, pattern=pattern, max_faces=max_faces)
        if not loaded:
            raise ValueError(f"no files matching {pattern!r} under {str(path)!r}")
        return cls.from_trimeshes([m for _, m in loaded], [n for n, _ in loaded])

    def simplified(self, max_faces: int) -> MeshBank:
        """The bank with each mesh cut to at most ``max_faces`` faces by vertex clustering
        (:func:`~sdn3d.meshes.shapenet.cluster_simplify`), then stretched back to the mesh's own bounds (clustering
        averages the extreme vertices inwards), same names and ids; each kept face keeps its part label (a face that
        clustering merges with others keeps the first one's). For searches where a coarse outline is enough:
        a silhouette a few dozen pixels across. Built once per ``max_faces`` and kept on the bank.

        The clustering (4 ms a template, 0.06 CPU s of every fitting process: issue 40) is also kept on disk, in
        :func:`sdn3d.io.cache_dir` ``("meshes")``, one file per bank and ``max_faces`` named by a hash of the bank's
        arrays, ``max_faces`` and the source of the modules that compute it (:func:`_simplified_key`): a later
        process reads the same arrays back instead. A file that cannot be read or is not a valid bank is computed
        and written again; where the folder cannot be written the bank is computed each time.

        >>> bank = MeshBank.templates()
        >>> coarse = bank.simplified(300)
        >>> int(coarse.num_faces.max()) <= 300, coarse.names == bank.names, coarse is bank.simplified(300)
        (True, True, True)
        """
        cache = self.__dict__.setdefault("_simplified", {})
        if max_faces not in cache:
            try:
                path = cache_dir("meshes") / f"simplified_{_simplified_key(self, max_faces)}.npz"
            except OSError:  # the modules' source unreadable (e.g. a zipped install): no file, computed each time
                path = None
            bank = None if path is None else _read_simplified(path, self.names)
            if bank is None:
                arrays = self._simplify(max_faces)
                bank = MeshBank.from_arrays(arrays[0], arrays[1], self.names, arrays[2])
                if path is not None:
                    _write_simplified(path, arrays)
            cache[max_faces] = bank.to(self.device)
        return cache[max_faces]

    def _simplify(self, max_faces: int) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
        """:meth:`simplified`'s arrays: per mesh ``(V', 3)`` float64 vertices, ``(F', 3)`` int64 faces and ``(F',)``
        int64 part labels."""
        from sdn3d.meshes.shapenet import cluster_simplify

        verts, faces, parts = [], [], []
        for i in range(len(self)):
            nv, nf = int(self.num_verts[i]), int(self.num_faces[i])
            full = self.verts[i, :nv].double().cpu().numpy()
            v, f, kept = cluster_simplify(full, self.faces[i, :nf].cpu().numpy(), max_faces, return_index=True)
            lo, hi = full.min(0), full.max(0)
            verts.append((normalize_to_unit_box(v) + 0.5) * (hi - lo) + lo)
            faces.append(np.asarray(f, dtype=np.int64))
            parts.append(self.face_parts[i, :nf].cpu().numpy()[kept].astype(np.int64))
        return verts, faces, parts

    # -- access -------------------------------------------------------------------------------

    def __len__(self) -> int:
        return self.verts.shape[0]

    @property
    def device(self) -> torch.device:
        return self.verts.device

    def index(self, name: str) -> int:
        """Mesh id of ``name``."""
        if name not in self.names:
            raise ValueError(f"name {name!r} is not in the bank; known: {self.names}")
        return self.names.index(name)

    def to(self, device: torch.device | str) -> MeshBank:
        """Move every tensor to ``device`` in place (like ``nn.Module.to``) and return ``self``."""
        for attr in ("verts", "faces", "num_verts", "num_faces", "face_mask", "face_parts", "ffd_basis"):
            setattr(self, attr, getattr(self, attr).to(device))
        return self

    def gather(self, mesh_ids: Tensor) -> tuple[Tensor, Tensor]:
        """Meshes of a batch of ids.

        Args:
            mesh_ids: ``(N,)`` integer mesh ids in ``[0, M)`` (any device; moved to the bank's).

        Returns:
            ``verts (N, Vmax, 3)`` and ``faces (N, Fmax, 3)``; index ``ffd_basis``, ``face_mask``,
            ``face_parts`` the same way for the rest.
        """
        if mesh_ids.dim() != 1 or mesh_ids.dtype.is_floating_point or mesh_ids.dtype == torch.bool:
            raise ValueError(f"mesh_ids must be a 1-D integer tensor, got {mesh_ids.dtype} "
                             f"{tuple(mesh_ids.shape)}")
        mesh_ids = mesh_ids.to(device=self.device, dtype=torch.long)
        if mesh_ids.numel() and (int(mesh_ids.min()) < 0 or int(mesh_ids.max()) >= len(self)):
            raise ValueError(f"mesh_ids must lie in [0, {len(self)}), got range "
                             f"[{int(mesh_ids.min())}, {int(mesh_ids.max())}]")
        return self.verts[mesh_ids], self.faces[mesh_ids]

    def to_trimesh(self, i: int, verts: Tensor | np.ndarray | None = None) -> trimesh.Trimesh:
        """Mesh ``i`` as a :class:`trimesh.Trimesh` (e.g. for glTF export).

        Args:
            i: mesh id.
            verts: optional ``(Vmax, 3)`` or ``(num_verts[i], 3)`` replacement vertices, e.g. the
                FFD-deformed ones; padding rows are dropped.
        """
        if not 0 <= i < len(self):
            raise ValueError(f"i must lie in [0, {len(self)}), got {i}")
        nv, nf = int(self.num_verts[i]), int(self.num_faces[i])
        if verts is None:
            verts = self.verts[i]
        if isinstance(verts, Tensor):
            verts = verts.detach().cpu().numpy()
        verts = np.asarray(verts)
        if verts.ndim != 2 or verts.shape[1] != 3 or verts.shape[0] not in (nv, self.verts.shape[1]):
            raise ValueError(f"verts must have shape ({nv}, 3) or ({self.verts.shape[1]}, 3), "
                             f"got {verts.shape}")
        faces = self.faces[i, :nf].cpu().numpy()
        import trimesh

        return trimesh.Trimesh(verts[:nv].astype(np.float64), faces, process=False)


@functools.cache
def default_bank() -> MeshBank:
    """The 8 procedural templates (built once per process; shared: read it, never move or change it in place)."""
    return MeshBank.templates()


#: The layout of :meth:`MeshBank.simplified`'s files (a change names every file anew).
_SIMPLIFIED_FORMAT = 1


def _simplified_key(bank: MeshBank, max_faces: int) -> str:
    """The name of ``bank.simplified(max_faces)``'s file: a hash of the format, ``max_faces``, the names, every array
    the clustering reads and the source of the modules that compute it (this one, ``shapenet``'s clustering and
    ``templates``' ``normalize_to_unit_box``), so a change to any of them makes another file."""
    import sdn3d.meshes.shapenet as shapenet
    import sdn3d.meshes.templates as templates

    digest = hashlib.sha256(f"{_SIMPLIFIED_FORMAT} {max_faces} {list(bank.names)!r}".encode())
    for module in (shapenet, templates):
        digest.update(Path(module.__file__).read_bytes())
    digest.update(Path(__file__).read_bytes())
    for array in (bank.verts, bank.faces, bank.num_verts, bank.num_faces, bank.face_parts):
        digest.update(array.detach().cpu().contiguous().numpy().tobytes())
    return digest.hexdigest()[:32]


def _read_simplified(path: Path, names: Sequence[str]) -> MeshBank | None:
    """The bank of :func:`_write_simplified`'s file, one mesh per name of ``names``, or None where the file is
    missing, unreadable, not of that layout or not a valid bank (a damaged file that still unpacks)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            verts, faces, parts = ([data[f"{kind}{i}"] for i in range(len(names))] for kind in ("v", "f", "p"))
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    for v, f, p in zip(verts, faces, parts, strict=True):
        if (v.dtype != np.float64 or v.ndim != 2 or v.shape[1:] != (3,) or f.dtype != np.int64 or f.ndim != 2
                or f.shape[1:] != (3,) or p.dtype != np.int64 or p.shape != f.shape[:1]):
            return None
    try:
        return MeshBank.from_arrays(verts, faces, names, parts)
    except ValueError:
        return None


def _write_simplified(path: Path, arrays: tuple[list[np.ndarray], ...]) -> None:
    """Store :meth:`MeshBank._simplify`'s arrays at ``path`` (atomically: a concurrent writer of the same name writes
    the same bytes); a folder that cannot be written keeps nothing."""
    named = {f"{kind}{i}": a for kind, lists in zip(("v", "f", "p"), arrays, strict=True) for i, a in enumerate(lists)}
    try:
        atomic_write(path, lambda handle: np.savez(handle, **named))
    except OSError:
        pass
