"""entry_pic.py OUT.png ENTRY DUMP_A LABEL_A DUMP_B LABEL_B: one Table 1 entry's pictures (dbench.py's per-entry dumps,
``DUMP/<ENTRY:04d>.npz``) side by side, each panel titled: the source frame, the target frame, the 2D paste, 3D-SDN of
code A and of code B, then each code's 3D-SDN minus the target (absolute, x3), enlarged 3x (nearest)."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def image(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float32) / (255.0 if np.asarray(x).dtype == np.uint8 else 1.0)
    return np.clip(x.transpose(1, 2, 0) if x.shape[0] == 3 else x, 0, 1)


def psnr(a: np.ndarray, b: np.ndarray) -> float:
    return float(10 * np.log10(1.0 / max(float(np.mean((a - b) ** 2)), 1e-12)))


def main(out: str, entry: int, dump_a: str, label_a: str, dump_b: str, label_b: str) -> None:
    a, b = np.load(f"{dump_a}/{entry:04d}.npz"), np.load(f"{dump_b}/{entry:04d}.npz")
    tgt = image(a["target"])
    panels = [(image(a["source"]), f"source frame ({a['key']})"), (tgt, "target frame"),
              (image(a["d2"]), f"2D paste: whole-frame PSNR {psnr(image(a['d2']), tgt):.2f}"),
              (image(a["sdn"]), f"3D-SDN, {label_a}: whole-frame PSNR {psnr(image(a['sdn']), tgt):.2f}"),
              (image(b["sdn"]), f"3D-SDN, {label_b}: whole-frame PSNR {psnr(image(b['sdn']), tgt):.2f}"),
              (np.clip(3 * np.abs(image(a["sdn"]) - tgt), 0, 1), f"|3D-SDN {label_a} - target| x3"),
              (np.clip(3 * np.abs(image(b["sdn"]) - tgt), 0, 1), f"|3D-SDN {label_b} - target| x3")]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9.6, 3.2 * len(panels)))
    for ax, (im, title) in zip(axes, panels, strict=True):
        ax.imshow(im, interpolation="nearest")
        ax.set_title(title, fontsize=10)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), *sys.argv[3:7])
