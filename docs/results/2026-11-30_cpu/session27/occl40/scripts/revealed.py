"""revealed.py OUT.json RUN_DIR [RUN_DIR...]: what happens to the revealed car of every occluder-removed entry of
Table 1 photo runs (session 11 semrain's dbench.py dumps, RUN_DIR.dump/NNNN.npz; ground truth used only to diagnose).

Per entry: the revealed car (the target's ground-truth instance with most pixels in the benchmark's 'all' region, not
the removed occluder), its pixels the source showed ('seen') and its pixels the target shows inside the region
('hidden': what the removal reveals); which proposal holds its seen pixels ('own': a proposal not picked for the
removal holds >= 30 % of them; 'merged': the removed proposal holds more of them than any other; 'missed': none holds
30 %); how 3D-SDN drew the hidden pixels (drawn car: any source code but input, fill, relit, in front; fill; kept
input) and 3D-SDN - 2D paste squared error split by those parts, as dB of the 2D paste's picture with 3D-SDN's pixels
of that part only (over the whole 'all' region); and the completion drawn outside the hidden pixels ('stray': drawn
in the region where the target does not show the revealed car). Run with /work/main/.venv/bin/python (numpy only).
"""
import json
import sys
from pathlib import Path

import numpy as np

INPUT, FILL, RELIT, IN_FRONT = 0, 4, 9, 10  # sdn3d.editing.photo.settings.SOURCE_NAMES


def one(path: Path) -> dict | None:
    d = np.load(path)
    if str(d["kind"])[:4] != "occl":
        return None
    t, s, b = (d[k].astype(np.float64) / 255 for k in ("target", "sdn", "d2"))
    reg, code, prop, src, tgt = d["region"], d["code"], d["proposals"], d["src_inst"], d["tgt_inst"]
    gt_ids = set(int(i) for i in np.atleast_1d(d["gt_ids"]))
    ids, counts = np.unique(tgt[reg], return_counts=True)
    cand = [(c, i) for i, c in zip(ids.tolist(), counts.tolist(), strict=True) if i > 0 and i not in gt_ids]
    e3, e2 = ((s - t) ** 2).sum(-1), ((b - t) ** 2).sum(-1)
    sse2 = max(float(e2[reg].sum()), 1e-9)

    def db(m: np.ndarray) -> float:
        return float(-10 * np.log10(max(sse2 + float((e3 - e2)[reg & m].sum()), 1e-9) / sse2))

    out = {"entry": path.stem, "n_reg": int(reg.sum()), "d": db(np.ones_like(reg))}
    if not cand:
        out["status"] = "no revealed car"
        return out
    rid = max(cand)[1]
    seen = src == rid
    hidden = (tgt == rid) & reg & ~seen
    picks = set(int(i) for i in np.atleast_1d(d["picks"]))
    pid, pcount = np.unique(prop[seen], return_counts=True)
    share = {int(i): int(c) / max(int(seen.sum()), 1)
             for i, c in zip(pid.tolist(), pcount.tolist(), strict=True) if i > 0}
    own = {i: v for i, v in share.items() if i not in picks}
    best_own = max(own.values(), default=0.0)
    in_pick = sum(v for i, v in share.items() if i in picks)
    status = "own" if best_own >= 0.3 else ("merged" if in_pick >= 0.3 else "missed")
    drawn = (code != INPUT) & (code != FILL) & (code != RELIT) & (code != IN_FRONT)
    filled = (code == FILL) | (code == RELIT)
    out.update({"rid": rid, "seen": int(seen.sum()), "hidden": int(hidden.sum()), "status": status,
                "own_share": round(best_own, 3), "pick_share": round(in_pick, 3),
                "hid_drawn": int((hidden & drawn).sum()), "hid_fill": int((hidden & filled).sum()),
                "hid_input": int((hidden & (code == INPUT)).sum()),
                "stray": int((reg & drawn & ~hidden).sum()),
                "db_hid_drawn": db(hidden & drawn), "db_hid_fill": db(hidden & filled),
                "db_stray": db(drawn & ~hidden), "db_rest": db(~hidden & ~drawn)})
    return out


def main(out: str, runs: list[str]) -> None:
    rows = []
    for run in runs:
        for p in sorted(Path(run + ".dump").glob("*.npz")):
            r = one(p)
            if r is not None:
                r["run"] = Path(run).name
                rows.append(r)
    with open(out + ".tmp", "w") as f:
        json.dump(rows, f, indent=0)
    Path(out + ".tmp").replace(out)
    for r in rows:
        print(" ".join(f"{k}={v:+.3f}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
