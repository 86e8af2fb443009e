"""The paper's protocol on many seeds: Table 1 beside ours, and each claim checked seed by seed.

Runs :func:`novelty.reproduce.run_protocol` (``hsom``, the paper's
constants; A with three pairs of runs as in Table 1) once per seed. Each
claim of the paper is written as a test on one seed's trials; the table says
on how many seeds it holds, with the range of the measured quantity.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from novelty.reproduce import PAPER_TABLE1, is_resting, run_protocol

from ._common import Result, parallel, pyplot, span

NAME = "table1"
#: the title, with the span of the seeds run ("0-9")
TITLE = "Table 1 on seeds {} and the paper's claims"

#: The door of A* (m along the route) and how far either side the sonar hears it; door G of B.
DOOR, DOOR_G, REACH = 3.0, 3.6, 1.0


def _excess(trial, mask=None) -> float:
    """Mean output above the resting activity per scan (over ``mask``)."""
    e = trial.novelty - trial.resting
    return float(e[mask].mean() if mask is not None else e.mean())


def _near_door(p) -> tuple[float, float]:
    t = p[("A*", "1")]
    near = t.near(DOOR, REACH)
    return _excess(t, near), _excess(t, ~near)


def _falls_each_trial(p) -> tuple[bool, float]:
    a = [p[("A", str(k))].integrated for k in range(1, 7)]
    rises = sum(later >= earlier for earlier, later in zip(a, a[1:]))
    return rises == 0, float(rises)


def _falls_per_pair(p) -> tuple[bool, float]:
    a = [p[("A", str(k))].integrated for k in range(1, 7)]
    pairs = [(a[i] + a[i + 1]) / 2 for i in (0, 2, 4)]
    return pairs[0] > pairs[1] > pairs[2], pairs[2] / pairs[0]


def _burst_at_door(p) -> tuple[bool, float]:
    near, away = _near_door(p)
    return near > away, near / away


def _nothing_else(p) -> tuple[bool, float]:
    _, away = _near_door(p)
    return away <= 0.005, away  # the paper's settled run: 0.30 over 100 scans, 0.003 a scan


def _burst_dies(p) -> tuple[bool, float]:
    first, last = (p[("A*", k)] for k in ("1", "5"))
    a, b = _excess(first, first.near(DOOR, REACH)), _excess(last, last.near(DOOR, REACH))
    return b < 0.75 * a, b / a


def _b_below_c(p) -> tuple[bool, float]:
    b, c = p[("B", "1")].integrated, p[("C", "1")].integrated
    return b < c, b / c


def _control_b(p) -> tuple[bool, float]:
    ratio = p[("B", "Control")].integrated / p[("B", "1")].integrated
    return ratio >= 2, ratio


def _control_c(p) -> tuple[bool, float]:
    ratio = p[("C", "Control")].integrated / p[("C", "1")].integrated
    return ratio >= 2, ratio


def _peaks_at_one(p) -> tuple[bool, float]:
    peaks = [p[k].maximum for k in (("A", "1"), ("B", "Control"), ("C", "Control"))]
    return min(peaks) >= 0.995, min(peaks)


def _b_burst_at_g(p) -> tuple[bool, float]:
    t = p[("B", "1")]
    where = float(t.distance[int(np.argmax(t.novelty))])
    return abs(where - DOOR_G) <= REACH, where


def _a_settles(p) -> tuple[bool, float]:
    return is_resting(p[("A", "6")]), p[("A", "6")].integrated


#: (the paper's words, our test, the measured quantity, the test function)
CLAIMS = (
    ("integrated output and maximum drop after each learning trial (Table 1)",
     "A: each trial below the one before", "trials that did not fall", _falls_each_trial),
    ("... (the same, per pair of L and NL trials)", "A: mean of each pair below the pair before",
     "last pair / first pair", _falls_per_pair),
    ("after three learning runs only the resting activity (trial 6)",
     "A 6: integrated <= 0.5 and maximum <= 0.2", "A 6 integrated", _a_settles),
    ("the novelty filter detects the open door", "A* 1: more novelty a scan within 1 m of the door",
     "near / away", _burst_at_door),
    ("no other novel features were detected", "A* 1: <= 0.005 a scan away from the door",
     "excess a scan away", _nothing_else),
    ("successive trials ... quickly learns this new feature", "A* 5 near the door < 0.75 of A* 1",
     "A* 5 / A* 1 near the door", _burst_dies),
    ("much more novelty in C than in B", "B 1 < C 1", "B 1 / C 1", _b_below_c),
    ("B's control: much more novelty", "B control >= 2 x B 1", "B control / B 1", _control_b),
    ("C's control: far more novelty", "C control >= 2 x C 1", "C control / C 1", _control_c),
    ("everything is initially novel", "A 1, both controls peak at 1.0", "least peak", _peaks_at_one),
    ("B: novelty at door G (first door on the right)", "B 1 peaks within 1 m of 3.6 m",
     "position of B 1's peak (m)", _b_burst_at_g),
)


#: The map option (not in the paper) run beside the paper's map: see ``sensitivity``.
OWN_RATE = {"neighbour_learning_rate": 0.05}
OWN_HOLDS = "holds, neighbour rate 0.05 (not the paper's)"


def _protocols(seed: int) -> tuple[dict, dict]:
    """The paper's HSOM and the HSOM with its own neighbour rate, on the same traversals (cached)."""
    return tuple({(t.experiment, t.trial): t for t in run_protocol("hsom", seed=seed, params=params)}
                 for params in ({}, OWN_RATE))


def claim_rows(protocols: list[dict], own: list[dict]) -> list[dict]:
    rows = []
    for words, test, measure, check in CLAIMS:
        found = [check(p) for p in protocols]
        values = [v for _, v in found]
        rows.append({"claim (the paper)": words, "our test": test,
                     "holds on seeds": f"{sum(ok for ok, _ in found)}/{len(protocols)}", "measured": measure,
                     "range": f"{min(values):.2f} to {max(values):.2f}",
                     OWN_HOLDS: f"{sum(check(p)[0] for p in own)}/{len(own)}"})
    return rows


def table_rows(protocols: list[dict], own: list[dict]) -> list[dict]:
    rows = []
    for experiment, trial, mode, paper_int, paper_max in PAPER_TABLE1:
        ours = np.array([p[(experiment, trial)].integrated for p in protocols])
        peaks = np.array([p[(experiment, trial)].maximum for p in protocols])
        label = trial if trial == "Control" else f"{trial} ({mode})"
        rows.append({"Exp": experiment, "Trial": label, "paper integrated": paper_int,
                     "seed 0": float(ours[0]), "mean": float(ours.mean()),
                     "range": f"{ours.min():.2f}-{ours.max():.2f}", "mean / paper": float(ours.mean() / paper_int),
                     "paper maximum": paper_max, "maximum, seed 0": float(peaks[0]),
                     "maximum, range": f"{peaks.min():.2f}-{peaks.max():.2f}",
                     "neighbour rate 0.05: mean": float(np.mean([p[(experiment, trial)].integrated
                                                                 for p in own]))})
    return rows


def run(out: Path, seeds=range(10), jobs: int = 1) -> Result:
    seeds = list(seeds)
    both = parallel(_protocols, seeds, jobs)
    protocols, own = [p for p, _ in both], [o for _, o in both]
    rows = table_rows(protocols, own)
    claims = claim_rows(protocols, own)
    return Result(NAME, TITLE.format(span(seeds)), rows, [], _plot(rows, out / f"{NAME}.png"),
                  f"Integrated output above the resting activity; 'seed 0' is the guide's table (docs/guide/paper.md), "
                  f"'mean' and 'range' over seeds {seeds[0]}-{seeds[-1]}; the last column (not the paper's "
                  "map) gives the SOM's neighbours a learning rate of 0.05.", tables={"claims": claims})


def _plot(rows: list[dict], path: Path) -> Path:
    plt = pyplot()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8.0, 3.6))
    x = np.arange(len(rows))
    ax.plot(x, [r["paper integrated"] for r in rows], "ks", label="paper")
    ax.plot(x, [r["mean"] for r in rows], "o", color="#1f3b73", label="ours, mean over seeds")
    low = [float(r["range"].split("-")[0]) for r in rows]
    high = [float(r["range"].split("-")[1]) for r in rows]
    ax.vlines(x, low, high, color="#1f3b73", lw=1, label="ours, range over seeds")
    ax.plot(x, [r["neighbour rate 0.05: mean"] for r in rows], "^", color="#d62728", ms=4,
            label="neighbour rate 0.05 (not the paper's), mean")
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{r['Exp']} {r['Trial'].split(' ')[0]}" for r in rows], rotation=90, fontsize=7)
    ax.set_ylabel("integrated novelty")
    ax.set_title("Table 1: the paper's values and ours", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
