"""The Bayesian signed-rank test of two detectors over tasks, with a region of practical equivalence.

Benavoli, Corani, Demsar & Zaffalon (2017), section 5.2. The differences
``z_1 .. z_n`` of a metric between two detectors, one per task, are modelled
by a Dirichlet process whose prior is a point mass at ``z_0 = 0`` of
strength ``s`` (default 0.5, the paper's choice). Its posterior is a
Dirichlet distribution over the weights of the observations,
``w = (w_0, w_1, .., w_n) ~ Dir(s, 1, .., 1)``, and the probabilities of the
three regions of the signed-rank statistic, over the pairs ``(i, j)`` of
``0 .. n`` (the Walsh averages ``(z_i + z_j) / 2``), are::

    theta_left  = sum_i sum_j w_i w_j I(z_i + z_j < -2 r)
    theta_rope  = sum_i sum_j w_i w_j I(|z_i + z_j| <= 2 r)
    theta_right = sum_i sum_j w_i w_j I(z_i + z_j > 2 r)

with ``r`` the half-width of the region of practical equivalence (ROPE).
Sampling ``w`` (a fixed seed) gives the posterior probability that each
region is the most probable one: ``P(left)``, ``P(rope)``, ``P(right)``,
which sum to 1. ``right`` means the first detector is practically better
(``z = a - b > r``), ``rope`` that the two are practically equivalent.
A decision is usual when one probability exceeds 0.95.

Reference
---------
Benavoli, A., Corani, G., Demsar, J. & Zaffalon, M. (2017). Time for a
change: a tutorial for comparing multiple classifiers through Bayesian
analysis. *JMLR* 18(77), 1-36.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BayesianSignedRank", "bayesian_signed_rank", "ROPE", "PRIOR_STRENGTH", "SAMPLES"]

#: half-width of the region of practical equivalence of a ROC AUC difference
ROPE = 0.01
#: the prior's strength s (a pseudo-observation at zero difference)
PRIOR_STRENGTH = 0.5
#: posterior samples drawn
SAMPLES = 20_000


@dataclass(frozen=True)
class BayesianSignedRank:
    """Posterior probabilities that the first detector is practically worse, equivalent, better."""

    n: int
    rope: float
    left: float
    equivalent: float
    right: float

    def decision(self, level: float = 0.95) -> str:
        """``"better"``, ``"equivalent"``, ``"worse"`` where a probability exceeds ``level``, else ``""``."""
        for name, p in (("better", self.right), ("equivalent", self.equivalent), ("worse", self.left)):
            if p > level:
                return name
        return ""


def bayesian_signed_rank(a, b, rope: float = ROPE, prior_strength: float = PRIOR_STRENGTH,
                         samples: int = SAMPLES, seed: int = 0) -> BayesianSignedRank:
    """The Bayesian signed-rank test of ``a - b`` over the tasks where both are defined.

    Parameters
    ----------
    a, b : array-like of shape (n_tasks,)
        One value a task for each detector (NaN: not completed).
    rope : float, default=0.01
        Half-width of the region of practical equivalence.
    prior_strength : float, default=0.5
        Weight ``s`` of the prior's pseudo-observation at zero difference.
    samples : int, default=20000
    seed : int, default=0
        Seed of the posterior samples.

    Examples
    --------
    >>> r = bayesian_signed_rank([0.80, 0.71, 0.92], [0.801, 0.709, 0.92])
    >>> r.equivalent
    1.0
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    shared = ~np.isnan(a) & ~np.isnan(b)
    z = np.r_[0.0, a[shared] - b[shared]]
    if not rope >= 0 or not prior_strength > 0:
        raise ValueError(f"rope must be >= 0 and prior_strength > 0; got {rope!r}, {prior_strength!r}.")
    walsh = z[:, None] + z[None, :]
    regions = (walsh < -2 * rope, np.abs(walsh) <= 2 * rope, walsh > 2 * rope)
    rng = np.random.default_rng(seed)
    w = rng.dirichlet(np.r_[prior_strength, np.ones(z.size - 1)], size=samples)
    # theta = w^T M w for each region's indicator matrix M
    theta = np.stack([np.einsum("si,ij,sj->s", w, m.astype(float), w) for m in regions], axis=1)
    winner = np.bincount(np.argmax(theta, axis=1), minlength=3) / samples
    return BayesianSignedRank(int(shared.sum()), float(rope), *(float(x) for x in winner))
