# ruff: noqa: E501
"""changed.py OUT.png TREE MAIN_RUN BRANCH_RUN N: the N entries of one Table 1 row whose 3D-SDN pick differs between
main and the branch (per-entry npz of session 11's dbench.py in RUN.dump, results.json in RUN), largest change of
3D-SDN PSNR all first; two rows each, whole frame, 2x. Panels: source with the operations' `from` points (yellow
crosses), the true car (white outline: ground truth, for scoring only), main's picked proposal (red) and the branch's
(green; where both pick the same proposal it is drawn green), 3D-SDN main, 3D-SDN branch; below: target, 2D paste
main, 2D paste branch; each titled with its PSNR all (dB)."""
import json
import sys

import numpy as np
from PIL import Image, ImageDraw

from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation

S = 2
SIZE = (312, 96)


def outline(mask: np.ndarray) -> np.ndarray:
    inner = mask.copy()
    inner[1:] &= mask[:-1]
    inner[:-1] &= mask[1:]
    inner[:, 1:] &= mask[:, :-1]
    inner[:, :-1] &= mask[:, 1:]
    return mask & ~inner


def metrics(run: str) -> dict[int, dict]:
    entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
    return {e["index"]: (e.get("metrics") or {}).get("photo") or {} for e in entries}


def panel(image: np.ndarray, title: str) -> Image.Image:
    big = Image.fromarray(np.kron(image, np.ones((S, S, 1), image.dtype)))
    canvas = Image.new("RGB", (big.width, big.height + 14), "white")
    canvas.paste(big, (0, 14))
    ImageDraw.Draw(canvas).text((2, 1), title, fill="black")
    return canvas


def main(out: str, tree: str, main_run: str, branch_run: str, count: int) -> None:
    entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
    mm, bm = metrics(main_run), metrics(branch_run)
    rows = []
    for i in sorted(set(mm) & set(bm)):
        try:
            zm, zb = np.load(f"{main_run}.dump/{i:04d}.npz"), np.load(f"{branch_run}.dump/{i:04d}.npz")
        except FileNotFoundError:
            continue
        if zm["picks"].tolist() != zb["picks"].tolist() and "3d-sdn" in mm[i] and "3d-sdn" in bm[i]:
            change = bm[i]["3d-sdn"]["all"]["psnr"] - mm[i]["3d-sdn"]["all"]["psnr"]
            rows.append((abs(change), i, zm, zb))
    rows.sort(key=lambda r: -r[0])
    lines = []
    for _, i, zm, zb in rows[:count]:
        src = zb["source"].copy()
        for iid, colour in ((int(k), (255, 255, 255)) for k in zb["gt_ids"]):
            src[outline(zb["src_inst"] == iid)] = colour
        for picks, colour in ((zm["picks"], (255, 40, 40)), (zb["picks"], (40, 255, 40))):
            for iid in picks.tolist():
                src[outline(zb["proposals"] == iid)] = colour
        first = panel(src, f"entry {i} {zb['kind']}: from (yellow), true car (white), main pick (red), branch (green)")
        draw = ImageDraw.Draw(first)
        for op in entries[i].operations:
            u, v = scale_operation(op, (1242, 375), SIZE).from_uv
            x, y = (u + 0.5) * S, (v + 0.5) * S + 14
            draw.line([(x - 5, y), (x + 5, y)], fill="yellow", width=2)
            draw.line([(x, y - 5), (x, y + 5)], fill="yellow", width=2)
        m, b = mm[i], bm[i]
        grid = [[first, panel(zm["sdn"], f"3D-SDN main {m['3d-sdn']['all']['psnr']:.2f} dB"),
                 panel(zb["sdn"], f"3D-SDN branch {b['3d-sdn']['all']['psnr']:.2f} dB")],
                [panel(zb["target"], "target"), panel(zm["d2"], f"2D paste main {m['2d']['all']['psnr']:.2f} dB"),
                 panel(zb["d2"], f"2D paste branch {b['2d']['all']['psnr']:.2f} dB")]]
        for cells in grid:
            line = Image.new("RGB", (sum(c.width for c in cells) + 4 * len(cells), cells[0].height), "white")
            x = 0
            for c in cells:
                line.paste(c, (x, 0))
                x += c.width + 4
            lines.append(line)
    sheet = Image.new("RGB", (max(line.width for line in lines), sum(line.height + 6 for line in lines)), "white")
    y = 0
    for line in lines:
        sheet.paste(line, (0, y))
        y += line.height + 3
    sheet.save(out)
    print(f"{out}: {len(lines) // 2} of {len(rows)} entries whose pick changed")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]))
