"""Wang & Hsu's (1990) habituating synapse with long-term memory.

The efficacy ``y`` of a synapse is coupled with a second variable ``z``, the
*speed of recovery*:

    tau * dy/dt = alpha * z * (y0 - y) - beta * y * S                     (1)
          dz/dt = gamma * z * (z - l) * S                                 (2)

``S`` is the stimulus, ``y0`` the unhabituated efficacy. Equation (1) is a
habituation term proportional to ``y`` and a recovery term whose rate
``alpha * z`` is itself learned. Equation (2) is a logistic decay: while the
synapse is stimulated, ``z`` falls from ``z0`` (< ``l``) towards 0 along an
inverse S-shaped curve, and without stimulus it stays where it is. So every
exposure leaves a trace, a lower ``z``, which

- lowers the level the efficacy settles at, ``alpha z y0 / (alpha z + beta S)``;
- slows recovery, so that the synapse stays habituated for longer.

A stimulus habituated to before is therefore re-habituated faster after the
synapse has recovered: long-term memory, which Stanley's model in
:mod:`novelty.habituation.stanley` does not have (its state is ``y`` alone, so
a recovered synapse is the same as a fresh one). ``tau`` scales equation (1)
only, as in the form reviewed by Marsland (2003): a neighbour's ``z`` falls as
fast as the winner's when both receive the same ``S``.

Solutions used
--------------
Under a constant stimulus, equation (2) has the closed form (with
``k = gamma * l * S`` and ``q = z(t) / l``)

    r = q + (1 - q) * exp(k * h)                                          (3)
    z(t + h) = z(t) / r
    integral of z over [t, t + h] = l * h - ln(r) / (gamma * S)           (4)

(evaluated as ``D / (gamma S)`` with ``D = k h - ln r``, which keeps its
precision for weak stimuli and long steps)

and at ``S = 0``, ``z`` is constant and (1) is linear:

    y(t + h) = y0 + (y(t) - y0) * exp(-alpha * z * h / tau)               (5)

Two discretisations:

- ``method="euler"`` (default, one step per scan as for Stanley): the explicit
  Euler step of (1)-(2) with both right-hand sides at the old values,

      y <- y + (h / tau) * (alpha * z * (y0 - y) - beta * y * S)         (6)
      z <- z + h * gamma * z * (z - l) * S

  with ``h = 1``; an elapsed time ``dt > 1`` is ``ceil(dt)`` equal sub-steps,
  so dt = 2 is exactly two scans.
- ``method="exact"`` (irregular timestamps): ``z`` from (3)-(4), exactly. For
  ``y``, equation (1) with ``z`` replaced by its exact mean over the step,
  ``A = alpha * (integral of z) / tau`` and ``B = beta * S * h / tau``:

      y_inf = y0 * A / (A + B)
      y(t + h) = y_inf + (y(t) - y_inf) * exp(-(A + B))                   (7)

  which is exact when ``S = 0`` (then it is (5)) or ``beta = 0``, so those
  cases take one step of any length. Otherwise (7) is applied on a fixed
  grid of sub-steps of length 1/8 (second order: with the defaults, within
  5e-6 of a fine numerical solution after 40 scans of stimulus), and because
  the grid is fixed, one step of dt = 2 is the same arithmetic as two of dt = 1.

Long gaps
---------
Up to 1024 sub-steps both methods iterate as above. Beyond (a gap in the
timestamps), the sub-steps stop as soon as the state has settled, and the
rest of the gap is done in closed form:

- ``z`` no longer changes (S = 0, gamma = 0, z = l, or z at its floor):
  with ``z`` constant each sub-step is a linear map of ``y``, whose n-fold
  power is ``y_inf + (y - y_inf) * rho ** n`` (Euler: ``rho = 1 - (h / tau)
  (alpha z + beta S)``; exact: ``rho = exp(-(A + B))``), so the closed form
  is the same recursion, to rounding;
- or ``alpha z <= 2**-53 * beta S`` for every unit: the recovery term is
  below the rounding of the habituation term, so ``y_inf <= 2**-53 y0`` and
  freezing ``z`` in ``y``'s map changes ``y`` by at most ``2**-53 y0``; ``z``
  itself follows its own closed form (Euler, where ``z - l`` rounds to
  ``-l``: ``z (1 - h gamma l S) ** n``; exact: equation (3) over the rest).

A gap then costs a number of sub-steps that depends on the parameters, not
on its length: ``z`` takes about ``(ln(1 / (l - z0)) + 37) / (gamma l S)``
units of time to fall that far, with the defaults 749 Euler sub-steps or
6127 exact ones. A very small ``gamma`` makes it long.

Defaults
--------
Wang (1993) fitted the model to toads' habituation over minutes to weeks;
those values are not reproduced here (not verified, see below). The defaults are
chosen to show the effect on the time scale of Marsland et al. (2000), tens
of scans: the paper's ``tau`` (3.33 winner, 14.3 neighbours) and
``alpha = 1.05``, with ``beta = 2``, ``gamma = 0.05``, ``z0 = 0.9``, ``l = 1``.
Then, with ``others="forget"``: a first exposure of 20 scans takes 16 scans
to bring the efficacy below 0.3 (and ``z`` from 0.9 to 0.77); after a
recovery of 200 scans the efficacy is back to 1.0, and the second exposure
takes 3 scans (16, then 5, with ``method="exact"``). Stanley's synapse takes 4
scans both times. Early in a first exposure the efficacy levels off near
``alpha z0 / (alpha z0 + beta) = 0.32``, then sinks as ``z`` falls, towards
0 under a very long stimulus.

What could and could not be verified
------------------------------------
Equations (1)-(2) are the form this project was given, attributed to
Marsland's (2003) review. The structure agrees with Wang's (1993) account of the same model, as
its abstract describes it: two interacting equations, one for the synaptic
weight and one for the speed of recovery, the latter an inverse S-shaped
curve whose high values mean fast recovery (short-term habituation) and low
values slow recovery (long-term habituation), which (2) is. The original
papers were not at hand, so these were not verified: the exact typography of
the constant ``l`` (it may be the number 1 in the original; the default
``l = 1`` makes both readings agree), whether Wang & Hsu's ``tau`` also
multiplies (2), whether ``z`` recovers slowly without stimulus (here it
does not), and their parameter values.

References
----------
Wang, D. & Hsu, C. (1990). SLONN: a simulation language for modeling of
neural networks. Simulation, 55, 69-93.

Wang, D. (1993). A neural model of synaptic plasticity underlying short-term
and long-term habituation. Adaptive Behavior, 2, 111-129.

Marsland, S. (2003). Novelty detection in learning systems. Neural Computing
Surveys, 3, 157-195 (the review of habituation models; equations (1)-(2)).

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000 (the time scale and tau).

One module although it is long (nearly half of it documentation): the two
equations, their closed forms and the Euler and exact integrators are checked
against each other in one place; the compiled steps are in ``_wang_hsu_steps``.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._component import KernelSpec, StateError
from .._validation import Interval, Options
from .base import Synapse

__all__ = ["WangHsuSynapse", "euler_advance", "exact_advance"]

#: Below this k = gamma l S h, a recovery step changes nothing in double
#: precision (relative changes of order k < 1e-17).
_NEGLIGIBLE_RATE = 1e-17

#: sub-step length of method="exact" under a stimulus (a divisor of 1, so the
#: grid of one step of dt = n is that of n steps of dt = 1)
_EXACT_SUBSTEP = 0.125

#: the least speed of recovery z (the smallest normal float): z never reaches 0
_Z_FLOOR = np.finfo(float).tiny

#: sub-steps iterated whatever happens; beyond, a long gap ends in closed form
#: once the state has settled (module docstring, "Long gaps")
_MAX_SUBSTEPS = 1024


def _n_substeps(span: float) -> float:
    """ceil(span), at least 1, as a float (exact: from 2**52 up every float is an integer)."""
    return max(1.0, float(math.ceil(span))) if span < 4503599627370496.0 else span


# The model's equations, as functions of a group of synapses (arrays ``y``, ``z``)
# under one stimulus: the reference runs them with numpy, the kernels compile
# them (novelty.habituation._wang_hsu_steps), so that the two cannot drift apart.
def euler_advance(y, z, s, tau, dt, alpha, beta, gamma, y0, l):  # noqa: E741
    """``(y, z)`` after ``dt`` of equation (6) in ceil(dt) sub-steps (a long gap: "Long gaps")."""
    n_sub = _n_substeps(dt)
    h = dt / n_sub
    long_gap = n_sub > _MAX_SUBSTEPS
    done = 0
    while done < n_sub:
        y_next = y + (h / tau) * (alpha * z * (y0 - y) - beta * y * s)
        # z > 0 always (z = 0 is no state a model file may hold): at the
        # smallest normal float it stops, as in the exact solution
        z_next = np.maximum(z + h * gamma * z * (z - l) * s, _Z_FLOOR)
        done += 1
        if long_gap and settled(z, z_next, s, alpha, beta):
            rest = n_sub - done
            c = h / tau
            rate = c * (alpha * z_next + beta * s)
            y_inf = level(c * alpha * z_next * y0, rate, y_next)
            y_end = y_inf + (y_next - y_inf) * (1.0 - rate) ** rest
            if not np.array_equal(z, z_next):
                z_next = np.maximum(z_next * (1.0 - h * gamma * l * s) ** rest, _Z_FLOOR)
            return y_end, z_next
        y, z = y_next, z_next
    return y, z


def settled(z, z_next, s, alpha, beta):
    """Whether the rest of a long gap may be done in closed form (module docstring)."""
    if np.array_equal(z, z_next):
        return True
    return beta * s > 0 and bool(np.all(alpha * z_next <= 2.0**-53 * beta * s))


def level(recovery, total, y):
    """y_inf = recovery / total; where total vanishes nothing moves, so y itself."""
    return np.where(total > 0, recovery / np.where(total > 0, total, 1.0), y)


def exact_advance(y, z, s, tau, dt, alpha, beta, gamma, y0, l):  # noqa: E741
    """``(y, z)`` after ``dt`` by equations (3)-(7) (a long gap: "Long gaps").

    At ``q = 1`` it takes ``log(0) = -inf`` (numpy warns of it; the reference
    silences that).
    """
    if dt <= 0:
        return y, z
    coupled = s > 0 and beta > 0
    n_sub = _n_substeps(dt / _EXACT_SUBSTEP - 1e-9) if coupled else 1.0
    h = dt / n_sub
    b = beta * s * h / tau
    long_gap = n_sub > _MAX_SUBSTEPS
    done = 0
    while done < n_sub:
        z_next, z_integral = recovery_step(z, s, h, gamma, l)
        a = (alpha / tau) * z_integral
        total = a + b
        # total > 0 but for z and b both vanishing, when nothing moves
        y_inf = level(y0 * a, total, y)
        y = y_inf + (y - y_inf) * np.exp(-total)
        done += 1
        if long_gap and settled(z, z_next, s, alpha, beta):
            rest = n_sub - done
            y = y_inf + (y - y_inf) * np.exp(-total * rest)
            if not np.array_equal(z, z_next):
                z_next = recovery_step(z_next, s, h * rest, gamma, l)[0]
            return y, z_next
        z = z_next
    return y, z


def recovery_step(z, s, h, gamma, l):  # noqa: E741
    """z after ``h`` under stimulus ``s`` and its integral over the step (equations 3-4)."""
    k = gamma * l * s * h
    if k < _NEGLIGIBLE_RATE:
        # z moves by a relative O(k) and its integral is z h (1 - O(k)): both
        # are exact in double precision here, and D / (gamma S) below would
        # divide by a product that underflows for a subnormal stimulus.
        return z, z * h
    q = np.minimum(z / l, 1.0)
    # D = k - ln(r) = -ln((1 - q) + q e^-k) >= 0, so that the integral is D / (gamma S)
    # and z(t + h) = z e^(D - k); log1p where D is small (weak stimulus, small z),
    # log-add-exp where it is large (q near 1, long steps).
    x = -q * np.expm1(-k)
    d = np.where(x < 0.5, -np.log1p(-np.minimum(x, 0.5)),
                 -np.logaddexp(np.log1p(-q), np.log(q) - k))
    z_next = np.maximum(z * np.exp(d - k), _Z_FLOOR)
    return z_next, d / (gamma * s)


class WangHsuSynapse(Synapse):
    """Wang & Hsu's habituating synapse with long-term memory.

    tau dy/dt = alpha z (y0 - y) - beta y S, and dz/dt = gamma z (z - l) S.

    Parameters
    ----------
    tau_winner : float, default=3.33
        Time constant of the winner's efficacy (equation 1).
    tau_neighbour : float, default=14.3
        Time constant of the neighbours' efficacy.
    alpha : float, default=1.05
        Recovery rate, scaled by the speed of recovery ``z``.
    beta : float, default=2.0
        Habituation rate.
    gamma : float, default=0.05
        Rate at which stimulation lowers the speed of recovery (equation 2).
    y0 : float, default=1.0
        Efficacy of an unhabituated synapse.
    z0 : float, default=0.9
        Speed of recovery of a fresh synapse; must be <= ``l``.
    l : float, default=1.0
        Upper fixed point of equation (2); ``z`` falls while ``z < l``.
    others : {"hold", "forget"}, default="hold"
        Rule for units outside the winning neighbourhood: no input, or
        S = 0 (they recover at the rate their own ``z`` allows).
    tau_forget : float or None, default=None
        Time constant of forgetting; ``tau_neighbour`` when None.
    method : {"euler", "exact"}, default="euler"
        Unit Euler steps (equation 6) or the time-aware solution (3)-(7).

    Attributes
    ----------
    efficacy_ : ndarray of shape (n_units,)
        Current efficacy ``y`` of each synapse.
    recovery_ : ndarray of shape (n_units,)
        Current speed of recovery ``z`` of each synapse (the long-term memory).

    References
    ----------
    Wang & Hsu (1990); Wang (1993); Marsland (2003), the review's equations
    for this model; see the module docstring for what was verified.

    Examples
    --------
    >>> syn = WangHsuSynapse().initialize(1)
    >>> syn.step(0, [])
    >>> round(float(syn.efficacy_[0]), 4), round(float(syn.recovery_[0]), 4)
    (0.3994, 0.8955)
    """

    _per_unit = ("efficacy_", "recovery_")

    _kernel = KernelSpec(
        steps="novelty.habituation._wang_hsu_steps",
        params=("alpha", "beta", "gamma", "y0", "z0", "l", "method"),
        arrays=("efficacy_", "recovery_"),
    )

    _parameter_rules = {
        **Synapse._common_rules,
        "alpha": Interval(numbers.Real, 0, None, closed="neither"),
        "beta": Interval(numbers.Real, 0, None, closed="left"),
        "gamma": Interval(numbers.Real, 0, None, closed="left"),
        "y0": Interval(numbers.Real, 0, None, closed="neither"),
        "z0": Interval(numbers.Real, 0, None, closed="neither"),
        "l": Interval(numbers.Real, 0, None, closed="neither"),
        "method": Options(("euler", "exact")),
    }

    def __init__(
        self,
        tau_winner=3.33,
        tau_neighbour=14.3,
        alpha=1.05,
        beta=2.0,
        gamma=0.05,
        y0=1.0,
        z0=0.9,
        l=1.0,  # noqa: E741 (the name of the constant in the equations)
        others="hold",
        tau_forget=None,
        method="euler",
    ):
        self.tau_winner = tau_winner
        self.tau_neighbour = tau_neighbour
        self.alpha = alpha
        self.beta = beta
        self.gamma = gamma
        self.y0 = y0
        self.z0 = z0
        self.l = l
        self.others = others
        self.tau_forget = tau_forget
        self.method = method

    def _validate_params(self) -> None:
        super()._validate_params()
        name = type(self).__name__
        if self.z0 > self.l:
            # z above l grows without bound under stimulation (equation 2).
            raise ValueError(
                f"The 'z0' parameter of {name} must be <= l ({self.l}). Got {self.z0} instead."
            )
        if self.method != "euler":
            return
        # A unit Euler step must not overshoot: y stays >= 0 while
        # (alpha z + beta S) / tau <= 1, and z stays > 0 while gamma l S < 1
        # (for stimuli S <= 1).
        fastest = self.alpha * self.l + self.beta
        taus = {"tau_winner": (self.tau_winner, fastest), "tau_neighbour": (self.tau_neighbour, fastest)}
        if self.tau_forget is not None:
            taus["tau_forget"] = (self.tau_forget, self.alpha * self.l)
        for key, (tau, low) in taus.items():
            if tau < low:
                raise ValueError(
                    f"The '{key}' parameter of {name} must be >= {low:g} for method='euler' "
                    f"(alpha * l{' + beta' if low == fastest else ''}; a larger step overshoots). "
                    f"Got {tau} instead; use method='exact' for fast time constants."
                )
        if self.gamma * self.l >= 1:
            raise ValueError(
                f"The 'gamma' parameter of {name} must be < 1 / l ({1 / self.l:g}) for "
                f"method='euler' (a larger step makes z negative). Got {self.gamma} instead."
            )

    @property
    def resting_efficacy(self) -> float:
        """The efficacy's limit under S = 1: 0 once z can fall, else alpha z0 y0 / (alpha z0 + beta)."""
        if self.gamma > 0 and self.z0 < self.l:
            return 0.0
        a = self.alpha * self.z0
        return float(self.y0 * a / (a + self.beta))

    def _fresh(self, n: int) -> dict[str, np.ndarray]:
        return {"efficacy_": np.full(n, float(self.y0)), "recovery_": np.full(n, float(self.z0))}

    # ---------------------------------------------------------------- the model
    def _advance(self, rows: np.ndarray, stimulus: float, tau: float, dt: float) -> None:
        y = self.efficacy_[rows]
        z = self.recovery_[rows]
        args = (stimulus, tau, dt, self.alpha, self.beta, self.gamma, self.y0, self.l)
        if self.method == "euler":
            y, z = euler_advance(y, z, *args)
        else:
            with np.errstate(divide="ignore"):  # log(1 - q) = -inf at q = 1 is meant
                y, z = exact_advance(y, z, *args)
        self.efficacy_[rows] = y
        self.recovery_[rows] = z

    def efficacy_range(self, stimulus: float = 1.0) -> tuple[float, float]:
        """``[0, y0]``: ``y`` relaxes towards ``y0 A / (A + B)``, which lies in it. The
        Euler step keeps to it for stimuli up to 1 only (see ``_validate_params``)."""
        if self.method == "euler" and stimulus > 1:
            return super().efficacy_range(stimulus)
        return 0.0, float(self.y0)

    def _check_state(self) -> None:
        super()._check_state()
        z = self.recovery_
        if np.any(z <= 0) or np.any(z > self.l * (1 + 1e-12)):
            raise StateError(f"{type(self).__name__}.recovery_ must lie in (0, l = {self.l}].")
