"""The reports of a run, shared by the protocols: tables, ``summary.md``, the critical-difference diagram.

- :mod:`~novelty.bench.reports.format`: how numbers and tables are written;
- :mod:`~novelty.bench.reports.ranking`: detectors ranked, ROC AUC per task;
- :mod:`~novelty.bench.reports.statistics`: the paired comparison, ranks per
  task and the tests between detectors;
- :mod:`~novelty.bench.reports.summary`: ``summary.md``;
- :mod:`~novelty.bench.reports.place_tables`: objects tasks' scores on objects in
  seen and in unseen places, apart;
- :mod:`~novelty.bench.reports.figures` and
  :mod:`~novelty.bench.reports.critical_difference`: what the plots share,
  and the critical-difference diagram.
"""
