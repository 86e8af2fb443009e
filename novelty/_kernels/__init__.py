"""Compiled fast paths for the habituating filter, chosen per (clusterer, synapse) pair.

The readable numpy code (:func:`novelty.filter.learn_stream`, ``match``,
``winners``) is the reference; a kernel here is an optimisation that must
give the same winners, weights and efficacies bit for bit
(``tests/test_kernels.py`` checks it). The filter asks :func:`learner` and
:func:`scorer` for a kernel on every call and falls back to the reference
when they answer ``None``:

- the pair has no kernel: learning is compiled for ``SOM``,
  ``GrowingNeuralGas`` and ``GrowWhenRequired`` (with Stanley firing
  counters) with a ``StanleySynapse`` (exact types, since a subclass may
  change the arithmetic), batch scoring for ``SOM`` with any synapse;
- the state is not in the plain layout the kernel writes to in place;
- numba is missing or failed to compile (a ``RuntimeWarning``, once);
- the environment variable ``NOVELTY_NO_KERNELS`` is set to a non-empty value
  other than ``0`` when the first kernel is asked for (for comparisons).

Compiling in the background. numba is imported only when the first kernel
is asked for, so ``import novelty`` does not pay for it. Compiling a module
of kernels (one for the SOM, one for the growing networks, each on its
first use) takes seconds; numba caches the machine code on disk
(``cache=True``, in ``NUMBA_CACHE_DIR`` when set) and later processes load it
in a fraction of a second (at once, when the cache holds them). So that no
call waits for the compiler, a background thread has a child process compile
the module into the cache (numba's compiler would hold this process's GIL)
and then loads it from there; meanwhile learning runs the reference loop in small blocks and hands
over to the kernel, mid-stream, as soon as it is ready (the two give
identical states, so the hand-over is invisible in the results). A process
that ends early waits for the thread at exit, so that the cache gets written;
Ctrl-C during that wait stops the compiler and exits quietly with status 130.
The child runs isolated (``python -I``, in the package's folder): nothing in
the user's working directory or ``PYTHON*`` variables is imported or read.
:func:`wait` blocks until the kernels are ready (benchmarks, tests). Batch
scoring is :mod:`.scoring`: a float32 pre-filter with exact re-checks, on
threads (``NOVELTY_NUM_THREADS``, default: the usable cores).
"""

from __future__ import annotations

import atexit
import os
import sys
import threading
import warnings
from typing import Callable

import numpy as np

from ..clusterers.gng import GrowingNeuralGas
from ..clusterers.gwr import GrowWhenRequired
from ..clusterers.kmeans import OnlineKMeans
from ..clusterers.som import SOM
from ..habituation.stanley import StanleySynapse
from .scoring import score

__all__ = ["learner", "scorer", "kernels_enabled", "wait"]


#: what the compiling child runs: ``python -I -c _CHILD module path...``
_CHILD = "import importlib, sys; sys.path[:0] = sys.argv[2:]; importlib.import_module(sys.argv[1])"


class _Compiled:
    """One module of kernels: loaded at once when numba's disk cache holds it, else
    compiled by a child process that a background thread waits for, while the
    caller goes on with the reference."""

    def __init__(self, name: str):
        self.name = name
        self.module = None  # once ready
        self.failed = False  # numba missing, broken or disabled: never retried
        self.started = False
        self.thread: threading.Thread | None = None  # the background compiler, if one runs
        self.error: BaseException | None = None  # raised in the thread, warned about here
        self.child = None  # the compiling child process (a subprocess.Popen), while it runs

    def get(self):
        """The module if ready; else start compiling it (once) and return None."""
        if self.module is not None:
            return self.module
        if self.failed:
            return None
        if self.error is not None:
            self.failed = True
            warnings.warn(
                f"novelty: compiled kernels are unavailable ({type(self.error).__name__}: "
                f"{self.error}); using the reference numpy loops, which give the same results "
                "more slowly.",
                RuntimeWarning,
                stacklevel=4,
            )
            return None
        if not self.started:
            if os.environ.get("NOVELTY_NO_KERNELS", "") not in ("", "0"):
                self.failed = True
                return None
            self.started = True
            if self._cached():
                # Loading takes a fraction of a second: less than sharing the GIL
                # with a loader thread would cost the caller, so load now.
                self._compile()
                return self.get()
            # A daemon joined at exit by _wait_at_exit, not by the interpreter, which would
            # report Ctrl-C during that wait as a traceback and exit with status 0.
            self.thread = threading.Thread(target=self._compile, name=f"novelty-{self.name}",
                                           daemon=True)
            self.thread.start()
            atexit.register(self._wait_at_exit)
        return None

    def _wait_at_exit(self) -> None:
        try:
            if self.thread is not None:
                self.thread.join()
        except KeyboardInterrupt:
            child = self.child
            if child is not None and child.poll() is None:
                child.kill()
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (AttributeError, OSError, ValueError):
                    pass
            os._exit(130)  # 128 + SIGINT, as the command line returns for Ctrl-C

    def _compile(self) -> None:
        import importlib

        name = f"{__name__}.{self.name}"
        try:
            if name not in sys.modules and not self._cached():
                self._compile_in_child(name)
            self.module = importlib.import_module(name)  # loads what the child cached
        except BaseException as exc:  # ImportError, or numba/LLVM failing to compile or load
            self.error = exc

    def _cached(self) -> bool:
        """Whether numba's disk cache seems to hold this module's kernels (an index file).

        A stale index only costs speed: the import then compiles in this thread.
        """
        import glob

        cache_dir = os.environ.get("NUMBA_CACHE_DIR")
        # numba's cache: NUMBA_CACHE_DIR/<one folder per source folder>/, else __pycache__
        folders = (glob.glob(os.path.join(cache_dir, "*")) if cache_dir
                   else [os.path.join(os.path.dirname(os.path.abspath(__file__)), "__pycache__")])
        return any(glob.glob(os.path.join(f, f"{self.name}.*.nbi")) for f in folders)

    def _compile_in_child(self, name: str) -> None:
        """Compile in a child process, which leaves the machine code in numba's disk cache.

        In a thread of this process numba's compiler holds the GIL for long
        stretches: the main thread, learning with the reference meanwhile, was
        measured 40x slower. A child that fails leaves no cache; the import in
        the thread then compiles after all.

        The child is isolated (``-I``: neither the working directory nor
        ``PYTHONPATH`` nor user site-packages on its path) and runs in the
        folder that holds the package; it is given this process's absolute
        ``sys.path`` entries, so it imports the same numba and novelty that
        this process will, and never a module that happens to lie in the
        working directory.
        """
        import subprocess  # a local import: 3 ms of `import novelty` for a cold cache only

        if not sys.executable:
            return
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        path = [root] + [p for p in sys.path if p and os.path.isabs(p) and p != root]
        env = dict(os.environ)
        if env.get("NUMBA_CACHE_DIR"):  # the child runs elsewhere: a relative folder would move
            env["NUMBA_CACHE_DIR"] = os.path.abspath(env["NUMBA_CACHE_DIR"])
        self.child = subprocess.Popen([sys.executable, "-I", "-c", _CHILD, name, *path], cwd=root,
                                      env=env, stdin=subprocess.DEVNULL,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            self.child.wait()
        finally:
            self.child = None

    def wait(self, timeout: float | None = None):
        self.get()
        if self.thread is not None:
            self.thread.join(timeout)
        return self.get()

    @property
    def compiling(self) -> bool:
        return self.started and self.module is None and not self.failed and self.error is None


_SOM = _Compiled("_som_stanley")
_GROWING = _Compiled("_growing")
_NEAREST = _Compiled("_nearest")  # batch scoring (see .scoring)


def _after_fork_in_child() -> None:
    # A compiler thread does not survive fork(); a child forked while one was
    # running would wait for it forever, so it starts its own when it needs one.
    for compiled in (_SOM, _GROWING, _NEAREST):
        if compiled.module is None and compiled.error is None:
            compiled.started, compiled.thread = False, None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def kernels_enabled() -> bool:
    """Whether compiled kernels are in use (waits for them to be compiled)."""
    return wait() is not None


def wait(timeout: float | None = None):
    """Compile (or load) every module of kernels now and block until done.

    Returns the SOM module, or None when kernels are unavailable.
    """
    _GROWING.wait(timeout)
    _NEAREST.wait(timeout)
    return _SOM.wait(timeout)


def _plain(a, ndim: int) -> bool:
    # The kernels update state in place: it must be a plain, writable float64 array.
    if type(a) is not np.ndarray or a.ndim != ndim or a.dtype != np.float64:
        return False
    flags = a.flags
    return flags.c_contiguous and flags.writeable


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` as the kernel's signature wants it: C-contiguous, writable float64 (copied if not)."""
    if a.dtype == np.float64:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=np.float64, order="C")


def _som_ready(som, y) -> bool:
    W = getattr(som, "weights_", None)
    return (
        _plain(W, 2)
        and _plain(y, 1)
        and y.shape[0] == W.shape[0]
        and hasattr(som, "_table_radius")
    )


def _stanley_ready(syn, n_units: int) -> bool:
    y = getattr(syn, "efficacy_", None)
    return (type(syn) is StanleySynapse and _plain(y, 1) and y.shape[0] == n_units
            and syn.method in ("euler", "exact") and syn.others in ("hold", "forget"))


def _growing_ready(net, syn) -> bool:
    W = getattr(net, "weights_", None)
    A = getattr(net, "edge_ages_", None)
    if not (_plain(W, 2) and type(A) is np.ndarray and A.shape == (W.shape[0], W.shape[0])
            and _stanley_ready(syn, W.shape[0])):
        return False
    if type(net) is GrowWhenRequired:  # its firing counters are a Stanley bank too
        return _stanley_ready(getattr(net, "firing_", None), W.shape[0])
    return _plain(getattr(net, "errors_", None), 1)


def learner(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X, dt, stimulus) -> novelty``, or None.

    The function gives what ``learn_stream`` gives, state and all.
    """
    kind = type(clusterer)
    if kind is SOM:
        # the kernel shares one rate between the winner and its neighbours
        if type(synapse) is not StanleySynapse or clusterer.neighbour_learning_rate is not None or \
                not _som_ready(clusterer, getattr(synapse, "efficacy_", None)):
            return None
        compiled, kernel, handing_over = _SOM, _learn_som_stanley, _som_handing_over
    elif kind is GrowingNeuralGas or kind is GrowWhenRequired:
        if not _growing_ready(clusterer, synapse):
            return None
        compiled, kernel, handing_over = _GROWING, _learn_growing, _growing_handing_over
    else:
        return None
    if compiled.module is None and compiled.get() is None:
        return handing_over if compiled.compiling else None
    return kernel


#: clusterers whose winner is the first unit of least squared distance, ``match``
#: and ``winners`` alike: batch scoring is the same kernel for all of them
_NEAREST_UNIT = (SOM, GrowingNeuralGas, GrowWhenRequired, OnlineKMeans)


def scorer(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X, winners=None, distances=None) -> novelty``, or None.

    The novelty is ``efficacy_[winners(X)]``; ``winners`` (int64) and
    ``distances``, if given, receive each row's winning row and its squared
    distance, as ``match`` computes them (:mod:`.scoring`).

    Scoring only reads the weights and the efficacies, so any synapse model
    with a plain ``efficacy_`` array will do.
    """
    if type(clusterer) not in _NEAREST_UNIT:
        return None
    W, y = getattr(clusterer, "weights_", None), getattr(synapse, "efficacy_", None)
    if not (_plain(W, 2) and _plain(y, 1) and y.shape[0] == W.shape[0]):
        return None
    if _NEAREST.module is None and _NEAREST.get() is None:
        return None
    return _score


def _score(net, syn, X, winners=None, distances=None):
    return score(_NEAREST.module, net.weights_, syn.efficacy_, X, winners, distances)


# ---------------------------------------------------------------- parameters
_DECAY_CODES = {"constant": 0, "linear": 1, "asymptotic": 2}
_plans: dict[int, np.ndarray] = {}
_params: dict[tuple, np.ndarray] = {}


def _plan(n_features: int) -> np.ndarray:
    plan = _plans.get(n_features)
    if plan is None:
        from ._pairwise import pairwise_plan

        plan = _plans[n_features] = pairwise_plan(n_features)
    return plan


def _som_stanley_params(som, syn, stimulus: float) -> np.ndarray | None:
    """The kernel's ``params`` vector (see ``_som_stanley.PARAMS``), or None if out of its scope.

    Parameters may change between calls (``set_params``), so they are read
    every time; the vector is cached by value because building it costs
    more than looking it up.
    """
    key = (som.n_rows, som.n_columns, som.decay, som.learning_rate, som.learning_rate_final,
           som.radius, som.radius_final, som.decay_steps, syn.method, syn.others,
           syn.tau_winner, syn.tau_neighbour, syn.tau_forget, syn.alpha, syn.y0, stimulus)
    params = _params.get(key)
    if params is None:
        if som.decay not in _DECAY_CODES or syn.method not in ("euler", "exact") \
                or syn.others not in ("hold", "forget"):
            return None
        tau_f = syn.tau_neighbour if syn.tau_forget is None else syn.tau_forget
        values = {
            "n_columns": som.n_columns, "decay": _DECAY_CODES[som.decay],
            "learning_rate": som.learning_rate, "learning_rate_final": som.learning_rate_final,
            "radius": som.radius, "radius_final": som.radius_final,
            "decay_steps": som.decay_steps, "exact": syn.method == "exact",
            "forget": syn.others == "forget", "tau_winner": syn.tau_winner,
            "tau_neighbour": syn.tau_neighbour, "tau_forget": tau_f, "alpha": syn.alpha,
            "y0": syn.y0, "stimulus": stimulus,
        }
        params = np.array([float(values[name]) for name in _SOM.module.PARAMS])
        if len(_params) > 256:  # a parameter sweep: do not grow without bound
            _params.clear()
        _params[key] = params
    return params


# ------------------------------------------------------------------ learning
def _learn_som_stanley(som, syn, X: np.ndarray, dt: np.ndarray, stimulus: float,
                       winners: np.ndarray | None = None,
                       distances: np.ndarray | None = None) -> np.ndarray:
    # ``winners`` (int64, one per row) receives the winning rows, for tests;
    # ``distances`` the squared distances to them.
    params = _som_stanley_params(som, syn, stimulus)
    if params is None or som.n_rows * som.n_columns != som.weights_.shape[0]:
        from ..filter import learn_stream

        return learn_stream(som, syn, X, dt, stimulus, distances=distances)
    n = X.shape[0]
    novelty = np.empty(n)
    radius, t = _SOM.module.som_stanley_stream(
        som.weights_, syn.efficacy_, _c(X), _c(dt),
        np.empty(n, dtype=np.int64) if winners is None else winners, novelty,
        np.empty(n) if distances is None else distances,
        _plan(X.shape[1]), params, True, som._table_radius, som.n_updates_,
    )
    som.n_updates_ = t
    if radius != som._table_radius:
        # SOM.adapt rebuilds its neighbour table whenever the scheduled radius changes
        som._rebuild_scratch()
    return novelty


#: scans learned by the reference between two looks at the compiler thread
_HANDOVER_BLOCK = 256


def _handing_over(compiled: _Compiled, kernel: Callable) -> Callable:
    """``kernel``'s stand-in while ``compiled`` compiles.

    It runs the reference block by block and hands over to ``kernel`` as
    soon as it is ready.
    """

    def learn(net, syn, X, dt, stimulus, winners=None, distances=None):
        from ..filter import learn_stream

        if winners is not None:  # only tests ask for winners, and they wait for the kernel
            raise ValueError("winners are only reported by the compiled kernel")
        novelty = np.empty(X.shape[0])
        d = np.empty(X.shape[0]) if distances is None else distances
        start = 0
        while start < X.shape[0]:
            if compiled.module is not None or compiled.get() is not None:
                novelty[start:] = kernel(net, syn, X[start:], dt[start:], stimulus,
                                         distances=d[start:])
                break
            stop = start + _HANDOVER_BLOCK
            novelty[start:stop] = learn_stream(net, syn, X[start:stop], dt[start:stop], stimulus,
                                               distances=d[start:stop])
            start = stop
        return novelty

    return learn


_som_handing_over = _handing_over(_SOM, _learn_som_stanley)


# ------------------------------------------------------------ growing networks
def _stanley_params(syn) -> np.ndarray:
    tau_f = syn.tau_neighbour if syn.tau_forget is None else syn.tau_forget
    return np.array([syn.method == "exact", syn.others == "forget", syn.tau_winner,
                     syn.tau_neighbour, tau_f, syn.alpha, syn.y0], dtype=np.float64)


def _growing_state(net, syn):
    """The network's own arrays, if the kernel can work on them in place; else None."""
    per_unit = net.firing_.efficacy_ if type(net) is GrowWhenRequired else net.errors_
    A, ids = net.edge_ages_, net.unit_ids_
    if (_plain(per_unit, 1) and type(A) is np.ndarray and A.dtype == np.int32
            and A.flags.c_contiguous and A.flags.writeable and type(ids) is np.ndarray
            and ids.dtype == np.int64 and ids.flags.c_contiguous and ids.flags.writeable):
        return net.weights_, per_unit, A, syn.efficacy_, ids
    return None


def _roomy_state(net, syn, extra: int):
    """Copies of the network's arrays with room for ``extra`` more units."""
    n = net.weights_.shape[0]
    cap = n + extra
    W = np.zeros((cap, net.weights_.shape[1]))
    W[:n] = net.weights_
    u = np.zeros(cap)  # GWR: firing counters; GNG: errors
    u[:n] = net.firing_.efficacy_ if type(net) is GrowWhenRequired else net.errors_
    A = np.full((cap, cap), -1, dtype=np.int32)
    A[:n, :n] = net.edge_ages_
    y = np.zeros(cap)
    y[:n] = syn.efficacy_
    ids = np.zeros(cap, dtype=np.int64)
    ids[:n] = net.unit_ids_
    return W, u, A, y, ids


def _learn_growing(net, syn, X: np.ndarray, dt: np.ndarray, stimulus: float,
                   distances: np.ndarray | None = None) -> np.ndarray:
    """GNG or GWR: the kernel on the network's own arrays while no unit is added, then on
    copies with room to grow, enlarged whenever the kernel stops for want of room."""
    module = _GROWING.module
    gwr = type(net) is GrowWhenRequired
    X, dt = _c(X), _c(dt)
    plan = _plan(X.shape[1])
    p = _stanley_params(syn)
    if gwr:
        g = np.array([net.activity_threshold_, net.habituation_threshold, net.epsilon_b,
                      net.epsilon_n, net.max_age, -1 if net.max_units is None else net.max_units,
                      net.firing_condition, net.new_unit_wins], dtype=np.float64)
        ph = _stanley_params(net.firing_)
    else:
        g = np.array([net.epsilon_b, net.epsilon_n, net.insertion_interval,
                      net.insertion_error_decay, net.error_decay, net.max_age, net.max_units],
                     dtype=np.float64)
    novelty = np.empty(X.shape[0])
    d = np.empty(X.shape[0]) if distances is None else distances
    age_dtype = net.edge_ages_.dtype
    state = _growing_state(net, syn)  # most single scans add no unit: no copies
    start = 0
    while start < X.shape[0]:
        n = net.weights_.shape[0]
        if state is None:
            # a GWR may add a unit per input, a GNG one per insertion_interval inputs;
            # at most doubling per call keeps the wasted rows few
            rest = X.shape[0] - start
            room = rest if gwr else rest // net.insertion_interval + 1
            state = _roomy_state(net, syn, max(1, min(room, max(n, 16))))
        W, u, A, y, ids = state
        out, out_d = novelty[start:], d[start:]
        if gwr:
            done, n, next_id = module.gwr_stream(W, u, A, y, ids, X[start:], dt[start:], out,
                                                 out_d, plan, g, p, ph, float(stimulus), n,
                                                 int(net.next_unit_id_))
        else:
            done, n, next_id, n_inputs = module.gng_stream(
                W, u, A, y, ids, X[start:], dt[start:], out, out_d, plan, g, p, float(stimulus),
                n, int(net.next_unit_id_), int(net.n_inputs_))
            net.n_inputs_ = int(n_inputs)
        if n != W.shape[0] or W is not net.weights_:  # units added or deleted: trim
            net.weights_ = W[:n].copy()
            net.edge_ages_ = A[:n, :n].astype(age_dtype)
            net.unit_ids_ = ids[:n].copy()
            syn.efficacy_ = y[:n].copy()
            if gwr:
                net.firing_.efficacy_ = u[:n].copy()
            else:
                net.errors_ = u[:n].copy()
        net.next_unit_id_ = int(next_id)
        if done < 0:
            raise RuntimeError("GrowingNeuralGas: the unit of largest error has no neighbour.")
        start += int(done)
        state = None
    return novelty


_growing_handing_over = _handing_over(_GROWING, _learn_growing)
