# ruff: noqa: E402, E501, E701, E702
"""exact.py MAIN_DIR BRANCH_DIR: paired.py's pooled turns >= 45 rows (the same pairs in the same order, the same
bootstrap) with 6 decimals, per source scene: the clause bounds unrounded, resampling whole cars (the rule's) and,
beside, pairs."""
import sys
from collections import defaultdict

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from paired import FILL, car_of, load  # noqa: E402

from sdn3d.evaluation.paired import paired_difference  # noqa: E402

main, branch = load(sys.argv[1]), load(sys.argv[2])
groups = defaultdict(list)
for k in sorted(set(main) & set(branch)):
    groups[(k[0], k[1])].append((main[k]["metrics"][FILL]["car"], branch[k]["metrics"][FILL]["car"], k[2]))
pooled = defaultdict(list)
for (source, bin_), got in sorted(groups.items(), key=lambda t: (t[0][0], int(t[0][1].split()[-1]))):
    if int(bin_.split()[-1]) >= 45:
        pooled[source] += got
for source, got in pooled.items():
    cars = [car_of(g[2]) for g in got]
    for name, grp in (("cars", cars), ("pairs", None)):
        d = paired_difference([g[1]["psnr"] for g in got], [g[0]["psnr"] for g in got], True, groups=grp)
        e = paired_difference([g[1]["l1"] for g in got], [g[0]["l1"] for g in got], False, groups=grp)
        print(f"{source} ({name}, {d.groups or d.n} resampled): n {len(got)} PSNR {d.mean:+.6f} [{d.low:+.6f}, {d.high:+.6f}]  L1 {e.mean:+.6f} [{e.low:+.6f}, {e.high:+.6f}]")
