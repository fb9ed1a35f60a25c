"""The real frame's two box cars (tests/data, README.md's boxes) listed by the code on PYTHONPATH: each fine
hypothesis of the fit (template, yaw, size, loss, belief) and the winner, to see what chooses the template.

    PYTHONPATH=CODE/src python real_probe.py RUN OUT_DIR
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import yaml

import sdn3d.geometric.fit as fit
from sdn3d.cli.edit import main as edit_main
from sdn3d.meshes.templates import TEMPLATE_NAMES

REPO = Path(__file__).resolve().parents[6]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
_original = fit.choose_again


def _recording(choice, yaw_belief=None):
    result = _original(choice, yaw_belief)
    belief = (yaw_belief(choice.values["ry"]).float() if yaw_belief is not None else None)
    for i in range(choice.loss.shape[0]):
        print(f"object {i}: winner {int(result.hypothesis[i])} {TEMPLATE_NAMES[int(result.template[i])]} "
              f"ry {math.degrees(float(result.ry[i])):.1f} dims {[round(v, 2) for v in result.dims[i].tolist()]}")
        for h in range(choice.loss.shape[1]):
            b = "" if belief is None else f" belief {float(belief[i, h]):+.2f}"
            print(f"  hyp {h}: {TEMPLATE_NAMES[int(choice.template[i, h])]:9s} loss {float(choice.loss[i, h]):.4f} "
                  f"ry {math.degrees(float(choice.values['ry'][i, h])):7.1f} "
                  f"dims {[round(v, 2) for v in choice.values['dims'][i, h].tolist()]}{b}")
    return result


def main() -> int:
    run, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    spec = out / "spec.yaml"
    spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": []}))
    fit.choose_again = _recording
    return edit_main([f"input.image={FRAME}", f"run={run}", "proposals=boxes", f"edits={spec}",
                      f"output_dir={out / 'listed'}", "threads=1"])


if __name__ == "__main__":
    sys.exit(main())
