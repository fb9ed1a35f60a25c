"""jtable.py JSONL: per joined frame, the de-render CPU seconds of each code jtime.sh alternated (median of every
timed call, min-max, count), the ratio branch / main of the medians with its spread over the rounds (each round:
main's median of its 3 calls and the branch's next to it), and with ``nojoin`` (the frame without its join) the
join's extra cost on main and on the branch; a markdown table (session 29 joincost29)."""
import json
import statistics
import sys

rows = [json.loads(line) for line in open(sys.argv[1])]
codes = list(dict.fromkeys(r["code"] for r in rows))
head = " | ".join(f"{c} CPU s: median [min, max] (n)" for c in codes)
extra = " | join's extra s, main -> branch" if "nojoin" in codes else ""
print(f"| frame (tuning tree) | {head} | branch / main (medians) | per-round ratio: median [min, max]{extra} |")
print("|---" * (len(codes) + 3 + bool(extra)) + "|")
for seed, key in dict.fromkeys((r["seed"], r["key"]) for r in rows):
    of = {c: [r for r in rows if (r["seed"], r["key"]) == (seed, key) and r["code"] == c] for c in codes}
    times = {c: [t for r in of[c] for t in r["cpu_s"]] for c in codes}
    med = {c: statistics.median(times[c]) for c in codes}
    rounds = [statistics.median(y["cpu_s"]) / statistics.median(x["cpu_s"])
              for x, y in zip(of["main"], of["branch"], strict=True)]
    cells = " | ".join(f"{med[c]:.3f} [{min(times[c]):.3f}, {max(times[c]):.3f}] ({len(times[c])})" for c in codes)
    more = (f" | {med['main'] - med['nojoin']:+.3f} -> {med['branch'] - med['nojoin']:+.3f}" if extra else "")
    print(f"| {key[8:]} ({seed}) | {cells} | x{med['branch'] / med['main']:.2f} | x{statistics.median(rounds):.2f} "
          f"[{min(rounds):.2f}, {max(rounds):.2f}] ({len(rounds)} rounds){more} |")
