"""Places and visits from poses, and the exploration task of places met first and again."""

import numpy as np
import pytest

from novelty.tasks.places import leader_places, place_visits, revisit_task


def test_a_scan_founds_a_place_beyond_the_radius_of_every_place_before():
    # 0 founds place 0; 0.5 is within 1 m of it; 1.5 founds place 1; 1.2 is 1.2 from 0, 0.3 from 1.5
    place, founders = leader_places([[0.0, 0.0], [0.5, 0.0], [1.5, 0.0], [1.2, 0.0], [0.0, 0.9]], radius=1.0)
    assert place.tolist() == [0, 0, 1, 1, 0] and founders.tolist() == [0, 2]


def test_a_place_faced_the_other_way_is_another_place_with_max_turn():
    poses = [[0.0, 0.0, 0.0], [0.5, 0.0, np.pi], [0.2, 0.0, 0.3]]
    assert leader_places(poses, 1.0)[0].tolist() == [0, 0, 0]
    place, founders = leader_places(poses, 1.0, max_turn=np.pi / 2)
    assert place.tolist() == [0, 1, 0] and founders.tolist() == [0, 1]


def test_a_visit_ends_only_when_the_robot_goes_beyond_leave():
    # out along a line to 7 m, back to 3 m, out again: places 1 m apart (radius 0.6), leave 1.2 m
    x = [0, 1, 2, 3, 4, 5, 6, 7, 6, 5, 4, 3, 4, 5, 6, 7]
    poses = np.c_[np.array(x, float), np.zeros(len(x))]
    place, founders = leader_places(poses, 0.6)
    assert place.tolist() == x and founders.tolist() == list(range(8))
    # turning at 7 and back to 6 stays within 1.2 m of place 6: the same visit; 5 was left 2 m behind
    assert place_visits(poses, place, founders, leave=1.2).tolist() == [0] * 9 + [1, 1, 1, 1, 2, 1, 1]


@pytest.mark.parametrize("call, match", [
    (lambda: leader_places([[0.0, np.nan]], 1.0), "finite rows"),
    (lambda: leader_places([[0.0, 0.0]], 0.0), "radius must be a positive"),
    (lambda: leader_places([[0.0, 0.0]], 1.0, max_turn=1.0), "max_turn needs headings"),
    (lambda: leader_places([[0.0, 0.0, 0.0]], 1.0, max_turn=4.0), r"in \(0, pi\]"),
    (lambda: place_visits([[0.0, 0.0]], [0, 0], [0], 2.0), "one place a scan"),
])
def test_bad_places_are_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.fixture
def drive(tmp_path):
    """The drive above as a CARMEN log: the ranges say how far along it the robot is."""
    x = [0, 1, 2, 3, 4, 5, 6, 7, 6, 5, 4, 3, 4, 5, 6, 7]
    path = tmp_path / "drive.log"
    path.write_text("".join(f"FLASER 2 {1 + p} {1 + p} {p} 0 0 {p} 0 0 {t} host {t}\n" for t, p in enumerate(x)))
    return path


def test_places_after_the_warm_up_are_tracked_and_their_visits_are_exposures(drive):
    task = revisit_task(drive, radius=0.6, leave=1.2, run_scans=4, sectors=2)
    assert task.run.tolist() == [0] * 4 + [1] * 4 + [2] * 4 + [3] * 4
    assert task.split.tolist() == ["train"] * 4 + ["test"] * 12
    # places 0-3 were met in the warm-up: familiar; 4-7 are tracked, their exposure the visits before
    assert task.columns["feature"].tolist()[4:] == ["place 4", "place 5", "place 6", "place 7", "place 6",
                                                    "place 5", "place 4", "", "place 4", "place 5", "place 6",
                                                    "place 7"]
    assert task.columns["exposure"].tolist() == [-1] * 4 + [0, 0, 0, 0, 0, 1, 1, -1, 1, 2, 1, 1]
    assert task.y.tolist() == [0] * 4 + [1] * 5 + [0] * 7
    assert task.columns["visit"].tolist()[:4] == [0, 0, 0, 0]
    assert task.poses[:, 0].tolist() == [0, 1, 2, 3, 4, 5, 6, 7, 6, 5, 4, 3, 4, 5, 6, 7]
    assert task.metadata["places"] == {"radius_m": 0.6, "leave_m": 1.2, "max_turn_rad": None, "n_places": 8,
                                       "familiar_places": 4}
    assert task.metadata["exploration"]["warmup_runs"] == 1


def test_a_last_short_block_joins_the_run_before(drive):
    assert revisit_task(drive, radius=0.6, run_scans=5, sectors=2).run.tolist() == [0] * 5 + [1] * 5 + [2] * 6


@pytest.mark.parametrize("options, match", [
    ({"run_scans": 8, "warmup": 2}, "2 runs of 8, not more than warmup=2"),
    ({"run_scans": 0}, "run_scans must be an int >= 1"),
    ({"warmup": True}, "warmup must be an int >= 1"),
    ({"radius": 1.0, "leave": 0.5}, r"leave \(0.5\) must be at least radius"),
])
def test_bad_task_settings_are_refused(drive, options, match):
    with pytest.raises(ValueError, match=match):
        revisit_task(drive, sectors=2, **options)
