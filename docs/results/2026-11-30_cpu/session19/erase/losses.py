# ruff: noqa: E501
"""losses.py MAIN_DIR BRANCH_DIR [LABEL]: per delete pair (ground-truth geometry (oracle)) of two counterfactual runs,
main's with fills telea, patchmatch and rays: the pairs where main's rays score below the better of Telea and
PatchMatch (PSNR on the vacated region plus shadow band) and their summed deficit; the pairs the branch's rays change
(on these trees: the holes over the vanishing point), how many of main's losses they are and their deficit; and the
branch's count of losses against main's original fills."""

from __future__ import annotations

import json
import sys


def psnr(run: dict, key: str, fill: str) -> float:
    return run[key]["metrics"][fill]["hole"]["psnr"]


def main() -> int:
    m = {p["key"]: p for p in json.load(open(f"{sys.argv[1]}/counterfactual.json"))["pairs"] if p["kind"] == "delete" and p["source"] == "oracle"}
    b = {p["key"]: p for p in json.load(open(f"{sys.argv[2]}/counterfactual.json"))["pairs"] if p["kind"] == "delete" and p["source"] == "oracle"}
    label = sys.argv[3] if len(sys.argv) > 3 else sys.argv[1]

    def best(k: str) -> float:
        return max(psnr(m, k, "photo:telea"), psnr(m, k, "photo:patchmatch"))

    loss = [k for k in m if psnr(m, k, "photo:rays") < best(k)]
    changed = [k for k in m if k in b and abs(psnr(b, k, "photo:rays") - psnr(m, k, "photo:rays")) > 1e-9]
    both = set(changed) & set(loss)
    loss_b = [k for k in m if k in b and psnr(b, k, "photo:rays") < best(k)]
    print(f"{label}: pairs {len(m)}; main's rays below the best of Telea/PatchMatch on {len(loss)} (summed deficit "
          f"{sum(best(k) - psnr(m, k, 'photo:rays') for k in loss):.1f} dB); pairs the branch changes {len(changed)}, of "
          f"them main's losses {len(both)} (deficit {sum(best(k) - psnr(m, k, 'photo:rays') for k in both):.1f} dB); "
          f"branch's rays below the best original on {len(loss_b)}")
    for k in sorted(loss, key=lambda k: psnr(m, k, "photo:rays") - best(k)):
        print(f"  {k}: rays {psnr(m, k, 'photo:rays'):.2f} (branch {psnr(b, k, 'photo:rays'):.2f}), Telea {psnr(m, k, 'photo:telea'):.2f}, "
              f"PatchMatch {psnr(m, k, 'photo:patchmatch'):.2f}, learnt {psnr(m, k, 'photo:learnt'):.2f}, vacated {m[k]['pixels']['vacated']} px"
              f"{' (changed by the branch)' if k in changed else ''}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
