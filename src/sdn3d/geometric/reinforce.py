"""REINFORCE for the (non-differentiable) choice of mesh template (3D-SDN, Sec. 3.1).

Each object draws ``K`` templates from the predicted distribution ``p(m)``; each sample is
rendered with the same pose and FFD and gets the reward ``r_k = -L_reproj``. The score-function
surrogate ``-mean_k (r_k - b) log p(m_k)`` has the policy gradient as its gradient. The baseline
``b`` lowers the variance:

- ``"moving_average"`` (default): an exponential moving average of the mean reward, kept in a
  buffer of :class:`MovingAverageBaseline` (saved in checkpoints, so a resumed run continues
  with the same baseline);
- ``"leave_one_out"``: per object, the mean reward of its other ``K - 1`` samples (unbiased,
  needs ``K >= 2``; adapts to each object's difficulty);
- ``"exact"``: no sampling at all: every template is rendered for every object and the gradient is that of
  the expected reward ``sum_m p(m) r_m`` (:func:`expected_reward_loss`; ``T`` renders per object, no variance).
"""

from __future__ import annotations

import torch
from torch import Tensor, nn

__all__ = ["BASELINES", "sample_templates", "reinforce_loss", "expected_reward_loss", "leave_one_out_baseline",
           "MovingAverageBaseline"]

BASELINES = ("moving_average", "leave_one_out", "exact")


def sample_templates(
    logits: Tensor, num_samples: int, generator: torch.Generator | None = None
) -> tuple[Tensor, Tensor]:
    """Draw ``K`` template indices per object from ``softmax(logits)`` (with replacement).

    Args:
        logits: ``(N, T)`` unnormalised log-probabilities.
        num_samples: ``K >= 1``.
        generator: optional RNG (on the logits' device).

    Returns:
        ``indices (N, K)`` long (into the ``T`` logits) and their ``log_probs (N, K)``
        (differentiable w.r.t. ``logits``).
    """
    if logits.dim() != 2 or logits.shape[1] == 0:
        raise ValueError(f"logits must have shape (N, T) with T >= 1, got {tuple(logits.shape)}")
    if num_samples < 1:
        raise ValueError(f"num_samples must be at least 1, got {num_samples}")
    log_probs = logits.log_softmax(dim=1)
    with torch.no_grad():
        indices = torch.multinomial(log_probs.exp(), num_samples, replacement=True, generator=generator)
    return indices, log_probs.gather(1, indices)


def leave_one_out_baseline(rewards: Tensor) -> Tensor:
    """``(N, K)`` mean reward of each object's other samples (``K >= 2``)."""
    if rewards.dim() != 2 or rewards.shape[1] < 2:
        raise ValueError(f"leave-one-out needs rewards of shape (N, K) with K >= 2, got {tuple(rewards.shape)}")
    k = rewards.shape[1]
    return (rewards.sum(1, keepdim=True) - rewards) / (k - 1)


def reinforce_loss(log_probs: Tensor, rewards: Tensor, baseline: Tensor | float = 0.0) -> Tensor:
    """Score-function surrogate ``-mean((r - b) log p)``; its gradient is the REINFORCE estimate.

    Args:
        log_probs: ``(N, K)`` log-probabilities of the sampled templates (with grad).
        rewards: ``(N, K)`` rewards (treated as constants).
        baseline: scalar or broadcastable ``(N, K)`` baseline (treated as a constant).
    """
    if log_probs.shape != rewards.shape:
        raise ValueError(f"log_probs {tuple(log_probs.shape)} and rewards {tuple(rewards.shape)} must match")
    advantage = (rewards - baseline).detach()
    return -(advantage * log_probs).mean()


def expected_reward_loss(logits: Tensor, rewards: Tensor) -> Tensor:
    """``-mean_n sum_m p_n(m) r_nm`` with ``p = softmax(logits)``: the exact policy gradient over all templates.

    Its gradient is the expectation of the REINFORCE estimate (with any baseline), so it has no variance.

    Args:
        logits: ``(N, T)`` template logits (with grad).
        rewards: ``(N, T)`` the reward of every template for every object (treated as constants).
    """
    if logits.shape != rewards.shape:
        raise ValueError(f"logits {tuple(logits.shape)} and rewards {tuple(rewards.shape)} must match")
    return -(logits.softmax(1) * rewards.detach()).sum(1).mean()


class MovingAverageBaseline(nn.Module):
    """Exponential moving average of the reward, in buffers (``value``, ``count``) so it resumes exactly.

    Args:
        momentum: weight of the old value in ``b <- m b + (1 - m) mean(r)``; the first update sets ``b``.
    """

    def __init__(self, momentum: float = 0.9) -> None:
        super().__init__()
        if not 0.0 <= momentum < 1.0:
            raise ValueError(f"momentum must lie in [0, 1), got {momentum}")
        self.momentum = float(momentum)
        self.register_buffer("value", torch.zeros(()))
        self.register_buffer("count", torch.zeros((), dtype=torch.long))

    def forward(self) -> Tensor:
        """The current baseline (0 before the first update)."""
        return self.value

    @torch.no_grad()
    def update(self, rewards: Tensor) -> Tensor:
        """Fold the mean of ``rewards`` into the average; returns the new value."""
        mean = rewards.detach().mean().to(self.value.dtype)
        # Branch-free (no host sync on GPUs): the first update takes the mean as it is.
        keep = torch.where(self.count > 0, self.momentum, 0.0).to(self.value.dtype)
        self.value.copy_(keep * self.value + (1.0 - keep) * mean)
        self.count.add_(1)
        return self.value
