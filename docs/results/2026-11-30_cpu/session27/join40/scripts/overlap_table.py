"""overlap_table.py UNION.json TABLE.md PLOT.png: step 1's separation table and plot from union.py's pairs (every
touching pair of fitted predicted proposals on the seven tuning Table 1 trees, main, w0; truth labels from the
ground-truth instance maps, an oracle used only to label): per footprint-overlap threshold, how many pairs of one
car's parts ("same"), of two cars ("two") and of anything else ("other") reach it; the same for the footprints' IoU
and for the union's fit IoU gain; and a scatter of the overlap against the gain, labelled by truth.
Run: python overlap_table.py /tmp/s27data/join40/union_main.json ../tables/overlap_pairs.md ../pictures/overlap.png
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = ("same", "two", "other")


def main() -> None:
    pairs = json.load(open(sys.argv[1]))
    n = {lab: sum(p["label"] == lab for p in pairs) for lab in LABELS}
    lines = ["Touching fitted predicted proposals (gap 1-4 px; all but 3 pairs touch), 7 tuning Table 1 trees, main "
             "9bee856 (frag40's caches), w0, 312x96. Truth (ground-truth instance maps, an oracle, labels only): "
             "*same* = both lie >= 50 % on one true car (two parts of one car), *two* = each >= 50 % on a different "
             f"true car, *other* = the rest. Pairs: same {n['same']}, two {n['two']}, other {n['other']}.", "",
             "| cue | threshold | same (one car's parts) | two (two cars) | other |", "|---|---|---|---|---|"]

    def row(cue: str, thr: str, test) -> None:
        c = {lab: sum(1 for p in pairs if p["label"] == lab and test(p)) for lab in LABELS}
        lines.append(f"| {cue} | {thr} | {c['same']} | {c['two']} | {c['other']} |")

    for t in (0.0, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5):
        row("footprint overlap / smaller footprint", "> 0" if t == 0 else f">= {t}",
            (lambda p, t=t: p["ios"] > 0) if t == 0 else (lambda p, t=t: p["ios"] >= t))
    for t in (0.1, 0.2, 0.3):
        row("footprint IoU", f">= {t}", lambda p, t=t: p["iou"] >= t)
    for t in (0.0, 0.05, 0.1):
        row("union's fit IoU - parts' (pixel-weighted)", f">= {t}",
            lambda p, t=t: (p["union_iou"] or 0) - p["parts_iou"] >= t)
    for t in (0.85, 0.9):
        row("union's fit IoU", f">= {t}", lambda p, t=t: (p["union_iou"] or 0) >= t)
    row("overlap >= 0.3 and union gain >= 0.03", "", lambda p: p["ios"] >= 0.3 and
        (p["union_iou"] or 0) - p["parts_iou"] >= 0.03)
    lines += ["", "The highest overlaps, by truth:", "", "| truth | tree | frame | ids | overlap / smaller | IoU | "
              "union fit IoU | parts' fit IoU |", "|---|---|---|---|---|---|---|---|"]
    for p in sorted(pairs, key=lambda p: -p["ios"])[:16]:
        lines.append(f"| {p['label']} | {p['tree']} | {p['key'][8:]} | {p['a']}, {p['b']} | {p['ios']:.2f} | "
                     f"{p['iou']:.2f} | {p['union_iou'] or 0:.3f} | {p['parts_iou']:.3f} |")
    open(sys.argv[2], "w").write("\n".join(lines) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for lab, col in zip(LABELS, ("tab:green", "tab:red", "tab:gray"), strict=True):
        sel = [p for p in pairs if p["label"] == lab]
        ax.scatter([p["ios"] for p in sel], [(p["union_iou"] or 0) - p["parts_iou"] for p in sel], s=12, c=col,
                   alpha=0.7, label=f"{lab} ({len(sel)})")
    ax.axvline(0.45, color="k", lw=0.8, ls="--")
    ax.text(0.46, ax.get_ylim()[1] * 0.9, "join_overlap 0.45", fontsize=8)
    ax.set_xlabel("fitted footprints' overlap / smaller footprint (main's fit)")
    ax.set_ylabel("union's fit IoU - parts' fit IoU")
    ax.set_title("Touching predicted proposals, 7 tuning trees, main, w0: one car's parts (same) vs two cars",
                 fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[3], dpi=90)


if __name__ == "__main__":
    main()
