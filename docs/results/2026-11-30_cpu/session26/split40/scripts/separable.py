"""separable.py FEAT.json [LABEL]: for each feature of splitfeat.py's rows (main's 2-means splits, labelled with the
ground truth as an oracle), the most 'one car' splits a single threshold on it would stop while stopping no
'two cars' split (either side of the threshold), and the threshold's range. Prints a markdown table."""
import json
import sys


def features(r: dict) -> dict[str, float]:
    i = 0 if r["n"][0] < r["n"][1] else 1  # the smaller part
    return {"area (px)": r["area"], "separation (std)": r["sep"], "vote gap / sqrt(area)": r["gap_rel"],
            "vote gap / pixel gap": r["conv"], "smaller part / area": min(r["n"]) / r["area"],
            "smaller part's pull": r["pull"][i], "larger part's pull": r["pull"][1 - i],
            "heatmap max, smaller part": r["hmax"][i], "heatmap max, larger part": r["hmax"][1 - i],
            "heatmap max ratio small / large": r["hmax"][i] / max(r["hmax"][1 - i], 1e-6),
            "heatmap at smaller part's vote mean": r["hvote"][i],
            "smaller part's vote mean in its box": float(r["inbox"][i])}


if __name__ == "__main__":
    rows = [r for r in json.load(open(sys.argv[1])) if r["split"] and r["kind"] != "other"]
    one = [features(r) for r in rows if r["kind"] == "one car"]
    two = [features(r) for r in rows if r["kind"] == "two cars"]
    label = sys.argv[2] if len(sys.argv) > 2 else sys.argv[1]
    print(f"{label}: {len(one)} splits cutting one car, {len(two)} separating two cars\n")
    print("| feature | one car: range | two cars: range | most one-car splits stopped, no two-car split stopped |")
    print("|---|---|---|---|")
    for f in one[0]:
        a, b = [x[f] for x in one], [x[f] for x in two]
        below = sum(x < min(b) for x in a)  # stop splits under the two-car minimum
        above = sum(x > max(b) for x in a)
        best = f"{below} (below {min(b):.3g})" if below >= above else f"{above} (above {max(b):.3g})"
        print(f"| {f} | {min(a):.3g} to {max(a):.3g} | {min(b):.3g} to {max(b):.3g} | {best} of {len(a)} |")
