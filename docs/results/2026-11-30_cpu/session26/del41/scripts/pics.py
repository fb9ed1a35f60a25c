"""pics.py OUT.png TITLE DUMP:INDEX[:LABEL] ...: one row per delete entry of dbench.py dumps (npz per entry): the
input with the picked proposal's mask outlined (yellow) and the edit region (cyan), the target, the 2D paste,
3D-SDN, the 3D-SDN removal's pixel sources (grey: the proposal's mask; red: 3D-SDN's fill beyond it, i.e. the
fitted silhouette, the shadow and their rims; green: relit; blue: thin things kept in front) and where 3D-SDN's
error exceeds the 2D paste's (red: 3D-SDN worse, green: better, inside the edit region), cropped around the edit
region, the mask and the fill (12 pixels more each side). LABEL names the code; the PSNRs are of the region."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

FILL, RELIT, IN_FRONT = 4, 9, 10


def psnr(a: np.ndarray, b: np.ndarray, region: np.ndarray) -> float:
    err = ((a.astype(float) - b.astype(float)) / 255) ** 2
    return float(10 * np.log10(1 / max(err[region].mean(), 1e-12)))


def outline(mask: np.ndarray) -> np.ndarray:
    m = mask.astype(bool)
    inner = m.copy()
    inner[1:] &= m[:-1]
    inner[:-1] &= m[1:]
    inner[:, 1:] &= m[:, :-1]
    inner[:, :-1] &= m[:, 1:]
    return m & ~inner


def main(out: str, title: str, specs: list[str]) -> None:
    fig, axes = plt.subplots(len(specs), 6, figsize=(6 * 2.4, len(specs) * 1.9 + 0.6), squeeze=False)
    for r, spec in enumerate(specs):
        parts = spec.split(":")
        dump, index, label = parts[0], int(parts[1]), parts[2] if len(parts) > 2 else ""
        d = np.load(f"{dump}/{index:04d}.npz")
        src, tgt, sdn, d2, region = d["source"], d["target"], d["sdn"], d["d2"], d["region"]
        mask = np.isin(d["proposals"], d["picks"]) & (d["proposals"] != 0)
        inp = src.copy()
        inp[outline(mask)] = (255, 255, 0)
        inp[outline(region)] = (0, 255, 255)
        code = d["code"]
        srcmap = np.full(src.shape, 40, np.uint8)
        srcmap[mask] = 140
        if code.size:
            srcmap[(code == FILL) & ~mask] = (230, 40, 40)
            srcmap[code == RELIT] = (40, 200, 40)
            srcmap[code == IN_FRONT] = (60, 90, 255)
        e3 = np.abs(sdn.astype(float) - tgt).mean(2)
        e2 = np.abs(d2.astype(float) - tgt).mean(2)
        diff = np.zeros(src.shape, np.uint8)
        worse = np.clip((e3 - e2) * 8, 0, 255) * region
        better = np.clip((e2 - e3) * 8, 0, 255) * region
        diff[..., 0], diff[..., 1] = worse.astype(np.uint8), better.astype(np.uint8)
        p3, p2 = psnr(sdn, tgt, region), psnr(d2, tgt, region)
        panels = [(inp, f"{label} #{index} input (yellow: proposal, cyan: region)"), (tgt, "target"),
                  (d2, f"2D paste ({label}) {p2:.2f} dB"), (sdn, f"3D-SDN ({label}) {p3:.2f} dB ({p3 - p2:+.2f})"),
                  (srcmap, "3D fill beyond mask red, relit green, kept blue"), (diff, "3D-SDN error vs 2D: red worse")]
        box = region | mask | ((code == FILL) if code.size else False)
        ys, xs = np.nonzero(box)
        y0, y1 = max(int(ys.min()) - 12, 0), min(int(ys.max()) + 13, src.shape[0])
        x0, x1 = max(int(xs.min()) - 12, 0), min(int(xs.max()) + 13, src.shape[1])
        for c, (img, name) in enumerate(panels):
            img = img[y0:y1, x0:x1]
            ax = axes[r, c]
            ax.imshow(img, interpolation="nearest")
            ax.set_title(name, fontsize=7)
            ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
