"""Measured properties of the paper's environments: what the simulated corridors must show."""

import functools

import numpy as np
import pytest

from novelty import sonar

NAMES = ["a", "a-star", "b", "c", "control"]


@functools.lru_cache(maxsize=None)
def _run(env: str, run: int, seed: int = 0):
    return sonar.simulate_run(env, seed, run)


@pytest.fixture(scope="module")
def sim():
    """simulate_run(env, run, seed=0), cached for the module (tests only read the results)."""
    return _run


def _nearest(X, reference):
    """Distance of each row of X to its nearest row of ``reference``."""
    d = ((X[:, None, :] - reference[None, :, :]) ** 2).sum(axis=2)
    return np.sqrt(d.min(axis=1))


@pytest.mark.parametrize("name", NAMES)
def test_every_environment_gives_about_100_scans_of_16_values_in_unit_range(sim, name):
    ds = sim(name, 0)
    assert ds.X.shape == (100, 16)
    assert ds.X.min() >= 0.0 and ds.X.max() <= 1.0
    assert ds.X.max() > 0.5  # something is near: not an empty perception
    assert ds.distance == pytest.approx(np.arange(1, 101) * 0.1)
    assert ds.poses.shape == (100, 3) and len(ds.feature_ids) == 100
    assert set(ds.run.tolist()) == {0}
    assert ds.metadata["map"] == name and ds.metadata["seed"] == 0


def test_two_runs_of_a_are_close_but_not_identical(sim):
    a0, a1 = sim("a", 0).X, sim("a", 1).X
    diff = np.abs(a0 - a1).mean()
    assert 0.005 < diff < 0.15
    reference = np.vstack([sim("a", r).X for r in range(3)])
    assert _nearest(sim("a", 3).X, reference).mean() < 0.25


def test_a_and_a_star_differ_only_around_the_opened_door(sim):
    near, far = [], []
    for run in range(3):
        a, s = sim("a", run), sim("a-star", run)
        d = np.abs(a.X - s.X).mean(axis=1)
        around = np.abs(a.distance - 3.0) <= 1.5
        near.append(d[around].mean())
        far.append(d[~around].mean())
    assert np.mean(far) < 0.02
    assert np.mean(near) > 5 * np.mean(far)


def test_c_differs_from_a_more_than_b_does_and_control_most(sim):
    reference = np.vstack([sim("a", r).X for r in range(3)])
    dist = {name: _nearest(sim(name, 3).X, reference).mean() for name in ["a", "b", "c", "control"]}
    assert dist["a"] < dist["b"] < 0.5
    assert dist["c"] > dist["b"] + 0.2
    assert dist["control"] > dist["c"] + 0.4


def test_the_thin_crack_is_perceived_in_some_runs_and_not_in_others(sim):
    seen = [any("crack-1" in f for f in sim("a", run).feature_ids) for run in range(8)]
    assert any(seen) and not all(seen)


def test_a_door_is_perceived_only_around_it(sim):
    ds = sim("a", 0)
    at = ds.distance[[("door-r1" in f) for f in ds.feature_ids]]
    assert at.size >= 5
    assert np.abs(at - 3.0).max() < 2.7  # 0.45 m half-width + 2 m salient range + the ring


def test_simulation_is_deterministic_and_seeded_by_seed_and_run():
    one = sonar.simulate_run("b", seed=3, run=2)
    again = sonar.simulate_run("b", seed=3, run=2)
    np.testing.assert_array_equal(one.X, again.X)
    np.testing.assert_array_equal(one.poses, again.poses)
    assert one.feature_ids == again.feature_ids
    assert not np.array_equal(one.X, sonar.simulate_run("b", seed=3, run=1).X)
    assert not np.array_equal(one.X, sonar.simulate_run("b", seed=4, run=2).X)


def test_feature_tables_place_the_papers_features():
    a = {f["id"]: f for f in sonar.feature_table("a")}
    assert a["door-r1"]["position"] == pytest.approx(3.0, abs=0.05)
    assert a["door-r1"]["side"] == "right" and a["door-r1"]["kind"] == "door"
    assert a["crack-1"]["kind"] == "crack" and a["crack-1"]["position"] < 1.5
    b = {f["id"]: f for f in sonar.feature_table("b")}
    deepest_in_a = max(f["depth"] for f in a.values() if f["kind"] == "door")
    assert b["door-g"]["depth"] > deepest_in_a
    c = {f["id"]: f for f in sonar.feature_table("c")}
    assert c["crack-c"]["position"] == pytest.approx(7.0)
    assert c["door-c1"]["depth"] > b["door-g"]["depth"]
    assert {f["kind"] for f in c.values()} >= {"door", "crack", "board"}
    a_star = {f["id"]: f for f in sonar.feature_table("paper-a-star")}
    assert a_star["door-r1-open"]["kind"] == "opening"


def test_environment_names_are_forgiving_and_unknown_ones_explained():
    assert sonar.get_environment("A*") is sonar.get_environment("paper-a-star")
    with pytest.raises(ValueError, match="known: a, a-star"):
        sonar.get_environment("corridor-z")


def test_corridor_a_without_extra_doors_keeps_only_the_papers_features():
    """The paper names A's crack and its door on the right at about 3 m; the other doors are chosen."""
    named = {f["id"] for f in sonar.get_environment(sonar.corridor_a(extra_doors=False)).feature_table()}
    assert named == {"crack-1", "door-r1"}
    opened = sonar.corridor_a(open_door=True, extra_doors=False).feature_table()
    assert {f["id"] for f in opened} == {"crack-1", "door-r1-open", "door-r1-open-frame"}
    full = {f["id"] for f in sonar.corridor_a().feature_table()}
    assert full == {f["id"] for f in sonar.feature_table("a")} and len(full) > 2


def test_switches_at_their_defaults_keep_the_simulated_runs_unchanged():
    """The defaults of the simulator's switches give the runs they gave before the switches existed.

    The two sums were computed from ``simulate("a", seed=0)`` before the
    switches (whole inches, edge echoes, A's extra doors) were added.
    """
    explicit = sonar.simulate(sonar.corridor_a(extra_doors=True), seed=0,
                              ranger=sonar.PolaroidRanger(edges=True, resolution=None))
    default = sonar.simulate("a", seed=0)
    np.testing.assert_array_equal(explicit.X, default.X)
    assert float(default.X.sum()) == pytest.approx(568.203831371467, rel=1e-12)
    assert float((default.X ** 2).sum()) == pytest.approx(443.8602519121565, rel=1e-12)
