"""LaserSectors: the sectors as a scikit-learn transformer, in a pipeline before the paper's preprocessing."""

import math

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.pipeline import make_pipeline

from novelty.io.scans.laser_sectors import LaserSectors
from novelty.sonar import SonarPreprocessor


def test_by_hand_with_invalid_readings():
    # 6 beams over 180 degrees in 3 sectors of two beams each
    X = [[1.0, np.nan, -np.inf, 3.0, 12.0, np.inf]]
    rings = LaserSectors(n_sectors=3, range_min=0.5, range_max=10.0).fit_transform(X)
    assert rings.tolist() == [[1.0, 0.5, np.inf]]
    paper = make_pipeline(LaserSectors(n_sectors=3, range_min=0.5, range_max=10.0), SonarPreprocessor(4.0))
    assert paper.fit_transform(X).tolist() == [[0.75, 0.875, 0.0]]


def test_geometry_front_and_names():
    X = np.array([[1.0, 2.0, 3.0, 4.0]])
    # beams at 0, 90, 180, 270 degrees, the front at 90: from the front they are at -90, 0, 90, -180,
    # so the ring from -180 degrees runs counter-clockwise: back, right, front, left
    sectors = LaserSectors(n_sectors=4, angle_min=0.0, angle_increment=math.pi / 2, front=math.pi / 2,
                           limits=(-math.pi, math.pi)).fit(X)
    assert sectors.sector_of_beam_.tolist() == [1, 2, 3, 0]
    assert sectors.transform(X).tolist() == [[4.0, 1.0, 2.0, 3.0]]
    assert sectors.get_feature_names_out().tolist() == ["sector0", "sector1", "sector2", "sector3"]
    assert clone(sectors).get_params() == sectors.get_params()


@pytest.mark.parametrize("params, match", [
    ({"n_sectors": 0}, "n_sectors"), ({"reduce": "max"}, "reduce"), ({"reduce": 101}, "reduce"),
    ({"range_min": -1.0}, "range_min"), ({"limits": (1.0, -1.0)}, "limits"), ({"n_sectors": 9}, "hold no beam"),
])
def test_bad_parameters_are_refused(params, match):
    with pytest.raises(ValueError, match=match):
        LaserSectors(**params).fit(np.ones((1, 4)))


def test_a_different_number_of_beams_is_refused():
    sectors = LaserSectors(n_sectors=2).fit(np.ones((1, 4)))
    with pytest.raises(ValueError, match="4 features"):
        sectors.transform(np.ones((1, 5)))
