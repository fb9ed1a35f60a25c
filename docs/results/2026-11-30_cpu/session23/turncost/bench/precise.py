"""precise.py LABEL MAIN_DIR BRANCH_DIR [...]: paired.py's PSNR rows (fill rays) with the mean difference branch -
main and its interval to 5 decimals (dB; paired.py prints 3, and this cut's differences are smaller), from the same
counterfactual.json files and pairing, by sdn3d.evaluation.paired.paired_difference with 10,000 resamples (paired.py
uses its default, 4,000)."""

import sys
from collections import defaultdict

from paired import LABELS, load

from sdn3d.evaluation.paired import paired_difference

FILL = "photo:rays"
args = sys.argv[1:]
print("| tree | source scene | kind / bin | n | branch - main, dB [95 %] | wins/losses/ties |")
print("|---|---|---|---|---|---|")
for i in range(0, len(args), 3):
    label, main, branch = args[i], load(args[i + 1]), load(args[i + 2])
    groups = defaultdict(list)
    for k in sorted(set(main) & set(branch)):
        groups[(k[0], k[1])].append(k)
    for (source, bin_), keys in sorted(groups.items()):
        for region in ("hole",) if bin_ == "delete" else ("car", "changed"):
            got = [(main[k]["metrics"][FILL][region]["psnr"], branch[k]["metrics"][FILL][region]["psnr"])
                   for k in keys if FILL in main[k]["metrics"] and FILL in branch[k]["metrics"]]
            if not got:
                continue
            d = paired_difference([g[1] for g in got], [g[0] for g in got], True, samples=10000)
            where = bin_ if bin_ == "delete" else f"{bin_}, {region} pixels"
            print(f"| {label} | {LABELS.get(source, source)} | {where} | {d.n} | {d.mean:+.5f} [{d.low:+.5f}, "
                  f"{d.high:+.5f}] | {d.wins}/{d.losses}/{d.ties} |")
