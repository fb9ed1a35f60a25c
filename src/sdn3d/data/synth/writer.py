"""Virtual KITTI 1.3.1 on-disk format: paths, headers and the per-sequence writer.

Layout under the dataset root (exactly the official tarballs' trees)::

    vkitti_1.3.1_rgb/<world>/<variation>/%05d.png        8-bit RGB
    vkitti_1.3.1_scenegt/<world>/<variation>/%05d.png    8-bit RGB colour-coded classes / instances
    vkitti_1.3.1_scenegt/<world>_<variation>_scenegt_rgb_encoding.txt
    vkitti_1.3.1_depthgt/<world>/<variation>/%05d.png    16-bit grey, z-depth in centimetres
    vkitti_1.3.1_motgt/<world>_<variation>.txt
    vkitti_1.3.1_extrinsicsgt/<world>_<variation>.txt

motgt conventions (as Virtual KITTI 1.3.1): ``l t r b`` are the inclusive pixel bounds of the
object's *visible* pixels; ``w3d h3d l3d`` in that order (the library's dims are (l, h, w));
``x3d y3d z3d`` the bottom-face centre in the camera frame; ``alpha = wrap(ry - atan2(x3d, z3d))``;
``truncr`` as in ``stats.py``; ``occupr`` = visible pixels / the 2D box's pixel count ``(r - l + 1) (b - t + 1)``,
as in the real files (an unoccluded car reads about 0.8: its silhouette does not fill its box); ``rx = rz = 0``.
The KITTI-like flags are derived: ``truncated`` = 0 if truncr < 0.05, 1 if truncr < 0.5, else 2; ``occluded``
from the true visible fraction ``f`` = visible / unoccluded pixels (``stats.py``; not written, the generator
alone knows it): 0 if f >= 0.95, 1 if f >= 0.4, else 2; ``label`` is ``DontCare`` when either flag is 2 or
the 2D box is under 25 px tall at 375 rows (the real files' rules; ``orig_label`` keeps Car / Van).
Objects with no visible pixel are not listed. Depth is clipped at 655.35 m; empty (sky) pixels are 65535.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.data.synth.classes import CLASS_COLORS, CLASS_ID, CLASS_NAMES, instance_colors

__all__ = [
    "MOTGT_HEADER",
    "EXTRINSICS_HEADER",
    "ENCODING_HEADER",
    "frame_path",
    "table_path",
    "encoding_path",
    "depth_to_png",
    "png_bytes",
    "encode_scenegt",
    "truncation_flag",
    "occlusion_flag",
    "SequenceWriter",
    "write_staged",
]

MOTGT_HEADER = (
    "frame tid label truncated occluded alpha l t r b w3d h3d l3d x3d y3d z3d ry rx rz "
    "truncr occupr orig_label moving model color"
)
# Worded as the published Virtual KITTI 1.3.1 files word it (the readers check only the first 13 words).
EXTRINSICS_HEADER = "frame r1,1 r1,2 r1,3 t1 r2,1 r2,2 r2,3 t2 r3,1 r3,2 r3,3 t3 0 0.1 0.2 1"
ENCODING_HEADER = "Category(:id) r g b"

_DIRS = {
    "rgb": "vkitti_1.3.1_rgb",
    "scenegt": "vkitti_1.3.1_scenegt",
    "depthgt": "vkitti_1.3.1_depthgt",
    "motgt": "vkitti_1.3.1_motgt",
    "extrinsicsgt": "vkitti_1.3.1_extrinsicsgt",
}


def frame_path(root: Path, kind: str, world: str, variation: str, frame: int) -> Path:
    """``<root>/vkitti_1.3.1_<kind>/<world>/<variation>/%05d.png`` for kind rgb, scenegt, depthgt."""
    if kind not in ("rgb", "scenegt", "depthgt"):
        raise ValueError(f"kind must be rgb, scenegt or depthgt, got {kind!r}")
    return Path(root) / _DIRS[kind] / world / variation / f"{frame:05d}.png"


def table_path(root: Path, kind: str, world: str, variation: str) -> Path:
    """``<root>/vkitti_1.3.1_<kind>/<world>_<variation>.txt`` for kind motgt, extrinsicsgt."""
    if kind not in ("motgt", "extrinsicsgt"):
        raise ValueError(f"kind must be motgt or extrinsicsgt, got {kind!r}")
    return Path(root) / _DIRS[kind] / f"{world}_{variation}.txt"


def encoding_path(root: Path, world: str, variation: str) -> Path:
    return Path(root) / _DIRS["scenegt"] / f"{world}_{variation}_scenegt_rgb_encoding.txt"


def write_staged(path: Path, data: bytes | str) -> None:
    """Write ``data`` to ``path`` in the generator's staging tree, plainly: no temporary file, no fsync.

    The tree is :func:`sdn3d.io.staged_directory`'s temporary directory, which becomes the dataset only once
    it is complete (and is removed if the run fails), so each file need not be atomic on its own; and
    :func:`~sdn3d.data.synth.generate.generate_dataset` flushes the whole tree to disk once before the swap.
    A temporary file, rename and fsync per file cost about 30 ms per frame (3 PNGs) on the project machine.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)


def png_bytes(array: np.ndarray) -> bytes:
    """PNG encoding of a ``(H, W, 3)`` uint8 or ``(H, W)`` uint16 array with fixed options.

    zlib level 1: about 3x faster than Pillow's default level 6 for 20% larger files (PNG
    encoding was a fifth of the generator's time). Fixed options and no metadata, so the same
    array always gives the same bytes.
    """
    array = np.ascontiguousarray(array)
    if not (array.dtype == np.uint8 and array.ndim == 3) and not (array.dtype == np.uint16 and array.ndim == 2):
        raise ValueError(f"png_bytes: expected (H, W, 3) uint8 or (H, W) uint16, got {array.dtype} {array.shape}")
    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, format="PNG", compress_level=1)
    return buffer.getvalue()


def depth_to_png(depth: np.ndarray) -> np.ndarray:
    """``(H, W)`` metres (inf = empty) -> uint16 centimetres, clipped at 65535 (655.35 m)."""
    cm = np.where(np.isfinite(depth), np.round(depth.astype(np.float64) * 100.0), 65535.0)
    return np.clip(cm, 0, 65535).astype(np.uint16)


_STATIC_LUT = np.zeros((len(CLASS_NAMES), 3), dtype=np.uint8)
for _name, _rgb in CLASS_COLORS.items():
    _STATIC_LUT[CLASS_ID[_name]] = _rgb


def encode_scenegt(class_map: np.ndarray, instance: np.ndarray, object_colors: np.ndarray) -> np.ndarray:
    """Colour-coded scene ground truth ``(H, W, 3)`` uint8.

    Args:
        class_map: ``(H, W)`` class ids.
        instance: ``(H, W)`` object index (-1 none).
        object_colors: ``(N, 3)`` uint8 colour of each object of the frame.
    """
    out = _STATIC_LUT[class_map]
    mask = instance >= 0
    if mask.any():
        out[mask] = object_colors[instance[mask]]
    return out


def truncation_flag(truncr: np.ndarray) -> np.ndarray:
    return np.where(truncr < 0.05, 0, np.where(truncr < 0.5, 1, 2))


def occlusion_flag(visible_fraction: np.ndarray) -> np.ndarray:
    """KITTI-like ``occluded`` flag from the share of the object's in-frame pixels that are visible."""
    return np.where(visible_fraction >= 0.95, 0, np.where(visible_fraction >= 0.4, 1, 2))


#: Real motgt rows are DontCare when their 2D box is under 25 px tall at Virtual KITTI's 375 rows.
MIN_BOX_HEIGHT_375 = 25


def _too_short(top: int, bottom: int, image_height: int) -> bool:
    """Whether an inclusive box ``top..bottom`` is under :data:`MIN_BOX_HEIGHT_375` px tall at 375 rows."""
    return (bottom - top + 1) * 375.0 / image_height < MIN_BOX_HEIGHT_375


def _wrap(angle: np.ndarray) -> np.ndarray:
    return np.remainder(angle + math.pi, 2 * math.pi) - math.pi


@dataclass
class SequenceWriter:
    """Writes one ``<world>/<variation>`` sequence: per-frame PNGs at once, text tables at :meth:`close`.

    Attributes:
        root: dataset root: the staging tree of :func:`~sdn3d.data.synth.generate.generate_dataset`, whose
            files are written plainly (:func:`write_staged`).
        world, variation: sequence names.
        tids, categories: every track id of the world and its category (Car / Van), for the
            instance colours (fixed per world by ``color_seed``) and the encoding file.
    """

    root: Path
    world: str
    variation: str
    tids: np.ndarray
    categories: list[str]
    color_seed: int
    _motgt: list[str] = field(default_factory=list)
    _extrinsics: list[str] = field(default_factory=list)
    _seen: set[int] = field(default_factory=set)

    def __post_init__(self) -> None:
        self.colors = instance_colors(self.tids, self.color_seed)

    def write_frame(
        self,
        frame: int,
        rgb: np.ndarray,
        class_map: np.ndarray,
        instance: np.ndarray,
        depth: np.ndarray,
        world_to_cam: np.ndarray,
        annotations: dict[str, np.ndarray],
        encoded: dict[tuple[str, int], bytes] | None = None,
    ) -> None:
        """Write the three PNGs of ``frame`` and buffer its motgt and extrinsics rows.

        Args:
            rgb, class_map, instance, depth: the rendered maps (``instance`` indexes the frame's
                objects, whose track ids are ``annotations['tid']``).
            world_to_cam: ``(4, 4)``.
            annotations: per-object arrays ``tid, dims (N, 3) = (l, h, w), bottom (N, 3), ry,
                box (N, 4), truncr, occupr (visible / box area), visible_fraction (visible / unoccluded),
                visible, moving, model, color, category``.
            encoded: the scenegt and depth PNGs of this frame's maps, shared by the writers of variations
                that render the same geometry (``generate.generate_sequences``): filled by the first writer,
                reused by the others (keyed by kind and colour seed). None: encode here.
        """
        encoded = {} if encoded is None else encoded
        write_staged(frame_path(self.root, "rgb", self.world, self.variation, frame), png_bytes(rgb))
        if ("scenegt", self.color_seed) not in encoded:
            tid = np.asarray(annotations["tid"], dtype=np.int64)
            row_of_tid = {int(t): i for i, t in enumerate(self.tids.tolist())}
            colors = self.colors[[row_of_tid[int(t)] for t in tid]] if len(tid) else np.zeros((0, 3), np.uint8)
            encoded["scenegt", self.color_seed] = png_bytes(encode_scenegt(class_map, instance, colors))
        if ("depthgt", 0) not in encoded:
            encoded["depthgt", 0] = png_bytes(depth_to_png(depth))
        write_staged(frame_path(self.root, "scenegt", self.world, self.variation, frame),
                     encoded["scenegt", self.color_seed])
        write_staged(frame_path(self.root, "depthgt", self.world, self.variation, frame), encoded["depthgt", 0])
        values = " ".join(f"{v:.9f}" for v in np.asarray(world_to_cam, dtype=np.float64)[:3].reshape(-1))
        self._extrinsics.append(f"{frame} {values} 0 0 0 1")
        self._motgt += self._motgt_rows(frame, annotations, int(class_map.shape[0]))

    def _motgt_rows(self, frame: int, a: dict[str, np.ndarray], image_height: int) -> list[str]:
        rows = []
        truncated = truncation_flag(a["truncr"])
        occluded = occlusion_flag(a["visible_fraction"])
        for i in np.argsort(a["tid"], kind="stable"):
            if a["visible"][i] <= 0:
                continue
            self._seen.add(int(a["tid"][i]))
            l3d, h3d, w3d = (float(v) for v in a["dims"][i])
            x, y, z = (float(v) for v in a["bottom"][i])
            ry = float(_wrap(np.asarray(a["ry"][i])))
            alpha = float(_wrap(np.asarray(ry - math.atan2(x, z))))
            category = a["category"][i]
            left, top, right, bottom = (int(v) for v in a["box"][i])
            label = "DontCare" if truncated[i] == 2 or occluded[i] == 2 or _too_short(top, bottom, image_height) \
                else category
            rows.append(
                f"{frame} {int(a['tid'][i])} {label} {int(truncated[i])} {int(occluded[i])} {alpha:.6f} "
                f"{left} {top} {right} {bottom} {w3d:.6f} {h3d:.6f} {l3d:.6f} {x:.6f} {y:.6f} {z:.6f} "
                f"{ry:.6f} 0.000000 0.000000 {float(a['truncr'][i]):.6f} {float(a['occupr'][i]):.6f} "
                f"{category} {int(bool(a['moving'][i]))} {a['model'][i]} {a['color'][i]}"
            )
        return rows

    def close(self) -> None:
        """Write motgt, extrinsics and the scenegt colour encoding (tracks seen in some frame)."""
        write_staged(
            table_path(self.root, "motgt", self.world, self.variation),
            "\n".join([MOTGT_HEADER, *self._motgt]) + "\n",
        )
        write_staged(
            table_path(self.root, "extrinsicsgt", self.world, self.variation),
            "\n".join([EXTRINSICS_HEADER, *self._extrinsics]) + "\n",
        )
        lines = [ENCODING_HEADER] + [f"{name} {r} {g} {b}" for name, (r, g, b) in CLASS_COLORS.items()]
        for i, (t, category) in enumerate(zip(self.tids.tolist(), self.categories, strict=True)):
            if t in self._seen:
                r, g, b = (int(v) for v in self.colors[i])
                lines.append(f"{category}:{t} {r} {g} {b}")
        write_staged(encoding_path(self.root, self.world, self.variation), "\n".join(lines) + "\n")
