"""Novelty tasks: every builder of a registered dataset or task, by where its scans come from.

- :mod:`~novelty.tasks.recordings`: the task of a user's recordings
  (``recording``): runs, features marked from a CSV or places on a grid,
  visit counts from poses;
- :mod:`~novelty.tasks.places`: places and visits from a robot's poses,
  and the exploration task of places met for the first time and again;
- :mod:`~novelty.tasks.radish`: the tasks of the three Radish logs
  (``exploration-radish-*``, ``inspection-objects-radish-*``,
  ``exploration-objects-radish-*``);
- :mod:`~novelty.tasks.objects`: virtual objects placed in a real
  recording (``inspection-objects``, ``exploration-objects``).

Each builds a :class:`~novelty.data.Dataset`; :mod:`novelty.datasets` makes
them by name.
"""
