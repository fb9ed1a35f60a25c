"""cf_pooled.py LABEL MAIN_PREFIX BRANCH_PREFIX TREE...: session 21 speck's paired.py (cf_paired.py here) with the
pairs of several counterfactual trees pooled per angle bin (``<PREFIX>_<TREE>/counterfactual.json``, cf.sh's
outputs), branch - main, 10k bootstrap resamples, 95 %. Run with a library on PYTHONPATH (sdn3d.evaluation.paired)."""

from __future__ import annotations

import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from cf_paired import load, rows  # noqa: E402


def main() -> int:
    label, main_prefix, branch_prefix, trees = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    main_pairs, branch_pairs = {}, {}
    for t in trees:
        main_pairs |= {(k[0], k[1], f"{t}/{k[2]}"): v for k, v in load(f"{main_prefix}_{t}").items()}
        branch_pairs |= {(k[0], k[1], f"{t}/{k[2]}"): v for k, v in load(f"{branch_prefix}_{t}").items()}
    print("| trees | source scene | kind / bin | fill | n | PSNR main | PSNR branch | branch - main [95 % CI] | "
          "wins/losses/ties | | | | |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows(label, main_pairs, branch_pairs):
        print(r)
    return 0


if __name__ == "__main__":
    sys.exit(main())
