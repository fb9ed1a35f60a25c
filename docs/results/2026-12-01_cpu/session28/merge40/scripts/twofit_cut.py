"""twofit.py's 2-means cut, importable (session 28 merge40)."""
import torch


def two_means(m: torch.Tensor, iters: int = 10) -> torch.Tensor:
    """``(H, W)`` bool: the part of ``m`` nearer the first of two 2-means centres on the pixels' (x, y)."""
    ys, xs = m.nonzero(as_tuple=True)
    p = torch.stack([xs, ys], 1).float()
    c = p[torch.stack([p[:, 0].argmin(), p[:, 0].argmax()])]
    for _ in range(iters):
        a = (p[:, None] - c[None]).square().sum(2).argmin(1)
        c = torch.stack([p[a == k].mean(0) if (a == k).any() else c[k] for k in range(2)])
    part = torch.zeros_like(m)
    part[ys[a == 0], xs[a == 0]] = True
    return part
