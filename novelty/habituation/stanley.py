"""Stanley's (1976) model of a habituating synapse, as used by Marsland et al. (2000).

The efficacy ``y`` of a synapse obeys

    tau * dy/dt = alpha * (y0 - y) - S                                   (1)

where ``S`` is the stimulus, ``y0`` the unhabituated efficacy, ``tau`` sets
the rate of habituation and ``alpha`` the rate of recovery. Under a constant
stimulus the solution relaxes exponentially to ``y_inf = y0 - S / alpha``:

    y(t + dt) = y_inf + (y(t) - y_inf) * exp(-alpha * dt / tau)          (2)

so held at S = 1 the efficacy falls to ``y0 - 1/alpha`` (0.0476 with the
paper's alpha = 1.05) and never below; at S = 0 it recovers towards ``y0``.

Two discretisations:

- ``method="euler"`` (default): the explicit Euler step with unit time step,

      y <- y + (dt / tau) * (alpha * (y0 - y) - S)                      (3)

  which from y = 1 with tau = 3.33 gives 0.6997, 0.4941, 0.3533, ... An
  elapsed time dt > 1 is integrated as n = ceil(dt) equal sub-steps of
  h = dt / n, so dt = 2 is exactly two scans' worth of steps. Each sub-step
  is the linear map ``y - y_inf <- (1 - alpha h / tau) (y - y_inf)``, so n of
  them are

      y <- y_inf + (y - y_inf) * (1 - alpha h / tau) ** n               (4)

  which :func:`euler_steps` uses beyond 1024 sub-steps (a long gap in the
  timestamps costs one step, not ceil(dt)); up to 1024 it iterates (3), so
  the results of ordinary steps are those of the loop, bit for bit.
- ``method="exact"``: equation (2), exact for any dt (irregular timestamps);
  from y = 1 with tau = 3.33 it gives 0.7424, 0.5545, 0.4174, ...

The paper does not say how it integrated. Its Table 1 fits neither scheme
alone: 0.35 is the third Euler winner step (exact needs two winner and
seven neighbour steps), but 0.42, its most frequent maximum, is the third
exact winner step and no count of Euler winner and neighbour steps
(``novelty reproduce --experiment maxima``; docs/reproduction.md). The
default stays Euler.

References
----------
Stanley, J. C. (1976). Computer simulation of a model of habituation.
Nature, 261, 146-148.

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, equation (1) and section 2.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._component import KernelSpec
from .._validation import Interval, Options
from .base import Synapse

__all__ = ["StanleySynapse", "euler_steps", "exact_step"]

#: sub-steps :func:`euler_steps` iterates one by one; beyond, equation (4)
MAX_EULER_SUBSTEPS = 1024


def euler_steps(y, stimulus, tau, dt, alpha, y0):
    """Efficacy ``y`` (a float or an array) after ``dt`` under equation (3), in ceil(dt) sub-steps.

    The reference and the compiled kernels both run this function, so that
    the two cannot drift apart. Up to ``MAX_EULER_SUBSTEPS`` sub-steps it
    iterates (3) (one sub-step, ``dt <= 1``, written without the loop: the
    same operations, a few nanoseconds less a unit in the compiled loop); beyond, it applies their closed form (4), the same
    recursion to rounding, in constant time (with ``tau >= alpha``, checked
    for ``method="euler"``, the factor ``1 - alpha h / tau`` lies in [0, 1)).
    """
    if dt <= 1.0:  # one sub-step of h = dt (the loop below, without its ceil and division)
        return y + (dt / tau) * (alpha * (y0 - y) - stimulus)
    if dt <= MAX_EULER_SUBSTEPS:
        n_sub = max(1, math.ceil(dt))
        h = dt / n_sub
        for _ in range(n_sub):
            y = y + (h / tau) * (alpha * (y0 - y) - stimulus)
        return y
    # from 2**52 up every float is an integer (and ceil would overflow an int64)
    n = dt if dt >= 4503599627370496.0 else float(math.ceil(dt))
    h = dt / n
    y_inf = y0 - stimulus / alpha
    return y_inf + (y - y_inf) * (1.0 - (h / tau) * alpha) ** n


def exact_step(y, stimulus, tau, dt, alpha, y0):
    """Efficacy ``y`` (a float or an array) after ``dt`` under equation (2), exactly.

    Like :func:`euler_steps`, run by the reference and compiled by the kernels.
    """
    y_inf = y0 - stimulus / alpha
    return y_inf + (y - y_inf) * math.exp(-alpha * dt / tau)


class StanleySynapse(Synapse):
    """Stanley's habituating synapse: tau dy/dt = alpha (y0 - y) - S.

    Parameters
    ----------
    tau_winner : float, default=3.33
        Time constant of the winner's synapse (fast habituation).
    tau_neighbour : float, default=14.3
        Time constant of the neighbours' synapses (slow habituation).
    alpha : float, default=1.05
        Recovery rate; the efficacy never falls below ``y0 - 1/alpha``.
    y0 : float, default=1.0
        Efficacy of an unhabituated synapse.
    others : {"hold", "forget"}, default="hold"
        Rule for units outside the winning neighbourhood: no input (the
        paper) or S = 0 (forgetting).
    tau_forget : float or None, default=None
        Time constant of forgetting; ``tau_neighbour`` when None.
    method : {"euler", "exact"}, default="euler"
        Explicit Euler step (equation 3) or exact solution (equation 2).

    Attributes
    ----------
    efficacy_ : ndarray of shape (n_units,)
        Current efficacy of each synapse.

    References
    ----------
    Stanley (1976); Marsland, Nehmzow & Shapiro (2000), equation (1).

    Examples
    --------
    >>> syn = StanleySynapse().initialize(1)
    >>> for _ in range(3):
    ...     syn.step(0, [])
    >>> [round(float(y), 4) for y in syn.efficacy_]
    [0.3533]
    >>> round(syn.resting_efficacy, 4)
    0.0476
    """

    _parameter_rules = {
        **Synapse._common_rules,
        "alpha": Interval(numbers.Real, 0, None, closed="neither"),
        "y0": Interval(numbers.Real, 0, None, closed="neither"),
        "method": Options(("euler", "exact")),
    }

    _kernel = KernelSpec(
        steps="novelty.habituation._stanley_steps",
        params=("alpha", "y0", "method"),
        arrays=("efficacy_",),
    )

    def __init__(
        self,
        tau_winner=3.33,
        tau_neighbour=14.3,
        alpha=1.05,
        y0=1.0,
        others="hold",
        tau_forget=None,
        method="euler",
    ):
        self.tau_winner = tau_winner
        self.tau_neighbour = tau_neighbour
        self.alpha = alpha
        self.y0 = y0
        self.others = others
        self.tau_forget = tau_forget
        self.method = method

    def _validate_params(self) -> None:
        super()._validate_params()
        if self.method == "euler":
            taus = {"tau_winner": self.tau_winner, "tau_neighbour": self.tau_neighbour}
            if self.tau_forget is not None:
                taus["tau_forget"] = self.tau_forget
            for name, tau in taus.items():
                # A unit Euler step with alpha/tau > 1 overshoots y_inf and oscillates.
                if tau < self.alpha:
                    raise ValueError(
                        f"The '{name}' parameter of StanleySynapse must be >= alpha "
                        f"({self.alpha}) for method='euler' (a larger step overshoots). "
                        f"Got {tau} instead; use method='exact' for fast time constants."
                    )

    @property
    def resting_efficacy(self) -> float:
        return float(self.y0 - 1.0 / self.alpha)

    def efficacy_range(self, stimulus: float = 1.0) -> tuple[float, float]:
        """``[y0 - stimulus / alpha, y0]``: each step moves ``y`` towards ``y_inf`` without
        passing it (equation 2, or equation 3 with ``h / tau * alpha <= 1``)."""
        return float(self.y0 - stimulus / self.alpha), float(self.y0)

    def _fresh(self, n: int) -> dict[str, np.ndarray]:
        return {"efficacy_": np.full(n, float(self.y0))}

    def _advance(self, rows: np.ndarray, stimulus: float, tau: float, dt: float) -> None:
        y = self.efficacy_[rows]
        if self.method == "exact":
            y = exact_step(y, stimulus, tau, dt, self.alpha, self.y0)
        else:
            y = euler_steps(y, stimulus, tau, dt, self.alpha, self.y0)
        self.efficacy_[rows] = y
