"""Habituation at two time scales: Staddon & Higa's (1996) cascade of leaky integrators.

Staddon & Higa's multiple-time-scale (MTS) model of habituation passes the
stimulus through a series of thresholded leaky integrators. Each unit keeps a
memory ``V`` of what reached it and passes on what its memory does not
cancel; the response is what passes the last unit. Earlier units are faster
than later ones, so under closely spaced stimuli the fast unit cancels
nearly all of the stimulus and the slow one learns little, while under
widely spaced stimuli the fast memory decays between them and the slow one
learns more: recovery is slower after spaced training than after massed
training, and slower the longer the training (rate sensitivity), which a
single integrator (Stanley's synapse) cannot show.

Here the cascade has two units, a fast memory ``F`` and a slow memory ``L``,
in the difference-equation form of the MTS model, one step per scan:

    F(t+1) = a_f F(t) + b_f S(t)                                          (1)
    L(t+1) = a_s L(t) + b_s X(t),      X(t) = max(0, S(t) - F(t))         (2)

and the efficacy of the synapse is the response it would give to a probe of
strength ``y0``, what passes both units:

    y = max(0, y0 - F - L)                                                (3)

The coefficients are those of the explicit Euler step (step ``h``) of

    tau dF/dt = c_f S - F,        r tau dL/dt = c_s X - L                 (4)

that is ``a_f = 1 - h / tau``, ``b_f = c_f h / tau``, ``a_s = 1 - h / (r
tau)``, ``b_s = c_s h / (r tau)``: ``tau`` is the schedule's time constant
(the winner's, a neighbour's or forgetting's), the slow memory's is ``r``
times it (``slowness``), and the gains ``c_f`` (``fast_gain``) and ``c_s``
(``slow_gain``) are what each memory settles at per unit of its input. The
fast unit alone (``c_s = 0``) is Stanley's synapse: with ``y = y0 - F``,
``tau dy/dt = (y0 - y) - c_f S``, which is Stanley's equation with
``alpha = 1`` and the stimulus scaled by ``c_f``.

An elapsed time ``dt`` is ``n = ceil(dt)`` steps of ``h = dt / n``, so
``dt = 2`` is exactly two scans. With ``tau >= 1`` (checked) every ``a`` lies
in [0, 1), so each step moves each memory towards its target without passing
it: ``0 <= F <= c_f S_max`` and ``0 <= L <= c_s S_max``, and the efficacy
lies in ``[max(0, y0 - (c_f + c_s) S_max), y0]``.

Solutions used and tested
-------------------------
From a fresh synapse (``F = L = 0``) under a constant stimulus ``S`` with
``c_f <= 1`` (checked), ``F`` rises to ``c_f S <= S``, so the threshold of
(2) never cuts and, with ``h = 1``::

    F(n) = c_f S (1 - a_f^n)                                              (5)
    L(n) = c_s (1 - c_f) S (1 - a_s^n)
           + b_s c_f S (a_s^n - a_f^n) / (a_s - a_f)      (a_s != a_f)   (6)

so the efficacy settles at ``y0 - c_f S - c_s (1 - c_f) S`` (the resting
efficacy, at ``S = 1``): under massed stimulation the slow memory receives
only the ``(1 - c_f) S`` the fast one lets through. If ``r >= 1 / (1 -
c_f)`` the slow memory never overshoots its input, ``L(n) <= c_s X(n)``
(by induction on ``D = c_s X - L``, ``D(n) = c_s S (a_s^n - (h c_f / tau)
(a_s^n - a_f^n) / (a_s - a_f)) >= 0``), so both memories rise and the
efficacy falls monotonically. Without stimulus both memories decay
geometrically, ``F a_f^n`` and ``L a_s^n``: the efficacy recovers, the
faster the less of the memory is slow.

Long gaps
---------
Up to 1024 steps are iterated. Beyond (a gap in the timestamps), the steps
go on only until the threshold of (2) can no longer switch: ``F <= S``
(then ``X = S - F`` for good, as ``F`` moves towards ``c_f S <= S``) or
``c_f S >= S`` (then ``X = 0`` for good). Equations (1)-(2) are then one
affine map of ``(F, L)``, and its power for the remaining steps is taken by
repeated squaring: a gap costs about ``log2(n)`` compositions, not ``n``
steps.

What could and could not be verified
------------------------------------
The cascade of thresholded integrators, faster units first, the response as
the stimulus minus the summed memories, and rate sensitivity as its purpose
are as the abstracts of Staddon & Higa (1996) and Staddon, Chelaru & Higa
(2002) describe them; the papers themselves were not at hand, so their
exact notation and fitted parameter values are not reproduced. The
parametrisation by a time constant, a slowness and two gains (equation 4),
the efficacy as the response to a probe (3), and the defaults are ours,
chosen so that the fast unit reduces to Stanley's synapse and the schedule's
time constants keep their meaning.

References
----------
Staddon, J. E. R. & Higa, J. J. (1996). Multiple time scales in simple
habituation. Psychological Review, 103(4), 720-733.

Staddon, J. E. R., Chelaru, I. M. & Higa, J. J. (2002). Habituation, memory
and the brain: the dynamics of interval timing. Behavioural Processes,
57(2-3), 71-88.

Stanley, J. C. (1976). Computer simulation of a model of habituation.
Nature, 261, 146-148 (the single integrator the fast unit reduces to).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._component import KernelSpec, StateError
from .._validation import Interval
from .base import Synapse

__all__ = ["StaddonHigaSynapse", "cascade_steps", "efficacy"]

#: steps iterated one by one; beyond, the rest of a long gap by the power of its affine map
MAX_STEPS = 1024


def cascade_steps(fast, slow, stimulus, tau, dt, fast_gain, slow_gain, slowness):
    """``(F, L)`` of one synapse after ``dt`` under a constant stimulus: equations (1)-(2).

    Plain float arithmetic, so that the reference (a loop over units) and the
    compiled kernels run the same operations in the same order.
    """
    n = max(1.0, float(math.ceil(dt))) if dt < 4503599627370496.0 else dt
    h = dt / n
    a_f = 1.0 - h / tau
    b_f = fast_gain * h / tau
    a_s = 1.0 - h / (slowness * tau)
    b_s = slow_gain * h / (slowness * tau)
    done = 0.0
    while done < n:
        if n > MAX_STEPS and (fast <= stimulus or fast_gain * stimulus >= stimulus):
            return affine_power(fast, slow, stimulus, a_f, b_f, a_s, b_s, n - done)
        passed = max(0.0, stimulus - fast)
        fast, slow = a_f * fast + b_f * stimulus, a_s * slow + b_s * passed
        done += 1.0
    return fast, slow


def affine_power(fast, slow, stimulus, a_f, b_f, a_s, b_s, steps):
    """``(F, L)`` after ``steps`` of (1)-(2) once the threshold cannot switch (module
    docstring, "Long gaps"), by repeated squaring of the affine map.

    The map is ``F <- a_f F + b_f S``, ``L <- a_s L - c F + c S`` with ``c = b_s`` while
    ``F <= S`` (the slow unit receives ``S - F``) and ``c = 0`` otherwise. It is held
    as the lower-triangular matrix ``[[m11, 0], [m21, m22]]`` and the offset ``(v1, v2)``.
    """
    c = b_s if fast <= stimulus else 0.0
    # the map of one step, and the accumulated map of the steps taken so far (identity)
    m11, m21, m22, v1, v2 = a_f, -c, a_s, b_f * stimulus, c * stimulus
    r11, r21, r22, w1, w2 = 1.0, 0.0, 1.0, 0.0, 0.0
    k = steps
    while k >= 1.0:
        if k % 2.0 == 1.0:  # accumulated <- one-power o accumulated
            r11, r21, r22, w1, w2 = (m11 * r11, m21 * r11 + m22 * r21, m22 * r22,
                                     m11 * w1 + v1, m21 * w1 + m22 * w2 + v2)
        k = (k - k % 2.0) / 2.0  # float halving, exact for any integer-valued float
        m11, m21, m22, v1, v2 = (m11 * m11, m21 * m11 + m22 * m21, m22 * m22,
                                 m11 * v1 + v1, m21 * v1 + m22 * v2 + v2)
    new_fast = r11 * fast + w1
    new_slow = r21 * fast + r22 * slow + w2
    # in exact arithmetic both stay >= 0 (each step is a convex combination)
    return max(0.0, new_fast), max(0.0, new_slow)


def efficacy(fast, slow, y0):
    """Equation (3): what passes both units of a probe of strength ``y0``."""
    return max(0.0, y0 - fast - slow)


class StaddonHigaSynapse(Synapse):
    """A habituating synapse with a fast and a slow memory in cascade (Staddon & Higa 1996).

    F <- a_f F + b_f S;  L <- a_s L + b_s max(0, S - F);  y = max(0, y0 - F - L).

    Parameters
    ----------
    tau_winner : float, default=3.33
        Time constant of the winner's fast memory (the slow one's is ``slowness`` times it).
    tau_neighbour : float, default=14.3
        Time constant of the neighbours' fast memory.
    fast_gain : float, default=0.8
        ``c_f``: the level the fast memory settles at per unit of stimulus, in (0, 1].
    slow_gain : float, default=0.8
        ``c_s``: the level the slow memory settles at per unit of what passes the fast one.
        0 leaves the fast memory alone (Stanley's synapse with alpha = 1).
    slowness : float, default=10.0
        ``r``: the slow memory's time constant over the fast one's, at least 1.
    y0 : float, default=1.0
        Efficacy of an unhabituated synapse (the strength of the probe).
    others : {"hold", "forget"}, default="hold"
        Rule for units outside the winning neighbourhood: no input (no time passes
        for them), or S = 0 (both memories decay, the slow one ``slowness`` times slower).
    tau_forget : float or None, default=None
        Time constant of the fast memory's decay; ``tau_neighbour`` when None.

    Attributes
    ----------
    efficacy_ : ndarray of shape (n_units,)
        Current efficacy ``y`` of each synapse (equation 3).
    fast_memory_ : ndarray of shape (n_units,)
        The fast memory ``F`` of each synapse.
    slow_memory_ : ndarray of shape (n_units,)
        The slow memory ``L`` of each synapse.

    References
    ----------
    Staddon & Higa (1996), the multiple-time-scale model; Staddon, Chelaru &
    Higa (2002); see the module docstring for what was verified.

    Examples
    --------
    >>> syn = StaddonHigaSynapse().initialize(1)
    >>> syn.step(0, [])
    >>> round(float(syn.fast_memory_[0]), 4), round(float(syn.slow_memory_[0]), 4)
    (0.2402, 0.024)
    >>> round(syn.resting_efficacy, 4)
    0.04
    """

    _per_unit = ("efficacy_", "fast_memory_", "slow_memory_")

    _kernel = KernelSpec(
        steps="novelty.habituation._staddon_higa_steps",
        params=("fast_gain", "slow_gain", "slowness", "y0"),
        arrays=("efficacy_", "fast_memory_", "slow_memory_"),
    )

    _parameter_rules = {
        **Synapse._common_rules,
        "fast_gain": Interval(numbers.Real, 0, 1, closed="right"),
        "slow_gain": Interval(numbers.Real, 0, None, closed="left"),
        "slowness": Interval(numbers.Real, 1, None, closed="left"),
        "y0": Interval(numbers.Real, 0, None, closed="neither"),
    }

    def __init__(
        self,
        tau_winner=3.33,
        tau_neighbour=14.3,
        fast_gain=0.8,
        slow_gain=0.8,
        slowness=10.0,
        y0=1.0,
        others="hold",
        tau_forget=None,
    ):
        self.tau_winner = tau_winner
        self.tau_neighbour = tau_neighbour
        self.fast_gain = fast_gain
        self.slow_gain = slow_gain
        self.slowness = slowness
        self.y0 = y0
        self.others = others
        self.tau_forget = tau_forget

    def _validate_params(self) -> None:
        super()._validate_params()
        taus = {"tau_winner": self.tau_winner, "tau_neighbour": self.tau_neighbour}
        if self.tau_forget is not None:
            taus["tau_forget"] = self.tau_forget
        for name, tau in taus.items():
            if tau < 1:
                # a_f = 1 - h / tau < 0 for a step of one scan: the memory would overshoot
                raise ValueError(
                    f"The '{name}' parameter of {type(self).__name__} must be >= 1 (one step "
                    f"a scan; a faster memory overshoots). Got {tau} instead."
                )

    @property
    def resting_efficacy(self) -> float:
        """``max(0, y0 - c_f - c_s (1 - c_f))``: the limit of (5)-(6) at S = 1."""
        return efficacy(float(self.fast_gain), float(self.slow_gain) * (1.0 - self.fast_gain),
                        float(self.y0))

    def efficacy_range(self, stimulus: float = 1.0) -> tuple[float, float]:
        """``[max(0, y0 - (c_f + c_s) stimulus), y0]``: each memory stays below its gain
        times the largest stimulus (module docstring)."""
        low = max(0.0, self.y0 - (self.fast_gain + self.slow_gain) * stimulus)
        return float(low), float(self.y0)

    def _fresh(self, n: int) -> dict[str, np.ndarray]:
        return {"efficacy_": np.full(n, float(self.y0)), "fast_memory_": np.zeros(n),
                "slow_memory_": np.zeros(n)}

    def _advance(self, rows: np.ndarray, stimulus: float, tau: float, dt: float) -> None:
        y, fast, slow = self.efficacy_, self.fast_memory_, self.slow_memory_
        gains = (float(self.fast_gain), float(self.slow_gain), float(self.slowness))
        for j in rows:
            f, s = cascade_steps(float(fast[j]), float(slow[j]), float(stimulus), float(tau),
                                 float(dt), *gains)
            fast[j], slow[j] = f, s
            y[j] = efficacy(f, s, float(self.y0))

    def _check_state(self) -> None:
        super()._check_state()
        name = type(self).__name__
        fast, slow = self.fast_memory_, self.slow_memory_
        if not (np.all(np.isfinite(fast)) and np.all(np.isfinite(slow))) or np.any(fast < 0) \
                or np.any(slow < 0):
            raise StateError(f"{name}.fast_memory_ and slow_memory_ must be finite and >= 0.")
        expected = np.maximum(0.0, self.y0 - fast - slow)
        if not np.array_equal(self.efficacy_, expected):
            raise StateError(f"{name}.efficacy_ must equal max(0, y0 - fast_memory_ - slow_memory_).")
