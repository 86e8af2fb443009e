"""Novelty tasks: every builder of a registered dataset or task, by where its scans come from.

- simulated by :mod:`novelty.sonar`: the paper's environments and tasks
  (:mod:`~novelty.tasks.paper`, built by :mod:`~novelty.tasks.simulated`),
  inspection corridors with inserted novelties
  (:mod:`~novelty.tasks.inspection`), explorations
  (:mod:`~novelty.tasks.exploration`: runs in order, features that appear,
  recur and change; :func:`~novelty.tasks.exploration.from_runs` builds one
  of your own runs); a simulated task's rows as the ``points`` input
  (:mod:`~novelty.tasks.inputs`);
- read from the user's files: the public UCI data sets
  (:mod:`~novelty.tasks.uci`), a file of scans split into a training and a
  test part (:mod:`~novelty.tasks.files`, :mod:`~novelty.tasks.resampling`);
- read from robot recordings (:mod:`novelty.io`): the task of a user's
  recordings (:mod:`~novelty.tasks.recordings`: runs, features marked from a
  CSV or places on a grid), places met again (:mod:`~novelty.tasks.places`),
  virtual objects placed in a recording (:mod:`~novelty.tasks.objects`),
  the Radish logs' tasks (:mod:`~novelty.tasks.radish`).

Each builds a :class:`~novelty.data.Dataset`. Their names are one table,
:mod:`~novelty.tasks.registered`; :mod:`novelty.datasets` makes them by
name (``novelty.datasets.load("exploration-tour")``).
"""
