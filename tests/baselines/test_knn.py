"""k nearest neighbours: distances by hand, the reference without each input itself, exact ties, PyOD's KNN."""

import numpy as np
import pytest

import novelty
from novelty.baselines import KNNDetector

#: five points on a line, distances by hand
LINE = np.array([[0.0], [1.0], [3.0], [6.0], [10.0]])


def test_the_kth_distance_and_the_mean_by_hand():
    det = KNNDetector(n_neighbors=2).fit(LINE)
    # from 2.0: 1.0 and 3.0 at 1, 0.0 at 2; from 20.0: 10 and 6 at 10 and 14
    np.testing.assert_array_equal(det.raw_novelty([[2.0], [20.0]]), [1.0, 14.0])
    mean = KNNDetector(n_neighbors=2, method="mean").fit(LINE)
    np.testing.assert_array_equal(mean.raw_novelty([[2.0], [20.0]]), [1.0, 12.0])


def test_the_reference_leaves_each_training_input_out_of_its_own_neighbours():
    det = KNNDetector(n_neighbors=2).fit(LINE)
    # the 2nd nearest of the others: 0 -> 3 (3), 1 -> 3 (2), 3 -> 0 or 6 (3), 6 -> 10 (4), 10 -> 3 (7)
    np.testing.assert_array_equal(det.reference_, [3.0, 2.0, 3.0, 4.0, 7.0])
    assert det.raw_novelty(LINE).tolist() == [1.0, 1.0, 2.0, 3.0, 4.0]   # in-sample: each its own neighbour


def test_a_copy_of_a_training_input_is_at_distance_exactly_zero():
    rng = np.random.default_rng(0)
    X = rng.random((200, 20)) / 3.0                    # values no float holds exactly, 20 features
    assert np.all(KNNDetector(n_neighbors=1).fit(X).raw_novelty(X) == 0.0)
    assert np.all(KNNDetector(n_neighbors=2).fit(np.vstack([X, X])).raw_novelty(X) == 0.0)   # both copies
    assert np.all(KNNDetector(n_neighbors=1).fit(np.vstack([X, X])).reference_ == 0.0)        # itself out, its twin in


def test_the_novelty_is_the_comparable_scale_of_the_raw_score(blobs, far):
    det = novelty.make("knn").fit(blobs)
    assert det.n_neighbors == 5 and det.method == "largest"
    assert det.novelty(far)[0] > 0.99 > det.novelty(blobs[:1])[0]


def test_fewer_training_inputs_than_neighbours_are_refused():
    with pytest.raises(ValueError, match=r"more training inputs than n_neighbors=5 .* n_samples = 5"):
        KNNDetector().fit(LINE)
    with pytest.raises(ValueError, match=r"'method' parameter of KNNDetector must be"):
        KNNDetector(method="median").fit(LINE)


def test_a_saved_model_scores_as_the_fitted_one(tmp_path, blobs, far):
    det = KNNDetector(n_neighbors=3).fit(blobs)
    det.save(tmp_path / "knn.npz")
    again = novelty.load(tmp_path / "knn.npz")
    X = np.vstack([blobs[::7], far])
    np.testing.assert_array_equal(again.raw_novelty(X), det.raw_novelty(X))
    np.testing.assert_array_equal(again.novelty(X), det.novelty(X))


@pytest.mark.parametrize("method", ["largest", "mean"])
def test_scores_equal_pyods_knn(blobs, far, method):
    knn = pytest.importorskip("pyod.models.knn")
    X = np.vstack([blobs[::3], far, blobs[:5]])         # copies of training inputs among them
    pyod = knn.KNN(method=method).fit(blobs)
    det = KNNDetector(method=method).fit(blobs)
    np.testing.assert_allclose(det.raw_novelty(X), pyod.decision_function(X), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.sort(det.reference_), np.sort(pyod.decision_scores_), rtol=1e-12, atol=1e-15)
