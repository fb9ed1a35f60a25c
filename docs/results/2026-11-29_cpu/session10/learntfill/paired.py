# ruff: noqa: E501
"""paired.py A/counterfactual.json[+A2/counterfactual.json] [B/...]: over the deletes of all the files together, photo:learnt
against every other fill (sdn3d.evaluation.paired: mean, 95 % bootstrap interval, wins/losses/ties) on the vacated
region + shadow band (PSNR, L1, darkening error), per file and pooled; the residual darkening of each fill."""
import json
import sys

from sdn3d.evaluation.paired import paired_difference

FILLS = ("photo:telea", "photo:patchmatch", "photo:rays", "photo:learnt")


def deletes(paths):
    """The deletes of one tree: its runs' files joined by '+' (each fill's metrics merged by pair key)."""
    merged = {}
    for path in paths.split("+"):
        for p in json.load(open(path))["pairs"]:
            if p["kind"] == "delete":
                merged.setdefault(p["key"], p)["metrics"].update(p["metrics"])
                merged[p["key"]]["draw_ms"].update(p["draw_ms"])
    return [p for p in merged.values() if all(m in p["metrics"] for m in FILLS)]


def table(name, rows):
    mean = lambda xs: sum(xs) / len(xs)  # noqa: E731
    print(f"\n### {name}: n = {len(rows)} deletes\n")
    print("| fill | PSNR dB | L1 | darkening (target's {:.3f}) | wall ms/delete (whole draw; base and learnt runs at different machine loads) |".format(mean([r["reference"]["target"] for r in rows if r["reference"]["target"] == r["reference"]["target"]])))
    print("|---|---|---|---|---|")
    for m in FILLS:
        dk = [r["metrics"][m]["hole"]["darkening"] for r in rows if r["metrics"][m]["hole"]["darkening"] == r["metrics"][m]["hole"]["darkening"]]
        print(f"| {m} | {mean([r['metrics'][m]['hole']['psnr'] for r in rows]):.2f} | {mean([r['metrics'][m]['hole']['l1'] for r in rows]):.4f} | {mean(dk):.3f} | {mean([r['draw_ms'][m] for r in rows]):.0f} |")
    print("\n| learnt vs | ΔPSNR dB [95 %] w/l/t | ΔL1 [95 %] w/l/t | Δdarkening error [95 %] w/l/t |\n|---|---|---|---|")
    for m in FILLS[:-1]:
        cells = []
        for metric, hib, dg in (("psnr", True, 2), ("l1", False, 4), ("darkening_error", False, 3)):
            pairs = [(r["metrics"]["photo:learnt"]["hole"][metric], r["metrics"][m]["hole"][metric]) for r in rows]
            pairs = [(a, b) for a, b in pairs if a == a and b == b]
            d = paired_difference([a for a, _ in pairs], [b for _, b in pairs], higher_is_better=hib)
            cells.append(f"{d.mean:+.{dg}f} [{d.low:+.{dg}f}, {d.high:+.{dg}f}] {d.wins}/{d.losses}/{d.ties}")
        print(f"| {m} | " + " | ".join(cells) + " |")


allrows = []
for path in sys.argv[1:]:
    rows = deletes(path)
    table(path.split("+")[0].split("/")[-2], rows)
    allrows += rows
if len(sys.argv) > 2:
    table("pooled", allrows)
