"""The clusterer interface: a custom clusterer registered in ten lines runs inside the
habituating filter and is saved and loaded like a built-in; so do the built-in growing ones."""

import numpy as np
import pytest

import novelty
from novelty.clusterers.base import NO_UNITS, Growth, Match
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.clusterers.som import SOM
from novelty.persistence import ModelFileError
from tests.damaged import damaging

REST = 1 - 1 / 1.05


def euler(n, tau=3.33, alpha=1.05):
    return REST + (1 - REST) * (1 - alpha / tau) ** n


@pytest.fixture
def tiny_kmeans():
    # ---- the ten lines a user writes ------------------------------------------
    @novelty.register_clusterer("tiny-kmeans")
    class TinyKMeans(novelty.Clusterer):
        """Winner-take-all online k-means with a fixed number of units."""

        def __init__(self, n_units=4, learning_rate=0.1):
            self.n_units, self.learning_rate = n_units, learning_rate

        def _initialize(self, X, rng):
            self.weights_ = rng.uniform(X.min(), X.max() + 1e-9, size=(self.n_units, X.shape[1]))

        def match(self, x):
            d = ((self.weights_ - x) ** 2).sum(axis=1)
            return Match(int(d.argmin()), float(d.min()), NO_UNITS)

        def adapt(self, x, match):
            self.weights_[match.winner] += self.learning_rate * (x - self.weights_[match.winner])
            return Growth()
    # ----------------------------------------------------------------------------

    yield TinyKMeans
    if "tiny-kmeans" in novelty.registry.clusterers:
        novelty.registry.clusterers.unregister("tiny-kmeans")


def test_it_is_listed(tiny_kmeans):
    assert novelty.available("clusterers")["tiny-kmeans"] == (
        "Winner-take-all online k-means with a fixed number of units."
    )
    assert novelty.registry.clusterers.parameters("tiny-kmeans") == ["learning_rate", "n_units"]


def test_it_runs_in_the_filter_and_novelty_falls_on_repeated_input(tiny_kmeans):
    det = novelty.make("habituating", clusterer="tiny-kmeans")
    assert isinstance(det.clusterer, tiny_kmeans)
    scan = np.array([0.2, 0.8, 0.5])
    out = np.array([det.score_learn_one(scan) for _ in range(30)])
    assert det.clusterer_.weights_.shape == (4, 3) and det.synapse_.n_units_ == 4
    assert np.all(np.diff(out) < 0)
    # no neighbours: the winner alone habituates, with the paper's tau = 3.33
    np.testing.assert_allclose(out, [euler(n) for n in range(30)], rtol=1e-12)
    assert np.sum(det.synapse_.efficacy_ < 1.0) == 1


def test_parameters_route_to_it_and_to_the_synapse(tiny_kmeans):
    det = novelty.make("habituating", clusterer="tiny-kmeans", n_units=2, learning_rate=0.5,
                       tau_winner=5.0, threshold=0.4)
    assert (det.clusterer.n_units, det.clusterer.learning_rate) == (2, 0.5)
    assert det.synapse.tau_winner == 5.0 and det.threshold == 0.4
    with pytest.raises(novelty.InvalidParameterError, match=r"'n_unit' \(did you mean 'n_units'\?\)"):
        novelty.make("habituating", clusterer="tiny-kmeans", n_unit=2)


def test_a_different_input_wins_a_fresh_unit(tiny_kmeans):
    det = novelty.make("habituating", clusterer="tiny-kmeans").fit(np.zeros((1, 2)))
    with damaging(det):  # a known start: the fitted parts are the engine's to write
        det.synapse_.efficacy_[:] = 1.0
        det.clusterer_.weights_[:] = [[0, 0], [0, 1], [1, 0], [1, 1]]
    a, b = np.array([0.1, 0.1]), np.array([0.9, 0.9])
    for _ in range(5):
        det.learn_one(a)
    assert det.score_one(a) == pytest.approx(euler(5))
    assert det.score_one(b) == 1.0
    ids, distances = det.winners(np.array([a, b]))
    np.testing.assert_array_equal(ids, [0, 3])
    np.testing.assert_allclose(distances, [np.sum((a - det.clusterer_.weights_[0]) ** 2),
                                           np.sum((b - det.clusterer_.weights_[3]) ** 2)])
    np.testing.assert_array_equal(det.novelty(np.array([a, b])), [det.score_one(a), 1.0])


def test_it_is_saved_and_loaded(tiny_kmeans, tmp_path):
    rng = np.random.default_rng(0)
    det = novelty.make("habituating", clusterer="tiny-kmeans", n_units=3).fit(rng.uniform(size=(50, 2)))
    det.save(tmp_path / "tiny.npz")
    loaded = novelty.load(tmp_path / "tiny.npz")
    assert type(loaded.clusterer_) is tiny_kmeans and loaded.clusterer.n_units == 3
    assert loaded.clusterer_.weights_.tobytes() == det.clusterer_.weights_.tobytes()
    Y = rng.uniform(size=(20, 2))
    assert loaded.stream(Y).tobytes() == det.stream(Y).tobytes()
    assert loaded.synapse_.efficacy_.tobytes() == det.synapse_.efficacy_.tobytes()


def test_once_unregistered_its_files_cannot_be_read(tiny_kmeans, tmp_path):
    det = novelty.make("habituating", clusterer="tiny-kmeans").fit(np.zeros((2, 2)))
    det.save(tmp_path / "tiny.npz")
    novelty.registry.clusterers.unregister("tiny-kmeans")
    with pytest.raises(ModelFileError, match="'tiny-kmeans', which is not registered"):
        novelty.load(tmp_path / "tiny.npz")


# ------------------------------------ the built-in growing clusterers in the filter
@pytest.mark.parametrize("name", ["gng", "gwr", "online-kmeans"])
def test_through_the_filter_novelty_is_in_range(name, corridor, traversals):
    rng = np.random.default_rng(3)
    X = np.vstack(traversals(corridor(1, n_scans=150), 2, rng))
    det = novelty.make("habituating", clusterer=name, synapse="stanley")
    out = det.stream(X)
    assert out.shape == (len(X),)
    assert np.all((out >= det.resting_novelty - 1e-12) & (out <= 1.0))
    assert out[0] == 1.0
    assert det.synapse_.n_units_ == det.clusterer_.n_units_
    assert np.all(np.isin(det.winners(X)[0], det.clusterer_.unit_ids_))


@pytest.mark.parametrize("name", ["gng", "gwr", "online-kmeans"])
def test_save_load_round_trip(tmp_path, name, corridor, traversals):
    rng = np.random.default_rng(4)
    scans = traversals(corridor(1, n_scans=150), 2, rng) + traversals(corridor(2, n_scans=150), 1, rng)
    extra = {} if name == "online-kmeans" else {"max_age": 20}   # so that units are also removed
    det = novelty.make("habituating", clusterer=name, synapse="stanley", **extra)
    det.fit(np.vstack(scans[:2]))
    path = tmp_path / f"{name}.npz"
    det.save(path)
    back = novelty.load(path)
    assert type(back.clusterer_) is type(det.clusterer_)
    np.testing.assert_array_equal(back.novelty(scans[2]), det.novelty(scans[2]))
    np.testing.assert_array_equal(back.stream(scans[2]), det.stream(scans[2]))
    for attr in ("weights_", "unit_ids_"):
        np.testing.assert_array_equal(getattr(back.clusterer_, attr), getattr(det.clusterer_, attr))
    if name == "gwr":
        assert type(back.clusterer_.firing_) is type(det.clusterer_.firing_)
        np.testing.assert_array_equal(back.clusterer_.firing_.efficacy_, det.clusterer_.firing_.efficacy_)
        np.testing.assert_array_equal(back.clusterer_.edge_ages_, det.clusterer_.edge_ages_)


def test_the_range_a_network_assumes_is_its_uniform_init_range():
    assert SOM().assumed_range() == (0.0, 1.0)
    assert SOM(init_range=(-2, 3)).assumed_range() == (-2.0, 3.0)
    assert SOM(init="sample").assumed_range() is None
    assert GrowWhenRequired().assumed_range() is None  # its units start on scans
    assert GrowWhenRequired(init="uniform").assumed_range() == (0.0, 1.0)
