"""variant.py VARIANT RAW.pt...: splits.py's census with main's 2-means split replaced by a variant (no code change
on the branch: the variant wraps panoptic._split_parts). VARIANT 'size': the threshold grows with the instance,
split_separation x max(1, sqrt(pixels / 1500)) (the brief's first idea: a near car's votes spread more);
'inbox': a split is kept only when each part's votes' mean lies inside its own pixels' box. Run from the worktree
root: PYTHONPATH=src python $D/scripts/variant.py size /tmp/s26data/frag40/raw/raw{11,13,31,33,35,37,39}.pt
(D: this folder)."""
import runpy
import sys

import torch

from sdn3d.semantic import panoptic

ORIGINAL = panoptic._split_parts
VARIANT = sys.argv.pop(1)
PIXELS: list[torch.Tensor] = []  # group_instances' pixel coordinates, captured for 'inbox'


def split_parts(target, slot, slots, min_area, separation, sure):
    high = ORIGINAL(target, slot, slots, min_area, separation, sure)
    count = torch.bincount(slot, minlength=slots).float()
    split = torch.bincount(slot, high.float(), slots) > 0
    if VARIANT == "size":
        # the slot's own separation, from the split at a tiny threshold: keep it when above the scaled threshold
        each = ORIGINAL(target, slot, slots, min_area, 1e-6, sure)
        scaled = separation * (count / 1500).sqrt().clamp_min(1)
        keep = torch.zeros_like(high)
        for s in split.nonzero().flatten().tolist():  # few splits per frame: a loop is fine in a record script
            m = slot == s
            t = target[m]
            hi = each[m]
            ax = torch.linalg.eigh((t - t.mean(0)).T @ (t - t.mean(0)) / m.sum()).eigenvectors[:, -1]
            p = t @ ax
            spread = ((p[hi].var(unbiased=False) + p[~hi].var(unbiased=False)) / 2).sqrt().clamp_min(0.5)
            if (p[hi].mean() - p[~hi].mean()).abs() / spread >= scaled[s]:
                keep[m] = hi
        return keep
    if VARIANT == "inbox":
        pix = PIXELS[-1]
        keep = high.clone()
        for s in split.nonzero().flatten().tolist():
            m = slot == s
            for part in (m & high, m & ~high):
                vote, lo, hi = target[part].mean(0), pix[part].amin(0) - 0.5, pix[part].amax(0) + 0.5
                if not bool(((vote >= lo) & (vote <= hi)).all()):
                    keep[m] = False
        return keep
    raise ValueError(f"VARIANT must be 'size' or 'inbox', got {VARIANT!r}")


def capture_nonzero(orig):
    def nonzero(x, *a, **k):
        out = orig(x, *a, **k)
        if k.get("as_tuple") and x.dim() == 3 and x.dtype == torch.bool:  # only the latest call is kept
            PIXELS[:] = [torch.stack([out[2].float(), out[1].float()], -1)]
        return out
    return nonzero


panoptic._split_parts = split_parts
if VARIANT == "inbox":
    torch.nonzero = capture_nonzero(torch.nonzero)
runpy.run_path(sys.argv[0].replace("variant.py", "splits.py"), run_name="__main__")
