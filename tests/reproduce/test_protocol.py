"""The paper's protocol, Table 1 and claims (Marsland, Nehmzow & Shapiro 2000), in the sonar world.

Each claim test runs on five seeds; the protocol runs once per seed (cached
here), and every run's traversal is simulated once per process (cached in
novelty.reproduce). Where the simulation does not support a claim as the
paper states it, the test's docstring says so, gives the numbers measured on
seeds 0-9, and tests the form that does hold; claims that do not hold in any
form are not tested (see docs/guide/paper.md).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import novelty
from novelty.reproduce import PAPER_TABLE1, Trial, is_resting, run_protocol

SEEDS = (0, 1, 2, 3, 4)
RESTING = 0.0476
#: Where the door of A* is (m along the route) and how far either side the sonar hears it.
DOOR, DOOR_REACH = 3.0, 1.0


@functools.lru_cache(maxsize=None)
def protocol(seed: int) -> dict[tuple[str, str], Trial]:
    return {(t.experiment, t.trial): t for t in run_protocol(seed=seed)}


@functools.lru_cache(maxsize=None)
def settled_a(seed: int, model_dir: str) -> list[Trial]:
    return run_protocol(seed=seed, a_pairs=None, experiments=("A",), model_dir=model_dir)


@pytest.fixture(scope="module")
def model_root(tmp_path_factory):
    return tmp_path_factory.mktemp("models")


def excess(trial: Trial, mask=None) -> float:
    """Mean output above the resting activity per scan (over ``mask``)."""
    e = trial.novelty - trial.resting
    return float(e[mask].mean() if mask is not None else e.mean())


# --------------------------------------------------------------- the protocol
def test_protocol_follows_table1():
    trials = list(protocol(0).values())
    assert [(t.experiment, t.trial, t.mode) for t in trials] == [(e, t, m) for e, t, m, _, _ in PAPER_TABLE1]
    for t in trials:
        assert t.novelty.shape == (100,) and t.distance.shape == (100,)
        assert np.all((t.novelty >= RESTING - 1e-9) & (t.novelty <= 1.0))
        assert t.resting == pytest.approx(RESTING, abs=1e-4)
        assert t.features and all({"id", "kind", "position", "side"} <= set(f) for f in t.features)
    # every run of an environment is a new traversal
    runs = [(t.experiment, t.run) for t in trials]
    assert len(set(runs)) == len(runs)
    assert trials[0].distance[0] == pytest.approx(0.1) and trials[0].distance[-1] == pytest.approx(10.0)


def test_a_model_file_links_each_run_to_the_next(tmp_path):
    trials = run_protocol(seed=0, experiments=("A",), model_dir=tmp_path)
    assert sorted(p.name for p in tmp_path.glob("*.npz")) == ["A-1.npz", "A-3.npz", "A-5.npz"]
    # the last non-learning run is exactly what the model saved after the last learning run says
    det = novelty.load(tmp_path / "A-5.npz")
    X = novelty.datasets.load("paper-a", run=trials[-1].run, seed=0).X
    np.testing.assert_allclose(det.novelty(X), trials[-1].novelty)


def test_any_registered_detector_runs_the_protocol():
    for name in ("gwr-novelty", "kohonen-filter"):  # a growing network; a detector without random_state
        trials = run_protocol(name, seed=0, experiments=("A",))
        assert [t.mode for t in trials] == ["L", "NL"] * 3
        assert all(np.all(np.isfinite(t.novelty)) for t in trials)


def test_protocol_refuses_bad_arguments():
    with pytest.raises(ValueError, match="a_pairs"):
        run_protocol(a_pairs=0)
    with pytest.raises(ValueError, match="experiments"):
        run_protocol(experiments=("A", "D"))


# ---------------------------------------------------------- the paper's claims
@pytest.mark.parametrize("seed", SEEDS)
def test_novelty_falls_after_each_learning_trial_in_a(seed):
    """Table 1: "both the integrated output and maximum output drop after each learning trial".

    Tested per pair of trials (a learning trial and the non-learning trial
    after it): each learning trial lowers the mean integrated novelty of the
    pair that follows; the first learning trial is more novel than the later
    ones; the last non-learning trial is below the first. Trial by trial the
    fall is not monotonic here: the spread from one traversal to the next
    (about +-3) is as large as one learning run's effect, so a trial can
    exceed the one before (seeds 0-9: NL 2 -> 4 rose on seeds 1 and 7, L 3 ->
    5 on seed 7, L 1 -> NL 2 on seed 3); the maxima do not fall steadily
    either (0.81, 0.81, 0.61 on seed 0) and are not tested.
    """
    a = [protocol(seed)[("A", str(k))] for k in range(1, 7)]
    pairs = [(a[i].integrated + a[i + 1].integrated) / 2 for i in (0, 2, 4)]
    assert pairs[0] > pairs[1] > pairs[2], pairs
    assert a[0].integrated > max(a[2].integrated, a[4].integrated)
    assert a[5].integrated < a[1].integrated


@pytest.mark.parametrize("seed", SEEDS)
def test_a_eventually_shows_only_the_resting_activity(seed, model_root):
    """Section 3.2: after a number of runs "the output of the novelty filter was only the resting activity".

    "Eventually" here means after far more learning runs than the paper's
    three: continuing in A, a non-learning run shows only the resting
    activity (integrated <= 0.5, maximum <= 0.2; the paper's settled run had
    0.30 and 0.12) after 12-18 learning runs (seeds 0-9; 18, 12, 14, 16, 12
    for seeds 0-4). The cap of 25 pairs is the protocol's default.
    """
    trials = settled_a(seed, str(model_root / f"seed{seed}"))
    assert trials[-1].mode == "NL" and is_resting(trials[-1])
    assert not any(is_resting(t) for t in trials[:-1] if t.mode == "NL")
    assert len(trials) // 2 <= 25


@pytest.mark.parametrize("seed", SEEDS)
def test_settling_in_a_saturates_the_map(seed, model_root):
    """Why the claims about A*, B and C are tested from the model after 3 pairs, as in Table 1.

    Not a claim of the paper but the reason some of its claims do not
    reproduce: the simulated corridor offers more distinct perceptions than
    the 10 x 10 map can hold apart, so A settles only once (nearly) every
    unit's synapse has habituated (92-98 of the 100 below 0.1 on seeds 0-9).
    From such a model nothing can be novel: the opened door of A* gives no
    burst. The paper's map was not saturated after A (its controls and
    first trials in new places reach fresh units).
    """
    trials = settled_a(seed, str(model_root / f"seed{seed}"))
    det = novelty.load(model_root / f"seed{seed}" / f"A-{len(trials) - 1}.npz")
    assert np.sum(det.synapse_.efficacy_ < 0.2) >= 90


@pytest.mark.parametrize("seed", SEEDS)
def test_opened_door_gives_a_burst_of_novelty_at_the_door(seed):
    """Section 4.1: "The novelty filter detects the open door, as can be seen from the burst of novelty".

    In the first A* trial the output within 1 m of the opened door is higher
    than elsewhere on the run (per scan above the resting activity, seeds
    0-9: 1.2-3.9 times). "No other novel features were detected" does not
    hold: A is not learned after three learning runs, so the rest of A* is
    about as novel as A itself (0.05-0.13 a scan); and the shut door of A at
    the same place is itself more novel than the rest of A on 9 of 10 seeds,
    so this test alone does not show that the opening caused the burst; the
    next test does, over the seeds.
    """
    t = protocol(seed)[("A*", "1")]
    near = t.near(DOOR, DOOR_REACH)
    assert excess(t, near) > excess(t, ~near)


def test_opening_the_door_changes_novelty_only_at_the_door():
    """Section 4.1: "No other novel features were detected", as a paired comparison over the seeds.

    The same model scores the A* run and the A run drawn with the same random
    numbers (same start, speed and jitter; the door shut): their difference
    is what opening the door did. Averaged over the five seeds it raises the
    novelty within 1 m of the door (0.042 a scan on seeds 0-4, 0.054 on
    5-9) and leaves the rest of the route as it was (0.002 and -0.000 a
    scan). Per seed the door's own effect varies: on seed 4 the opened door
    is less novel than the shut one (-0.065 a scan), so the claim is tested
    on the mean, not seed by seed.
    """
    near_effect, other_effect = [], []
    for seed in SEEDS:
        t = protocol(seed)[("A*", "1")]
        near = t.near(DOOR, DOOR_REACH)
        diff = t.novelty - t.paired
        near_effect.append(diff[near].mean())
        other_effect.append(diff[~near].mean())
    assert np.mean(near_effect) > 0.02
    assert np.mean(near_effect) > 2 * abs(np.mean(other_effect))


def test_the_burst_at_the_door_dies_away_over_the_next_trials():
    """Section 4.1: "successive trials show that the filter quickly learns to recognise this new feature".

    After two learning runs of A* the novelty within 1 m of the door has
    fallen by at least a quarter from the first A* trial, on average over the
    five seeds (0.189 -> 0.106 a scan on seeds 0-4, 0.170 -> 0.082 on 5-9).
    Seed by seed it falls on 9 of seeds 0-9, but not on seed 1 (0.179 ->
    0.187) and only barely on seeds 2 and 7 (0.186 -> 0.182, 0.106 -> 0.102):
    with A itself unlearned, each learning run also moves the units that the
    door's perceptions share with the rest of the corridor. Tested on the mean.
    """
    first, last = [], []
    for seed in SEEDS:
        p = protocol(seed)
        near = p[("A*", "1")].near(DOOR, DOOR_REACH)
        first.append(excess(p[("A*", "1")], near))
        last.append(excess(p[("A*", "5")], near))
    assert np.mean(last) < 0.75 * np.mean(first)


@pytest.mark.parametrize("seed", SEEDS)
def test_first_trial_in_b_is_less_novel_than_in_c(seed):
    """Section 4.3: "much more novelty is detected in environment C than in environment B".

    Table 1: 3.38 against 9.68. Holds on seeds 0-9 (B's first trial 0.27-0.79 of C's).
    """
    p = protocol(seed)
    assert p[("B", "1")].integrated < p[("C", "1")].integrated


@pytest.mark.parametrize("seed", SEEDS)
def test_controls_show_more_novelty_than_after_training_in_a(seed):
    """Sections 4.2-4.3: "much more novelty was detected" by the filter trained in the control area.

    B: the control-trained filter finds at least twice the novelty of the
    A-trained filter's first trial in B (3.1-10.3 times on seeds 0-9; the
    paper 8.0). C: more, but not "far more" on every seed (1.07-3.9 times on
    seeds 0-9, under 1.5 on seeds 1, 3 and 7; the paper 2.9): C's glass wall
    is an acoustic mirror that returns no echo to the oblique sensors, so
    much of C's left side is silent, as the open area the control filter
    learned is.
    """
    p = protocol(seed)
    assert p[("B", "Control")].integrated >= 2 * p[("B", "1")].integrated
    assert p[("C", "Control")].integrated > p[("C", "1")].integrated


@pytest.mark.parametrize("seed", SEEDS)
def test_first_runs_of_an_untrained_filter_peak_at_one(seed):
    """Table 1: the maximum output is 1.00 in A's first trial and in both controls.

    "Everything is initially novel" in A's first run, and the control
    filter meets perceptions of B and C that reach units the open area never
    trained (an untouched synapse: output 1.0).
    """
    p = protocol(seed)
    for key in (("A", "1"), ("B", "Control"), ("C", "Control")):
        assert p[key].maximum == pytest.approx(1.0), key
    assert p[("A", "1")].novelty[0] == pytest.approx(1.0)
