# ruff: noqa: E501
"""realdel.py MAIN_SRC MERGED_SRC (session 27 shadow41's script, labels for session 28) RUN OUT_DIR: the real Virtual KITTI frame of tests/data (README's *Edit your own
image* boxes), each car deleted with ``sdn3d-edit`` (the user's own command, proposals=boxes, default photo
appearance) by main's code tree and by the branch's, weights RUN (w0: /tmp/s21data/demo/out); writes
OUT_DIR/real_deletes.png: per car a row, crops around the car (2x), panels titled: the input, main's delete, the
branch's delete, the pixels where they differ (white: branch lighter, magenta: darker, grey: same). Run with
OMP_NUM_THREADS=1; each code tree's src goes on PYTHONPATH per call."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402
from PIL import Image  # noqa: E402

BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]


def main() -> int:
    codes = {"main 5c8b4a43": Path(sys.argv[1]), "merged fa9f1f42": Path(sys.argv[2])}
    run, out = sys.argv[3], Path(sys.argv[4])
    out.mkdir(parents=True, exist_ok=True)
    frame = codes["main 5c8b4a43"] / "tests" / "data" / "0006_30-deg-right_00043.png"
    original = np.asarray(Image.open(frame).convert("RGB"))
    fig, axes = plt.subplots(2, 4, figsize=(20, 6.5), squeeze=False)
    for row, (iid, box) in zip(axes, zip((12001, 12002), BOXES, strict=True), strict=True):
        x0, y0, x1, y1 = box["box"]
        crop = (slice(max(0, y0 - 60), min(375, y1 + 60)), slice(max(0, x0 - 60), min(1242, x1 + 100)))
        spec = out / f"spec_{iid}.yaml"
        spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "delete", "id": iid}]}))
        got = {}
        for name, code in codes.items():
            target = out / f"{name.split()[0]}_{iid}"
            env = dict(os.environ, PYTHONPATH=str(code / "src"), OMP_NUM_THREADS="1")
            subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", f"input.image={frame}", f"run={run}",
                            "proposals=boxes", f"edits={spec}", f"output_dir={target}"], check=True, cwd=code,
                           stdout=subprocess.DEVNULL, env=env)
            got[name] = np.asarray(Image.open(target / "edited.png").convert("RGB"))
        diff = got["merged fa9f1f42"].astype(float).mean(2) - got["main 5c8b4a43"].astype(float).mean(2)
        vis = np.full(diff.shape + (3,), 0.5)
        vis[diff > 1] = (1.0, 1.0, 1.0)
        vis[diff < -1] = (1.0, 0.0, 1.0)
        panels = [(f"car {iid}: input", original), (f"car {iid} deleted: main 5c8b4a43", got["main 5c8b4a43"]),
                  (f"car {iid} deleted: merged (faint_light 0.98)", got["merged fa9f1f42"]),
                  (f"merged vs main: lighter (white) / darker (magenta), {int((np.abs(diff) > 1).sum())} px", vis)]
        for ax, (title, img) in zip(row, panels, strict=True):
            ax.imshow(img[crop], interpolation="nearest")
            ax.set_title(title, fontsize=10)
            ax.axis("off")
    fig.suptitle("Real Virtual KITTI frame (tests/data), sdn3d-edit proposals=boxes, delete, weights of session 28's demo run",
                 fontsize=12)
    fig.tight_layout()
    fig.savefig(out / "real_deletes.png", dpi=60)
    print(out / "real_deletes.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
