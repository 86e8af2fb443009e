"""A warning, once per detector, of scans far outside the range its clusterer assumes."""

import warnings

import numpy as np
import pytest

import novelty


def far_outside(n=30, seed=0):
    """Standardised scans: what StandardScaler in front of the detector gives, far outside [0, 1]."""
    return np.random.default_rng(seed).normal(0.0, 3.0, (n, 3))


def test_scans_far_outside_the_assumed_range_warn_once():
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    with pytest.warns(novelty.ScanRangeWarning, match=r"starts its units uniformly in \[0, 1\] \(init='uniform'\).*"
                                         r"these scans lie far outside it \(from -\d.* to \d.*\).*MinMaxScaler") as seen:
        det.fit(far_outside())
        det.partial_fit(far_outside(seed=1))
        det.learn_one(far_outside(1)[0])
    assert len([w for w in seen if "far outside" in str(w.message)]) == 1


@pytest.mark.parametrize("name, params, X", [
    ("hsom", {}, np.random.default_rng(0).uniform(-0.5, 1.5, (30, 3))),  # near [0, 1]: not far
    ("hsom", {"init": "sample"}, far_outside()),  # units on the scans: no range assumed
    ("hsom", {"init_range": (-10.0, 10.0)}, far_outside()),  # the range given
    ("kmeans-stanley", {}, far_outside()),  # units placed on the scans
])
def test_no_warning_where_the_scans_fit_what_the_parameters_assume(name, params, X):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        novelty.make(name, **params).fit(X)


def test_a_preset_on_units_drawn_in_0_1_warns_too():
    with pytest.warns(novelty.ScanRangeWarning, match=r"GrowWhenRequired .*init='uniform'.*far outside"):
        novelty.make("gwr-novelty").fit(far_outside())
