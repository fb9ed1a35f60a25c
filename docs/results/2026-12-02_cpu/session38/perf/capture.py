# ruff: noqa: INP001, E501
"""capture.py SPEC OUT: pickle the photo stage's inputs of one sdn3d-edit run to OUT.pkl (bench.py reads
/tmp/s38photo/cap/SPEC.pkl)."""
import pickle
import sys

from sdn3d.cli import edit
from sdn3d.editing import appearance
from sdn3d.editing.photo.recolor import paints

spec, out = sys.argv[1], sys.argv[2]
orig = appearance.PhotoRenderer.draw


def draw(self, state, edited, ops=(), generated=None):
    with open(out + ".pkl", "wb") as fh:
        pickle.dump({"original": state.original, "frame": state.frame, "scene": state.scene, "edited": edited,
                     "bank": state.bank, "settings": self.settings, "recolor": paints(ops)}, fh)
    return orig(self, state, edited, ops, generated)


appearance.PhotoRenderer.draw = draw
edit.main([
    "input.image=tests/data/0006_30-deg-right_00043.png",
    f"edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/{spec}.yaml",
    "run=/tmp/w38/outputs/demo/runs", "proposals=boxes", "threads=1", f"output_dir={out}", "overwrite=true",
    "progress=false"])
