"""The one table of the registered datasets and tasks: each name and its builder, imported on first use.

:data:`novelty.registry.datasets` (``novelty.datasets.load(name)``) makes
them by name; every builder is in this package, by where its scans come
from: the paper's simulated environments (:mod:`~novelty.tasks.paper`),
generated corridors (:mod:`~novelty.tasks.inspection`), explorations
(:mod:`~novelty.tasks.exploration`), public data sets
(:mod:`~novelty.tasks.uci`), the user's files (:mod:`~novelty.tasks.files`)
and recordings (:mod:`~novelty.tasks.recordings`,
:mod:`~novelty.tasks.radish`, :mod:`~novelty.tasks.objects`). A new task is
a builder in one of them (or a module of its own here) and a line below.
"""

__all__ = ["TASKS"]

#: every registered dataset and task: its name and ``"module:builder"``
TASKS = {
    "paper-a": "novelty.tasks.paper:paper_a",
    "paper-a-star": "novelty.tasks.paper:paper_a_star",
    "paper-b": "novelty.tasks.paper:paper_b",
    "paper-c": "novelty.tasks.paper:paper_c",
    "paper-control": "novelty.tasks.paper:paper_control",
    "paper-a-to-a-star": "novelty.tasks.paper:paper_a_to_a_star",
    "paper-a-to-b": "novelty.tasks.paper:paper_a_to_b",
    "paper-a-to-c": "novelty.tasks.paper:paper_a_to_c",
    "inspection": "novelty.tasks.inspection:inspection",
    "inspection-easy": "novelty.tasks.inspection:inspection_easy",
    "inspection-medium": "novelty.tasks.inspection:inspection_medium",
    "inspection-hard": "novelty.tasks.inspection:inspection_hard",
    "exploration-tour": "novelty.tasks.exploration.tours:paper_tour",
    "exploration-open-door": "novelty.tasks.exploration.tours:open_door",
    "exploration-patrol": "novelty.tasks.exploration.tours:patrol",
    "exploration-irregular": "novelty.tasks.exploration.recurrence:irregular",
    "exploration-return": "novelty.tasks.exploration.recurrence:returning",
    "exploration-moving": "novelty.tasks.exploration.recurrence:moving",
    "uci-wall-following": "novelty.tasks.uci:uci_wall_following",
    "uci-wall-following-novelty": "novelty.tasks.uci:uci_wall_following_novelty",
    "uci-sonar": "novelty.tasks.uci:uci_sonar",
    "uci-sonar-mines": "novelty.tasks.uci:uci_sonar_mines",
    "files": "novelty.tasks.files:files",
    "recording": "novelty.tasks.recordings:recording_task",
    "exploration-radish-intel": "novelty.tasks.radish:radish_intel",
    "exploration-radish-aces": "novelty.tasks.radish:radish_aces",
    "exploration-radish-csail": "novelty.tasks.radish:radish_csail",
    "inspection-objects": "novelty.tasks.objects.object_tasks:inspection_task",
    "exploration-objects": "novelty.tasks.objects.object_tasks:exploration_task",
    "inspection-objects-radish-intel": "novelty.tasks.radish:inspection_objects_intel",
    "inspection-objects-radish-aces": "novelty.tasks.radish:inspection_objects_aces",
    "inspection-objects-radish-csail": "novelty.tasks.radish:inspection_objects_csail",
    "exploration-objects-radish-intel": "novelty.tasks.radish:exploration_objects_intel",
    "exploration-objects-radish-aces": "novelty.tasks.radish:exploration_objects_aces",
    "exploration-objects-radish-csail": "novelty.tasks.radish:exploration_objects_csail",
}
