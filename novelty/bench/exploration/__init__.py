"""The exploration protocol: every scan scored, then learned, in order.

One place for everything of this protocol:

- :mod:`~novelty.bench.exploration.prequential`: what a cell computes, and
  the learning policies (online, frozen, refit, window=N);
- :mod:`~novelty.bench.exploration.metrics`: first-encounter detection,
  habituation over exposures, false alarms, re-detection, integrated novelty
  per run;
- :mod:`~novelty.bench.exploration.summary`: the exploration tables;
- :mod:`~novelty.bench.exploration.plots`: novelty along the exploration,
  exposure curves, learning curves.

The tasks it runs on are datasets (:mod:`novelty.tasks.exploration`,
built with :func:`novelty.tasks.exploration.from_runs` from recorded runs). The
harness reads the protocol through :data:`PROTOCOL`.

Shares its name with ``novelty/tasks/exploration/``: the exploration protocol lives in the benchmark
beside the hold-out protocol, its tasks among the tasks.
"""

from ..protocol import Protocol
from .plots import plot_exploration
from .prequential import EXPLORATION_COLUMNS, evaluate
from .summary import exploration_markdown, exploration_text

__all__ = ["PROTOCOL"]

#: the exploration protocol as the harness sees it
PROTOCOL = Protocol(
    name="exploration",
    evaluate=evaluate,
    columns=tuple(EXPLORATION_COLUMNS),
    metric="roc_auc",
    metric_name="first-encounter ROC AUC",
    table=exploration_text,
    summary=exploration_markdown,
    plots=plot_exploration,
)
