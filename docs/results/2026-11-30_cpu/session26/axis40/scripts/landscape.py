"""landscape.py OUT.json POSE_TABLE_ARGS...: benchmarks/pose_table.py (of the code on the path, run from its tree)
with a spy on the test-time fit that, after each fit, fits every object once more from the winner's template,
size, place and FFD at 18 yaws (the winner's yaw + -40..+40 degrees by 10, and each of those reversed), with the fit's
own fine stage (``fit._stage``, its objective and steps). OUT.json: per object (keyed by frame and the final yaw,
rounded as pose_table writes it) the starts, the yaws they ended at and their losses. With the truth (an oracle,
read only to score) this tells whether the objective prefers the off-axis fit or the search never started near the
axis. Run as diag.sh runs diag_pose.py (PYTHONPATH=CODE/src:CODE, cd CODE), e.g. with --rows gt_fit."""
# ruff: noqa: E402
import json
import math
import sys
from pathlib import Path

import torch

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import pose_table as pt

import sdn3d.geometric.fit as gf

OFFSETS = [math.radians(d) for d in range(-40, 41, 10)]
OUT: list[dict] = []
CUR = {"key": None}
_fit, _load = gf.fit_to_masks, pt.load_frame


def spy_load(record, *a, **k):
    CUR["key"] = record.key
    return _load(record, *a, **k)


def spy_fit(masks, *a, **k):
    result = _fit(masks, *a, **k)
    c = result.choice
    if c is None or not len(result.ry):
        return result
    n, hyps = c.loss.shape
    win = torch.stack([(c.values["ry"][i] - result.ry[i]).abs().argmin() for i in range(n)])
    everyone = torch.arange(n)
    offs = torch.tensor(OFFSETS + [o + math.pi for o in OFFSETS])
    s = len(offs)
    obj = everyone.repeat_interleave(s)
    start = {k: v[everyone, win][obj].clone() for k, v in c.values.items()}
    start["ry"] = gf._wrap(start["ry"] + offs.repeat(n))
    settings = c.settings
    bank = c.bank.simplified(settings.fine_faces) if settings.fine_faces else c.bank
    values, loss = gf._stage(bank, c.template[everyone, win][obj], start, c.dims0[obj], c.ry0[obj], c.mask[obj],
                             c.ign[obj], c.K[obj], settings.fine_size, settings.fine_steps, settings, with_ffd=True,
                             height=c.camera_height)
    for i in range(n):
        rows = slice(i * s, (i + 1) * s)
        OUT.append({"frame": CUR["key"], "ry": round(float(result.ry[i]), 4), "win": int(win[i]),
                    "win_loss": float(c.loss[i, win[i]]), "fitted": bool(result.fitted[i]),
                    "start": start["ry"][rows].tolist(), "end": values["ry"][rows].tolist(),
                    "loss": loss[rows].tolist()})
    return result


gf.fit_to_masks = spy_fit
pt.load_frame = spy_load
out = sys.argv[1]
pt.main(sys.argv[2:])
Path(out).write_text(json.dumps(OUT))
print(f"landscape: {len(OUT)} objects -> {out}", file=sys.stderr)
