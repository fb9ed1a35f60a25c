# ruff: noqa: INP001, E501
"""edgeband.py SCRIPT ARGS...: runs SCRIPT (a benchmark script path, or -m MODULE) with the proposals' fit leaving out
of its silhouette loss a band of EDGE_PX pixels on both sides of every semantic proposal's outline (added to
derender's unsure_pixels; the masks keep their pixels). EDGE_PX=0: main as it is. A wrapper for tuning, session 37."""
import os
import runpy
import sys

import torch
import torch.nn.functional as F

import sdn3d.derender as dr

PX = int(os.environ.get("EDGE_PX", "0"))
_original = dr._objects_3d


def outline_band(masks: torch.Tensor, px: int) -> torch.Tensor:
    """``(H, W)`` bool: the pixels within ``px`` of any of ``masks (N, H, W)``'s outlines, inside or outside."""
    m = masks[:, None].float()
    grown = F.max_pool2d(m, 2 * px + 1, 1, px)
    shrunk = -F.max_pool2d(-m, 2 * px + 1, 1, px)
    return ((grown > 0) & ~(shrunk > 0)).any(0)[0]


def _patched(masks, ids, box_rows, image, intrinsics, source, gt, models, min_pixels, refine, photo, boxes, fit,
             class_names, unsure_pixels=None, earlier=None, same=None):
    if PX > 0 and source == "semantic" and fit is not None and len(masks):
        keep = torch.ones(len(masks), dtype=torch.bool)
        keep[box_rows] = False
        if bool(keep.any()):
            band = outline_band(masks[keep], PX)
            unsure_pixels = band if unsure_pixels is None else (unsure_pixels | band)
    return _original(masks, ids, box_rows, image, intrinsics, source, gt, models, min_pixels, refine, photo, boxes,
                     fit, class_names, unsure_pixels, earlier, same)


dr._objects_3d = _patched
if sys.argv[1] == "-m":
    sys.argv = sys.argv[2:]
    runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
else:
    sys.argv = sys.argv[1:]
    runpy.run_path(sys.argv[0], run_name="__main__")
