# ruff: noqa: INP001, E501
"""Pictures of a few counterfactual pairs as the benchmark draws them (the benchmark itself writes none).

    python pics.py subtree TREE SUB TARGETS...      # SUB: TREE's files, counterfactual_pairs.json cut to TARGETS
    python pics.py draw SUB OUT METHOD [bench overrides...]   # inside a code tree (its src on PYTHONPATH): runs that
                                                    # code's sdn3d-bench counterfactual=true on SUB and saves METHOD's
                                                    # drawn picture of every pair as OUT/<pair>.png
    python pics.py sheet SUB OUT.png LABEL=DIR...   # per pair: source | target | each DIR's picture, cropped around
                                                    # the car, its vacated region and shadow band

TARGETS are world/variation/frame_instance (as in the pair keys). Nothing here changes what the benchmark draws: the
renderers are wrapped only to save their pictures.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw


def subtree(tree: str, sub: str, targets: list[str]) -> None:
    src, dst = Path(tree), Path(sub)
    dst.mkdir(parents=True)
    for entry in src.iterdir():
        if entry.name != "counterfactual_pairs.json":
            os.symlink(entry, dst / entry.name)
    index = json.loads((src / "counterfactual_pairs.json").read_text())
    keep = set(targets)
    index["pairs"] = [p for p in index["pairs"]
                      if f"{p['world']}/{p['variation']}/{p['frame']:05d}_{p['instance_id']}" in keep]
    (dst / "counterfactual_pairs.json").write_text(json.dumps(index))
    print(len(index["pairs"]), "pairs")


def draw(sub: str, out: str, method: str, overrides: list[str]) -> int:
    import sdn3d.evaluation.counterfactual as cf

    Path(out).mkdir(parents=True, exist_ok=True)
    current = {}
    score, renderers = cf._score_pair, cf._renderers

    def scored(result, pair, *a, **k):
        current["key"] = pair.key
        return score(result, pair, *a, **k)

    class Saving:
        def __init__(self, name, renderer):
            self._name, self._renderer = name, renderer

        def __getattr__(self, attr):
            return getattr(self._renderer, attr)

        def draw(self, *a, **k):
            drawn = self._renderer.draw(*a, **k)
            if self._name == method:
                image = drawn.image.float().clamp(0, 1).permute(1, 2, 0).numpy()
                name = current["key"].replace("/", "_").replace(" ", "_")
                Image.fromarray((image * 255).round().astype(np.uint8)).save(f"{out}/{name}.png")
            return drawn

    cf._score_pair = scored
    cf._renderers = lambda names, *a, **k: {n: Saving(n, r) for n, r in renderers(names, *a, **k).items()}
    from sdn3d.cli.bench import main

    return main(["counterfactual=true", f"data.root={sub}", f"output_dir={out}/bench", *overrides])


def sheet(sub: str, out: str, runs: list[str]) -> None:
    root = Path(sub)
    index = json.loads((root / "counterfactual_pairs.json").read_text())
    runs = [r.split("=", 1) for r in runs]
    rows = []
    for p in index["pairs"]:
        if p["kind"] == "turn" and p["angle_deg"] == 15:
            continue
        what = "delete" if p["kind"] == "delete" else f"turn_{p['angle_deg']:g}"
        key = f"{p['world']}/{p['variation']}/{p['frame']:05d}_{p['instance_id']} {what}"
        masks = [np.asarray(Image.open(root / p[k])) > 0 for k in ("source_mask", "target_mask", "vacated", "shadow")
                 if p.get(k)]
        ys, xs = np.nonzero(np.any(masks, axis=0))
        pad = 12
        box = (max(0, xs.min() - pad), max(0, ys.min() - pad), min(624, xs.max() + pad + 1), min(192, ys.max() + pad + 1))
        tiles = [("source", Image.open(root / p["source"]).convert("RGB")),
                 ("target", Image.open(root / p["target"]).convert("RGB"))]
        name = key.replace("/", "_").replace(" ", "_")
        tiles += [(label, Image.open(f"{d}/{name}.png").convert("RGB")) for label, d in runs]
        h = 120
        row = []
        for label, im in tiles:
            c = im.crop(box)
            c = c.resize((max(1, round(c.width * h / c.height)), h), Image.NEAREST)
            ImageDraw.Draw(c).text((2, 2), label, fill=(255, 255, 0))
            row.append(c)
        width = sum(c.width for c in row) + 4 * (len(row) - 1)
        canvas = Image.new("RGB", (width, h + 14), (0, 0, 0))
        ImageDraw.Draw(canvas).text((2, h + 1), key, fill=(255, 255, 255))
        x = 0
        for c in row:
            canvas.paste(c, (x, 0))
            x += c.width + 4
        rows.append(canvas)
    width = max(r.width for r in rows)
    out_im = Image.new("RGB", (width, sum(r.height + 4 for r in rows)), (0, 0, 0))
    y = 0
    for r in rows:
        out_im.paste(r, (0, y))
        y += r.height + 4
    out_im.save(out)


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "subtree":
        subtree(args[0], args[1], args[2:])
    elif cmd == "draw":
        raise SystemExit(draw(args[0], args[1], args[2], args[3:]))
    else:
        sheet(args[0], args[1], args[2:])
