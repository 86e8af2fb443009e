"""The hold-out protocol: train on the familiar route, freeze, score the test part.

One place for everything of this protocol:

- :mod:`~novelty.bench.holdout.evaluate`: what a cell computes;
- :mod:`~novelty.bench.holdout.metrics`: the metrics of a cell (ROC AUC,
  average precision, TPR at a low FPR, detection delay, false alarms,
  integrated novelty);
- :mod:`~novelty.bench.holdout.summary`: the ranked table;
- :mod:`~novelty.bench.holdout.plots`: ROC curves, novelty along the route,
  ROC AUC per task, boxplots over seeds.

The harness reads them through :data:`PROTOCOL`.
"""

from ..protocol import Protocol
from .evaluate import METRIC_COLUMNS, evaluate
from .plots import plot_run
from .summary import ranking_text, summary_sections

__all__ = ["PROTOCOL"]

#: the hold-out protocol as the harness sees it
PROTOCOL = Protocol(
    name="holdout",
    evaluate=evaluate,
    columns=tuple(METRIC_COLUMNS),
    metric="roc_auc",
    metric_name="ROC AUC",
    table=ranking_text,
    summary=summary_sections,
    plots=plot_run,
)
