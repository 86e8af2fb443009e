"""Novelty along the route: every mark the data has is drawn and named once in a legend."""

import numpy as np
import pytest

pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")

import matplotlib  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

from novelty.bench.reports import route  # noqa: E402

matplotlib.use("Agg")


def test_every_mark_of_a_route_is_named_and_runs_are_drawn_along_the_scans():
    fig, ax = plt.subplots()
    novelty = np.array([1.0, 0.5, 0.2, 0.9, 0.4, 0.1])
    along = route.plot_route(ax, novelty, y=[0, 1, 0, 0, 1, 0], distance=[0.1, 0.2, 0.3, 0.1, 0.2, 0.3],
                             threshold=0.6, resting=0.05, alarm=[1, 0, 0, 1, 0, 0])
    names = ax.get_legend_handles_labels()[1]
    assert sorted(names) == sorted([route.NOVELTY, route.NOVEL, route.THRESHOLD, route.RESTING, route.ALARM,
                                    route.RUN_START])
    assert along == "scan"  # the distance starts again at scan 3: two runs, drawn one after the other
    starts = [line.get_xdata()[0] for line in ax.lines if line.get_label() == route.RUN_START]
    assert starts == [3]
    (band,) = [c for c in ax.collections if c.get_label() == route.ALARM]
    # a span half a scan either side of each alarm (scans 0 and 3), along the top of the axes
    spans = sorted((p.vertices[:, 0].min(), p.vertices[:, 0].max()) for p in band.get_paths())
    assert spans == [(-0.5, 0.5), (2.5, 3.5)]
    assert all(p.vertices[:, 1].min() >= 0.9 for p in band.get_paths())   # in axes height: above the novelty
    assert ax.get_ylim()[1] * 0.93 >= novelty.max()
    plt.close(fig)


def test_a_threshold_known_from_a_scan_on_is_drawn_from_there():
    fig, ax = plt.subplots()
    route.plot_route(ax, [0.2, 0.9, 0.1, 0.8], threshold=[np.nan, np.nan, 0.5, 0.5], alarm=[np.nan, np.nan, 0, 1])
    (line,) = [line for line in ax.lines if line.get_label() == route.THRESHOLD]
    assert np.isnan(line.get_ydata()[:2]).all() and line.get_ydata()[2:].tolist() == [0.5, 0.5]
    assert [c.get_label() for c in ax.collections] == [route.ALARM]
    plt.close(fig)


def test_one_run_with_its_distance_draws_only_what_it_has():
    fig, ax = plt.subplots()
    along = route.plot_route(ax, [0.3, 0.2, 0.1], distance=[0.5, 1.0, 1.5])
    assert along == "distance along the route (m)"
    assert ax.get_legend_handles_labels()[1] == [route.NOVELTY]
    assert ax.lines[0].get_xdata().tolist() == [0.5, 1.0, 1.5]
    plt.close(fig)


def test_a_route_figure_has_one_legend_naming_each_mark_once():
    cell = {"novelty": np.array([0.2, 0.9, 0.1]), "y": np.array([0, 1, 0]), "distance": np.arange(3.0),
            "threshold": np.array(0.5), "resting": np.array(0.05)}
    fig = route.route_figure("t, seed 0", [("a", cell), ("b", {**cell, "resting": np.array(0.0)})])
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [route.NOVEL, route.NOVELTY, route.THRESHOLD,
                                                          route.RESTING, route.ALARM]  # scan 1 above 0.5
    assert fig.axes[-1].get_xlabel() == "scan"  # a distance equal to the scan's index is no distance
    plt.close(fig)
