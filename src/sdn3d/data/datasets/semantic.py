"""Semantic branch dataset: one item per frame, image and label maps at the working size."""

from __future__ import annotations

from collections.abc import Sequence

from torch import Tensor
from torch.utils.data import Dataset

from sdn3d.data.errors import SkipLog
from sdn3d.data.frames import intrinsics_vector, load_frame
from sdn3d.data.records import FrameRecord
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.labels import SemanticClass, class_list

__all__ = ["SemanticDataset"]


class SemanticDataset(Dataset):
    """Frames for the semantic branch (DRN).

    Item (``H, W`` = working size)::

        image       (3, H, W) float32 in [0, 1]
        label       (H, W) int64 class index, 255 = ignore (IGNORE_INDEX)
        instance    (H, W) int64 class_id * 1000 + k, 0 = no instance
        intrinsics  (4,) float32 fx, fy, cx, cy at the working size
        key         str, FrameRecord.key

    Args:
        records: frames (all of one dataset kind).
        image_size: working size ``(W, H)``.
        classes: class list for logging; default from the records' dataset.
        cache_items: keep every frame's maps after its first read (items are deterministic), so that later epochs
            do not read and decode its files again; items are the same either way (copies of the kept tensors).
            At 312x96 a frame keeps ~0.6 MB (labels and ids as int32), at 1242x375 ~9 MB. Each loader worker
            keeps its own.
    """

    def __init__(
        self,
        records: Sequence[FrameRecord],
        image_size: tuple[int, int],
        classes: Sequence[SemanticClass] | None = None,
        cache_items: bool = False,
    ) -> None:
        self.records = list(records)
        self.image_size = (int(image_size[0]), int(image_size[1]))
        self._items: dict[int, tuple[Tensor, Tensor, Tensor, Tensor]] | None = {} if cache_items else None
        kinds = {r.dataset for r in self.records}
        if len(kinds) > 1:
            raise ValueError(f"records must all come from one dataset kind, got {sorted(kinds)}")
        if classes is None:
            classes = class_list(kinds.pop()) if kinds else ()
        self.classes: tuple[SemanticClass, ...] = tuple(classes)

    @classmethod
    def from_source(cls, source: SourceConfig, part: str, skip: SkipLog | None = None,
                    cache_items: bool = False) -> SemanticDataset:
        """The ``part`` (train / val / test) of ``source`` at its working size; ``skip`` as in
        :func:`~sdn3d.data.sources.load_split` (the skip policy)."""
        return cls(load_split(source, part, skip), source.image_size, source.class_list, cache_items)

    @property
    def class_names(self) -> list[str]:
        return [c.name for c in self.classes]

    def __len__(self) -> int:
        return len(self.records)

    def __getitem__(self, index: int) -> dict[str, Tensor | str]:
        record = self.records[index]
        cached = self._items.get(index) if self._items is not None else None
        if cached is None:
            frame = load_frame(record, self.image_size, semantic=True, instances=True)
            image, label, instance = frame.image, frame.semantic, frame.instances
            intrinsics = intrinsics_vector(frame.intrinsics)
            if self._items is not None:  # labels and ids as int32: half the memory
                self._items[index] = (image.clone(), label.int(), instance.int(), intrinsics.clone())
        else:  # copies: the caller may change its item in place
            image, intrinsics = cached[0].clone(), cached[3].clone()
            label, instance = cached[1].long(), cached[2].long()
        return {
            "image": image,
            "label": label,
            "instance": instance,
            "intrinsics": intrinsics,
            "key": record.key,
        }
