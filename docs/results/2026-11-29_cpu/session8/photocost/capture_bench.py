# ruff: noqa: E402, E501, E701, E702
"""capture_bench.py OUT_DIR BENCH_ARGS...: runs ``sdn3d.cli.bench`` with every call of the photo appearance's
render_photo saved (its arguments, torch.save, OUT_DIR/NNNN.pt) so that replay_photo.py can redraw them with another
code and compare the pictures bit for bit (the scenes come from the bench's own de-rendering)."""
import sys
from pathlib import Path

import torch

import sdn3d.editing.appearance as appearance

out = Path(sys.argv[1]); out.mkdir(parents=True, exist_ok=True)
real = appearance.render_photo
count = [len(list(out.glob("*.pt")))]


def capture(original, transform, scene, edited, bank=None, settings=None, recolor=None, generated=None, source=None):
    torch.save({"original": original, "transform": transform, "scene": scene, "edited": edited,
                "settings": settings, "recolor": recolor, "generated": generated}, out / f"{count[0]:04d}.pt")
    count[0] += 1
    return real(original, transform, scene, edited, bank, settings, recolor, generated, source)


appearance.render_photo = capture
from sdn3d.cli.bench import main

sys.exit(main(sys.argv[2:]))
