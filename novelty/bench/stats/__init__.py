"""Statistics of a benchmark: aggregates over seeds and comparisons of detectors.

- :mod:`~novelty.bench.stats.aggregate`: result rows as numbers, means and
  spreads;
- :mod:`~novelty.bench.stats.across_tasks`: ranks, Friedman's test,
  Wilcoxon-Holm pairs and the critical-difference groups (Demsar 2006);
- :mod:`~novelty.bench.stats.signed_rank`: the pairwise Wilcoxon signed-rank
  tests and Holm's correction.

Shares its name with novelty/rosnode/stats.py: this is the benchmark's statistics, that the live
node's counts.
"""
