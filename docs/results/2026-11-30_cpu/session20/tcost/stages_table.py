"""stages_table.py MAIN.txt[,MAIN.txt...] NEW.txt[,NEW.txt...]: stages.py outputs of two codes (alternating runs)
as one table: each stage's wall ms per turn, the mean over each code's runs, its share of main's prepare +
render_photo, and new - main. No interval: the runs are few; the table says where a turn's time goes."""

import re
import sys


def read(paths: str) -> list[dict[str, float]]:
    runs = []
    for path in paths.split(","):
        runs.append({m[2]: float(m[1]) for m in re.finditer(r"^ +([\d.]+) ms +[\d.]+ %  (\S+)$", open(path).read(),
                                                             re.M)})
    return runs


main, new = read(sys.argv[1]), read(sys.argv[2])
mean = {name: {k: sum(r.get(k, 0.0) for r in runs) / len(runs) for k in runs[0]} for name, runs in
        (("main", main), ("new", new))}
whole = mean["main"]["render_photo"] + mean["main"]["PhotoSource.__init__"]
print(f"| stage (nested: a callee's time is also its caller's) | main ms per turn ({len(main)} runs) | share of main's "
      f"turn | this branch ms ({len(new)} runs) | this - main |")
print("|---|---|---|---|---|")
for k in sorted(mean["main"], key=lambda k: -mean["main"][k]):
    m, n = mean["main"][k], mean["new"].get(k, 0.0)
    print(f"| `{k}` | {m:.1f} | {100 * m / whole:.1f} % | {n:.1f} | {n - m:+.1f} |")
