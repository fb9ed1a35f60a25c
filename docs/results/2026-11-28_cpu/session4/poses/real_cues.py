"""What the geometric branch and the lamp cue say about the real frame's two cars (issue 40), and what the fit chose.

    python docs/results/2026-11-28_cpu/session4/poses/real_cues.py RUN_DIR OUT_DIR [OVERRIDE ...]

Runs ``sdn3d-edit`` (listing only, the two boxes) in this process with a hook on the geometric predictor and the
fit's choice; prints per car the net's yaw, the lamp reading, the yaw after the lamps, the MultiBin belief, and the
fine hypotheses (yaw, loss, belief). The yaws the photo shows: both cars drive away, rear visible, front to the
left (local orientation: back views).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(REPO / "src"))

import sdn3d.geometric.fit as fitmod  # noqa: E402
from sdn3d.geometric.lamps import red_lamps  # noqa: E402
from sdn3d.geometric.model import ray_angle  # noqa: E402
from sdn3d.geometric.predict import GeometricPredictor  # noqa: E402

FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
SPEC = "objects:\n- box: [466, 203, 666, 333]\n  class: Car\n- box: [704, 194, 917, 305]\n  class: Car\nops: []\n"


def main() -> None:
    run, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    (out / "spec.yaml").write_text(SPEC)
    report: dict = {}
    orig_predict = GeometricPredictor.predict

    def predict(self, crop, mask, box, intrinsics, *a, **k):
        cue, self.lamp_cue = self.lamp_cue, None
        net = orig_predict(self, crop, mask, box, intrinsics, *a, **k)
        self.lamp_cue = cue
        res = orig_predict(self, crop, mask, box, intrinsics, *a, **k)
        present, usable, offset = red_lamps(crop * mask, mask, cue)
        import torch
        torch.save({"crop": crop * mask, "mask": mask, "box": box, "ray": ray_angle(box, intrinsics)}, out / "crops.pt")
        ray = ray_angle(box, intrinsics)
        report["branch"] = [
            {
                "net_ry_deg": round(math.degrees(float(net["ry"][i])), 1),
                "lamps_ry_deg": round(math.degrees(float(res["ry"][i])), 1),
                "ray_deg": round(math.degrees(float(ray[i])), 1),
                "red_lamps_present": bool(present[i]),
                "cue_usable": bool(usable[i]),
                "red_offset": round(float(offset[i]), 3),
                "bin_probs": [round(float(p), 3) for p in res["yaw_bins"][i].softmax(0)] if "yaw_bins" in res else None,
            }
            for i in range(len(box))
        ]
        return res

    GeometricPredictor.predict = predict
    orig_choose, orig_stage, last = fitmod._choose, fitmod._stage, {}

    def stage(*a, **k):
        values, loss = orig_stage(*a, **k)
        last["ry"], last["template"] = values["ry"], a[1]
        return values, loss

    def choose(loss, belief, reverse, settings):
        index = orig_choose(loss, belief, reverse, settings)
        n, h = loss.shape
        ry = last["ry"].view(n, h)
        report["fit"] = [
            {
                "chosen": int(index[i]),
                "hypotheses": [
                    {
                        "ry_deg": round(math.degrees(float(ry[i, j])), 1),
                        "loss": round(float(loss[i, j]), 4),
                        "belief": round(float(belief[i, j]), 3),
                        "reverse": round(float(reverse[i, j]), 3),
                        "template": int(last["template"].view(n, h)[i, j]),
                    }
                    for j in range(h)
                ],
            }
            for i in range(n)
        ]
        return index

    fitmod._stage, fitmod._choose = stage, choose
    from sdn3d.cli.edit import main as edit

    edit(
        [
            f"input.image={FRAME}",
            f"run={run}",
            "proposals=boxes",
            f"edits={out / 'spec.yaml'}",
            f"output_dir={out / 'listing'}",
            *sys.argv[3:],
        ]
    )
    listing = json.loads((out / "listing" / "objects.json").read_text())
    keys = ("id", "yaw_deg", "template", "fit_iou", "hypothesis")
    report["listed"] = [{k: o.get(k) for k in keys} for o in listing["objects"]]
    (out / "real_cues.json").write_text(json.dumps(report, indent=1))
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
