import pytest

from novelty import sonar

matplotlib = pytest.importorskip("matplotlib", reason="plotting is an optional extra")
matplotlib.use("Agg")


def test_map_with_one_scan_and_the_scan_image(tmp_path):
    import matplotlib.pyplot as plt

    ds = sonar.simulate("a", seed=0)
    ax = sonar.plot_map("a", ds, scan=30)
    assert len(ax.patches) >= 16 + 1  # one cone per sonar, and the robot
    ax2 = sonar.plot_scans(ds)
    image = ax2.get_images()[0].get_array()
    assert image.shape == (16, 100)
    ax2.figure.savefig(tmp_path / "scans.png")
    assert (tmp_path / "scans.png").stat().st_size > 1000
    plt.close("all")


def test_plot_map_needs_the_dataset_for_a_scan():
    import matplotlib.pyplot as plt

    with pytest.raises(ValueError, match="dataset"):
        sonar.plot_map("b", scan=3)
    plt.close("all")
