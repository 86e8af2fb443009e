"""Online k-means by hand: running means, or a constant learning rate; units placed on the first inputs."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import novelty
from novelty.clusterers.kmeans import OnlineKMeans


def test_online_kmeans_by_hand():
    km = OnlineKMeans(n_clusters=2).initialize(np.array([[0.0, 0.0], [1.0, 1.0]]), random_state=0)
    km.weights_[:] = [[0.0, 0.0], [1.0, 1.0]]
    for x in ([0.5, 0.0], [1.0, 0.5], [0.25, 0.5]):
        m, growth = km.learn_one(np.array(x))
        assert m.neighbours.size == 0 and growth.added == 0
    np.testing.assert_allclose(km.weights_, [[0.25, 0.5 / 3], [1.0, 0.75]])   # running means
    np.testing.assert_array_equal(km.counts_, [3, 2])
    const = OnlineKMeans(n_clusters=1, learning_rate=0.5).initialize(np.zeros((1, 1)))
    const.learn_one(np.ones(1))
    const.learn_one(np.ones(1))
    np.testing.assert_array_equal(const.weights_, [[0.75]])


def test_online_kmeans_first_places_the_first_distinct_inputs_by_hand():
    km = OnlineKMeans(n_clusters=2, init="first").initialize(np.array([[0.0], [9.0]]))
    np.testing.assert_array_equal(km.weights_, [[0.0]])   # the first input only, standing for none yet
    np.testing.assert_array_equal(km.counts_, [0])
    growths = [km.learn_one(np.array([x]))[1] for x in (0.0, 0.0, 1.0, 1.0, 3.0)]
    # 0 and its repeat are learned by unit 0; 1 is placed (and stands for itself); 3 comes when full
    assert [g.added for g in growths] == [0, 0, 1, 0, 0] and growths[2].new_winner
    np.testing.assert_array_equal(km.weights_, [[0.0], [1.0 + (3.0 - 1.0) / 3]])
    np.testing.assert_array_equal(km.counts_, [2, 3])
    np.testing.assert_array_equal(km.unit_ids_, [0, 1])
    assert km.grows_for(np.zeros(1, dtype=np.intp), np.ones(1)) is None


def test_online_kmeans_first_scores_new_inputs_by_their_match_while_placing():
    """Placing is not a judgement: unscored inputs are matched against the units placed so far."""
    det = novelty.make("habituating", clusterer="online-kmeans", clusterer__init="first",
                       clusterer__n_clusters=10, novelty_rule="mismatch", match_scale=1.0)
    det.stream(np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]]))
    assert det.clusterer_.n_units_ == 2
    y = det.synapse_.efficacy_
    near, far = det.novelty(np.array([[0.0, 0.5], [0.0, 3.0]]))
    assert near == 1 - (1 - y[0]) * np.exp(-0.25 / 2)
    assert far == 1 - (1 - y[0]) * np.exp(-9.0 / 2)


@settings(max_examples=40, deadline=None)
@given(X=st.lists(st.lists(st.sampled_from([0.0, 0.25, 0.5, 1.0]), min_size=2, max_size=2),
                  min_size=1, max_size=30),
       k=st.integers(1, 8), cut=st.integers(0, 30))
def test_online_kmeans_first_is_the_same_streamed_or_batched(X, k, cut):
    X = np.array(X)

    def make():
        return novelty.make("habituating", clusterer="online-kmeans", clusterer__init="first",
                            clusterer__n_clusters=k, novelty_rule="mismatch", match_scale="scott")

    one, two = make(), make()
    by_scan = np.concatenate([one.stream(x[None, :]) for x in X])
    cut = min(max(cut, 1), len(X))
    batched = np.concatenate([two.stream(X[:cut]), two.stream(X[cut:]) if cut < len(X) else []])
    assert by_scan.tobytes() == batched.tobytes()
    np.testing.assert_array_equal(one.clusterer_.weights_, two.clusterer_.weights_)
    assert one.clusterer_.n_units_ == min(k, len(np.unique(X, axis=0)))


def test_online_kmeans_first_state_checks():
    from novelty._component import StateError

    km = OnlineKMeans(n_clusters=3, init="first").initialize(np.zeros((1, 2)))
    km._check_state()                        # one unit of three, standing for no input yet: valid
    km.weights_ = np.zeros((4, 2))
    km.counts_ = np.zeros(4, dtype=np.int64)
    km.unit_ids_ = np.arange(4)
    km.next_unit_id_ = 4
    with pytest.raises(StateError, match="n_clusters"):
        km._check_state()
    sampled = OnlineKMeans(n_clusters=1).initialize(np.zeros((1, 2)))
    sampled.counts_[:] = 0
    with pytest.raises(StateError, match="at least 1"):
        sampled._check_state()


def test_online_kmeans_placement_radius_by_hand():
    km = OnlineKMeans(n_clusters=3, init="first", placement_radius=1.5).initialize(np.zeros((1, 1)))
    growths = [km.learn_one(np.array([x]))[1].added for x in (0.0, 1.0, 2.0, 4.0, 10.0, 20.0)]
    # 1 and 2 are within 1.5 of unit 0 (2 exactly 1.5 from its mean 0.5): learned, not placed;
    # 4 and 10 are placed; 20 comes when the three units are there
    assert growths == [0, 0, 0, 1, 1, 0]
    np.testing.assert_array_equal(km.weights_, [[1.0], [4.0], [15.0]])
    np.testing.assert_array_equal(km.counts_, [3, 1, 2])


def test_online_kmeans_auto_radius_is_the_filters_match_scale():
    det = novelty.make("habituating", clusterer="online-kmeans", clusterer__init="first",
                       clusterer__n_clusters=50, clusterer__placement_radius="auto",
                       novelty_rule="mismatch", match_scale="scott", calibration_scans=30)
    X = np.random.default_rng(1).uniform(size=(60, 3))
    det.stream(X[:1])
    assert det.clusterer_.placement_radius_ == 0.0          # no scale yet: every distinct scan
    det.stream(X[1:])
    assert det.clusterer_.placement_radius_ == det.match_scale_ > 0
    W = det.clusterer_.weights_
    gaps = np.sqrt(((W[:, None, :] - W[None, :, :]) ** 2).sum(-1))[np.triu_indices(len(W), 1)]
    assert det.clusterer_.n_units_ < 50 and gaps.min() > 0
    fixed = novelty.make("habituating", clusterer="online-kmeans", clusterer__init="first",
                         clusterer__placement_radius="auto", novelty_rule="mismatch", match_scale=0.25)
    fixed.fit(X)
    assert fixed.clusterer_.placement_radius_ == 0.25


@pytest.mark.parametrize("params,message", [
    ({"init": "first", "placement_radius": -0.5}, "placement_radius"),
    ({"init": "first", "placement_radius": "scott"}, "placement_radius"),
    ({"init": "sample", "placement_radius": 0.5}, "init='first' only"),
    ({"init": "reservoir"}, "init"),
])
def test_online_kmeans_refuses_bad_placement(params, message):
    km = OnlineKMeans(**params)
    with pytest.raises(ValueError, match=message):
        km.initialize(np.zeros((2, 2)))
    assert not hasattr(km, "weights_")


@pytest.mark.parametrize("bad", [-1.0, np.inf, np.nan, True])
def test_online_kmeans_refuses_a_bad_radius_in_its_state(bad):
    from novelty._component import StateError

    km = OnlineKMeans(n_clusters=3, init="first", placement_radius=0.5).initialize(np.zeros((1, 2)))
    km.placement_radius_ = bad
    with pytest.raises(StateError, match="placement_radius_"):
        km._check_state()
