"""redraw.py PROBE_DIR OUT_DIR [photo_key=value ...] (speck's, session 21; PROBE_DIR: /tmp/s21data/speck/real_main):
the real frame's edits that probe.py de-rendered and resolved
(PROBE_DIR/scenes.pt) drawn again by render_photo with the code tree's conf/edit.yaml photo settings (run from
its root) and the overrides given (no
de-render: the same scene and edits); saves NAME.png and NAME.npz (edited picture, source map) per edit, and prints
each edit's draw time.

    cd CODE_TREE && PYTHONPATH=CODE_TREE/src OMP_NUM_THREADS=1 nice -n 5 python redraw.py PROBE_DIR OUT_DIR [...]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import torch
import yaml
from PIL import Image

from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import render_photo

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"


def main() -> int:
    probe, out = Path(sys.argv[1]), Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(1)
    photo = yaml.safe_load((Path.cwd() / "conf" / "edit.yaml").read_text())["photo"]
    for item in sys.argv[3:]:
        key, value = item.split("=", 1)
        photo[key] = yaml.safe_load(value)
    settings = PhotoSettings.from_mapping(photo)
    saved = torch.load(probe / "scenes.pt", weights_only=False)
    original = torch.from_numpy(np.array(Image.open(FRAME).convert("RGB"))).permute(2, 0, 1).contiguous()
    for name, edited in saved["edits"].items():
        t = time.perf_counter()
        res = render_photo(original, saved["frame"], saved["scene"], edited, settings=settings)
        dt = time.perf_counter() - t
        picture = res.image.permute(1, 2, 0).numpy()
        Image.fromarray(picture).save(out / f"{name}.png")
        np.savez_compressed(out / f"{name}.npz", edited=picture, source=res.source.numpy())
        print(name, f"{1000 * dt:.0f} ms", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
