"""The trial protocol of Marsland, Nehmzow & Shapiro (2000), its Table 1 and its figures.

Section 3.2 ("Description of the Experiments") and section 4: trials come in
pairs, a learning run (L) along the 10 m route that trains the filter and saves
it, then a non-learning run (NL) that only records novelty; every run starts
from the model saved after the previous learning run. The order, as in
Table 1:

- experiment 1, environment A: L, NL, L, NL, L, NL from an untrained filter;
- experiment 1, A* (a door opened): NL, L, NL, L, NL from the model learned in A;
- experiment 2, B: NL, L, NL, L, NL from the model learned in A, then the
  control: B scored by a filter trained in the open "control" area;
- experiment 3, C: the same as B.

Each run is a fresh wall-following traversal (new run-to-run variation),
seeded. For each trial the table gives the output of the output neuron
integrated over the run with the resting activity subtracted (0.0476 a step
for the paper's constants) and its maximum.

The paper continued in A "until a non-learning run showed only the resting
activity" and needed three pairs. ``a_pairs=3`` (the default) keeps Table 1's
count; ``a_pairs=None`` applies the paper's rule instead (:func:`is_resting`),
adding pairs until it holds (at most ``max_a_pairs``), so that A*, B and C
start from a model that has settled in A.

The paper does not say how long the control filter was trained; here it
learns as many runs of the control area as A had learning runs, unless
``control_runs`` says otherwise.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, sections 3-4, Table 1,
figures 4 and 5.

The package by job: :mod:`~novelty.reproduce.trial` (a trial and the
resting criterion), :mod:`~novelty.reproduce.protocol` (running the trials),
:mod:`~novelty.reproduce.table1` (the table beside the paper's) and
:mod:`~novelty.reproduce.figures` (figures 4 and 5).

Shares its name with ``novelty/cli/reproduce.py``: the paper's experiments, and the command that
runs them (a command's module is named after the command).
"""

from .figures import plot_experiment1, plot_experiments2_3, write_figures
from .protocol import ENVIRONMENTS, run_protocol  # noqa: F401  (ENVIRONMENTS: read from here too)
from .table1 import (PAPER_TABLE1, TABLE1_COLUMNS, table1_markdown, table1_rows,  # noqa: F401
                     write_table1_csv, write_table1_markdown)
from .trial import RESTING_INTEGRATED, RESTING_MAXIMUM, Trial, is_resting

__all__ = ["PAPER_TABLE1", "Trial", "run_protocol", "is_resting", "table1_rows", "table1_markdown",
           "write_table1_csv", "write_table1_markdown", "plot_experiment1", "plot_experiments2_3",
           "write_figures", "RESTING_INTEGRATED", "RESTING_MAXIMUM"]
