"""spy_pose.py SPY.json POSE_TABLE_ARGS...: benchmarks/pose_table.py (of the code on the path, run from its tree) with
a spy on the fit's choice (``sdn3d.geometric.fit.choose_again``): per fitted object, every fine hypothesis' template,
yaw, size, loss, belief and border test, and the winner; and on the truth's sizes (an oracle, only to score).
Run with ``--rows gt_fit`` only: then each frame makes one fit call whose
objects are the row's objects in order, so the records line up with the pose table's ``gt_fit`` objects (score
with choices.py). Run as pose.sh does (cd CODE; PYTHONPATH=CODE/src:CODE)."""
# ruff: noqa: E402
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import pose_table as pt

import sdn3d.geometric.fit as gf

RECORDS: list[dict] = []
TRUTH: dict[str, dict] = {}
_choose_again = gf.choose_again
_scene_from_frame = pt.scene_from_frame


def spy_truth(record, size):
    scene = _scene_from_frame(record, size)
    o = scene.objects
    TRUTH[record.key] = {str(int(i)): [round(v, 3) for v in d] for i, d in zip(o.instance_id.tolist(), o.dims.tolist(),
                                                                              strict=True)}
    return scene


def spy(choice, yaw_belief=None):
    result = _choose_again(choice, yaw_belief)
    ry = choice.values["ry"]
    belief = (yaw_belief(ry).float() if yaw_belief is not None else None)
    for i in range(choice.loss.shape[0]):
        RECORDS.append({"template": choice.template[i].tolist(), "loss": [round(v, 6) for v in choice.loss[i].tolist()],
                        "ry": [round(v, 4) for v in ry[i].tolist()],
                        "dims": [[round(v, 3) for v in d] for d in choice.values["dims"][i].tolist()],
                        "belief": None if belief is None else [round(v, 4) for v in belief[i].tolist()],
                        "start_ry": round(float(choice.ry0[i]), 4),
                        "start_dims": [round(v, 3) for v in choice.dims0[i].tolist()],
                        "inward": choice.inward[i].tolist(), "won": int(result.hypothesis[i]),
                        "fitted": bool(result.fitted[i]),
                        "template_won": int(result.template[i])})
    return result


if __name__ == "__main__":
    out = sys.argv[1]
    gf.choose_again = spy
    pt.scene_from_frame = spy_truth
    pt.main(sys.argv[2:])
    Path(out).write_text(json.dumps({"records": RECORDS, "truth_dims": TRUTH}))
