"""real_delete.py RUN OUT.npz: the real Virtual KITTI frame of tests/data (1242x375) de-rendered as ``sdn3d-edit``
does with the README's two boxes (``proposals=boxes``, the weights of RUN), then each car deleted by the 2D paste
baseline (``baseline_photo``, default photo settings: ``fill='rays'``) at the working size, with whichever code is on
PYTHONPATH. Writes OUT.npz: ``source`` (h, w, 3) uint8 working picture, ``car0`` / ``car1`` the two deletes, ``ids``
the composed instance map, ``principal`` the working camera's (cx, cy). Run once per code:
cd /tmp/s22data/base2d/main_9b7 && PYTHONPATH=src OMP_NUM_THREADS=1 /work/main/.venv/bin/python real_delete.py \
    /tmp/s21data/demo/out /tmp/s22data/base2d/real_main.npz   (and the same from the branch's tree)
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import torch
import yaml

from sdn3d.cli import edit as cli
from sdn3d.cli._config import compose_config
from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.editing.session import EditSession
from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
from sdn3d.evaluation.baselines import baseline_photo
from sdn3d.scene.maps import compose_instances

FRAME = Path("/work/wt/base2d/tests/data/0006_30-deg-right_00043.png")
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]


def main(run: str, out: str) -> None:
    torch.set_num_threads(1)
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "spec.yaml"
        spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "delete", "id": 12001}]}))
        cfg = compose_config([f"input.image={FRAME}", f"run={run}", "proposals=boxes", f"edits={spec}",
                              f"output_dir={tmp}/out", "threads=1"], "edit")
        cli.check_settings(cfg)
        compose = compose_settings(cfg)
        appearance, photo = appearance_settings(cfg)
        _, edit_spec, _, (inp, record) = cli._read_inputs(cfg)
        checkpoints = cli.resolve_checkpoints(cfg, record)
        models, code_bank = cli.load_models(cfg, checkpoints)
        settings = session_settings(cfg, checkpoints, compose, appearance, photo)
        derendered = EditSession(models, code_bank, settings).derender(inp, edit_spec)
    scene, image = derendered.scene, inp.image.float()
    ids = compose_instances(scene).cpu()
    pictures = {}
    for car, iid in enumerate((12001, 12002)):
        ys, xs = (ids == iid).nonzero(as_tuple=True)
        at = (float(xs.float().mean()), float(ys.float().mean()))
        picture = baseline_photo(image, scene, [BenchmarkOperation.delete(at)], frame_size=None)
        pictures[f"car{car}"] = (picture.clamp(0, 1) * 255).round().byte().permute(1, 2, 0).numpy()
    tmp_out = f"{out}.tmp.npz"
    np.savez(tmp_out, source=(image.clamp(0, 1) * 255).round().byte().permute(1, 2, 0).numpy(), ids=ids.numpy(),
             principal=np.array([scene.intrinsics.cx, scene.intrinsics.cy]), **pictures)
    os.replace(tmp_out, out)
    print(out, tuple(image.shape), scene.intrinsics)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
