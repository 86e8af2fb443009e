"""The answers of "Which detector?", generated from the committed results of the suites that measure them.

README.md and docs/guide/which-detector.md hold regions ``<!-- generated:
which-detector/<part> -->``, rewritten by ``python benchmarks/tables.py`` like the
results tables (and checked by ``tests/test_tables.py``):

- ``answers``: the table, one row a question, the one detector that answers it
  and what was measured of it;
- ``count``: how many detectors the package registers;
- ``frozen``, ``learning``, ``paper``, ``long-term``: each answer's evidence in
  sentences.

The detector that answers a question is named once, in :mod:`novelty.answers`
(which the command line's examples and the quick benchmark's verdict read too),
and :data:`ANSWERS` here gives the rule that chose it; every figure, rank and count is computed here from the rows
committed in ``benchmarks/results/`` by the package's own report functions, so
the README, the guide and the site cannot disagree, and a new run of a suite
changes every sentence it measures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from novelty.answers import ANSWERS as USE

#: the suites the answers are measured on, by what they measure
DETECTION, EXPLORATION = "detection", "exploration"
OBJECTS_INSPECTION, OBJECTS_EXPLORATION = "objects-inspection", "objects-exploration"
#: the detectors of the points input (the robot's pose with each scan): their exploration and their guard
MAPS_EXPLORATION, MAPS_DETECTION = "maps-exploration", "maps-detection"
#: the detectors of the points input frozen on the objects tasks: the objects in seen and unseen places
MAPS_INSPECTION = "maps-inspection"
SUITES = (DETECTION, EXPLORATION, OBJECTS_INSPECTION, OBJECTS_EXPLORATION, MAPS_INSPECTION, MAPS_EXPLORATION,
          MAPS_DETECTION)
#: the maps of the bar and the occupancy grid they must be ahead of: the form chosen by studies/maps/maps-grid.md
MAPS, GRID = ("habituating-map", "map-explore"), "occupancy-grid-one-pass"
#: the bar on objects in seen places: inspection ROC AUC and first-encounter AUC (and chance, on unseen places)
BAR_INSPECTION, BAR_FIRST_SIGHT, CHANCE = 0.95, 0.90, 0.5
#: the answer before the rule of studies/learning_answer/learning-answer.md (the sonar ring alone)
BEFORE = "explore"


@dataclass(frozen=True)
class Answer:
    """One question of "Which detector?" and the detector that answers it."""

    key: str            # the region of its evidence: which-detector/<key>
    want: str           # the question, as the table asks it
    use: str            # the one detector named
    chosen: str         # how it was chosen (a sentence)
    what: str = ""      # what it is, where its name does not say


ANSWERS = (
    Answer("frozen", "to learn a clean area, freeze, then flag what differs", USE["frozen"],
           "its settings were chosen on the detection suite's selection seeds 5-9, which no table reports"),
    Answer("learning", "a robot that keeps learning: flag a feature at first sight, then let it grow familiar",
           USE["learning"],
           "chosen by a rule fixed before its run (`studies/learning_answer/learning-answer.md`) against `explore` "
           "and `habituating-map` on seeds 100-104 of the simulated open door, tour and patrol and the six objects "
           "tasks: the one candidate that stays above chance frozen on every hold-out task (seeds 5-9 and 105-109)",
           "a map of 0.2 m cells in the world frame, each with the paper's habituating synapse; it needs the "
           "robot's pose with each scan (the `points` input, [the map](objects.md#a-habituating-map-novelty-where-"
           "the-scan-was-taken-ours))"),
    Answer("no-pose", "the same, on a robot that does not know its pose (the sonar ring alone)",
           USE["no-pose"],
           "chosen by a rule fixed before its run (`studies/learning_answer/learning-answer-no-pose.md`) among the 13 "
           "habituating detectors of the ring, on the same tasks and seeds: the one that stays above chance frozen "
           "on every hold-out task (seeds 5-9 and 105-109), by 0.008",
           "a growing network with the Wang-Hsu long-term synapse, on the sonar ring"),
    Answer("paper", "the paper's exact behaviour", USE["paper"],
           "Marsland, Nehmzow & Shapiro (2000) with every constant of the paper"),
    Answer("long-term", "long-term habituation (a feature that returns settles lower each time)",
           USE["long-term"], "the Wang-Hsu synapse with the exploring network"),
    Answer("baseline", "a baseline to beat", USE["baseline"], "the reference of the detection suite"),
)
BY_KEY = {a.key: a for a in ANSWERS}


# ------------------------------------------------------------------ measuring
def _ordinal(n: int) -> str:
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def _ranked(rows: list[dict]) -> dict[str, dict]:
    from novelty.bench.reports.ranking import rank_detectors

    return {r["detector"]: r for r in rank_detectors(rows)}


def _seeds(rows: list[dict]) -> str:
    seeds = sorted({r["seed"] for r in rows})
    return f"seeds {seeds[0]}-{seeds[-1]}" if seeds == list(range(seeds[0], seeds[-1] + 1)) else \
        "seeds " + ", ".join(map(str, seeds))


def _tasks(rows: list[dict]) -> list[str]:
    return sorted({r["task"] for r in rows})


def _auc_rank(rows: list[dict], detector: str) -> str:
    """``0.716, 1st of 18``: the detector's ROC AUC over the suite and its rank."""
    ranked = _ranked(rows)
    record = ranked[detector]
    return f"{record['roc_auc']:.3f}, {_ordinal(record['rank'])} of {len(ranked)}"


def _exploration(rows: list[dict]) -> dict[str, dict[str, dict]]:
    """``{detector: {task: record}}`` of the exploration verdicts."""
    from novelty.bench.exploration.summary import exploration_records

    out: dict[str, dict[str, dict]] = {}
    for task, records in exploration_records(rows).items():
        for record in records:
            out.setdefault(record["detector"], {})[task] = record
    return out


def _short(task: str) -> str:
    return task.removeprefix("exploration-").removeprefix("objects-")


def _where(found: dict[str, dict], verdict: str) -> list[str]:
    """The tasks (short names) on which a detector's record has ``verdict`` (flags, habituates, both)."""
    return [_short(t) for t, r in sorted(found.items()) if r[verdict]]


def _on(names: list[str], of: int, what: str) -> str:
    """``4 of the 9 exploration tasks (irregular, open-door, return, tour)``; ``none of the 3 logs``."""
    return f"{len(names)} of the {of} {what} ({', '.join(names)})" if names else f"none of the {of} {what}"


def _count(names: list[str]) -> str:
    """``none``, ``1 (open-door)``, ``2 (open-door, return)``."""
    return f"{len(names)} ({', '.join(names)})" if names else "none"


def _plural(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


def _mean_auc(found: dict[str, dict]) -> float:
    return sum(r["auc"] for r in found.values()) / len(found)


def _auc_place(by_detector: dict[str, dict[str, dict]], detector: str) -> str:
    """``0.646, 7th of 21``: the detector's mean first-encounter AUC over the tasks and its rank."""
    means = sorted(((_mean_auc(f), d) for d, f in by_detector.items()), key=lambda m: (-m[0], m[1]))
    rank = [d for _, d in means].index(detector) + 1
    return f"{_mean_auc(by_detector[detector]):.3f}, {_ordinal(rank)} of {len(means)}"


def _span(values) -> str:
    values = sorted(values)
    return f"{values[0]:.2f}-{values[-1]:.2f}"


def _verdicts_on(found: dict[str, dict], what: str) -> str:
    """``flagging on none and habituating on 1 of the 3 objects tasks (aces)``."""
    flags, habituates = _where(found, "flags"), _where(found, "habituates")
    if not flags and not habituates:
        return f"flagging and habituating on none of the {len(found)} {what}"
    return (f"flagging on {_on(flags, len(found), what)} and habituating on "
            f"{_on(habituates, len(found), what)}")


def _guard_low(rows: list[dict], detector: str) -> tuple[float, str]:
    """The detector's lowest mean ROC AUC over the hold-out tasks, and its task."""
    by_task = {}
    for r in rows:
        if r["detector"] == detector and r.get("status") == "ok":
            by_task.setdefault(r["task"], []).append(float(r["roc_auc"]))
    return min((sum(v) / len(v), t) for t, v in by_task.items())


def _chance(value: float) -> str:
    """``, at chance`` for a mean ROC AUC that rounds to 0.500, ``, below chance`` under it, else nothing."""
    if round(value, 3) == 0.5:
        return ", at chance"
    return ", below chance" if value < 0.5 else ""


def _kinds(found: dict[str, dict]) -> tuple[list[float], list[float]]:
    """First-encounter AUCs on the simulated tasks and on the objects tasks."""
    return ([r["auc"] for t, r in found.items() if "radish" not in t],
            [r["auc"] for t, r in found.items() if "objects" in t])


def _verdicts(found: dict[str, dict], what: str) -> str:
    """``flags first sight on 1 (csail-familiar) and habituates on none of the 9 exploration tasks it runs``."""
    return (f"flags first sight on {_count(_where(found, 'flags'))} and habituates on "
            f"{_count(_where(found, 'habituates'))} of the {len(found)} {what}")


def facts(results: Callable[[str], list[dict]]) -> dict[str, str]:
    """The measured cell of each answer's row, from the committed rows (``results(suite)``)."""
    detection, exploration = results(DETECTION), _exploration(results(EXPLORATION))
    inspection, objects = results(OBJECTS_INSPECTION), _exploration(results(OBJECTS_EXPLORATION))
    maps = _exploration(results(MAPS_EXPLORATION))
    tasks_detection = f"{len(_tasks(detection))} tasks x {_seeds(detection)}"
    aucs = [r["roc_auc"] for r in _ranked(inspection).values()]
    use = BY_KEY["learning"].use
    simulated, on_objects = _kinds(maps[use])
    low, low_task = _guard_low(results(MAPS_DETECTION), use)
    long_term = exploration[BY_KEY["long-term"].use]
    no_pose = BY_KEY["no-pose"].use
    ring_low, ring_low_task = _guard_low(detection, no_pose)
    both = {d for d, found in exploration.items() for r in found.values() if r["both"]}
    return {
        "frozen": (f"ROC AUC {_auc_rank(detection, BY_KEY['frozen'].use)} on the detection suite "
                   f"({tasks_detection}; `{BY_KEY['baseline'].use}` {_auc_rank(detection, BY_KEY['baseline'].use)}); "
                   f"with virtual objects in real recordings {_auc_rank(inspection, BY_KEY['frozen'].use)}, "
                   f"every detector within {_span(aucs)}"),
        "learning": (f"needs the robot's pose with each scan; frozen, its lowest mean ROC AUC on the hold-out tasks "
                     f"with poses is {low:.3f} ({low_task}); learning, it {_verdicts(maps[use], 'exploration tasks it runs')} "
                     f"(first-encounter AUC {_span(simulated)} on the simulated tasks, {_span(on_objects)} with virtual "
                     f"objects in real recordings, mean {sum(on_objects) / len(on_objects):.3f}; `{BEFORE}` on the "
                     f"sonar ring {_mean_auc(objects[BEFORE]):.3f})"),
        "no-pose": (f"frozen, its lowest mean ROC AUC on the detection suite is {ring_low:.3f} "
                    f"({ring_low_task}{_chance(ring_low)}); "
                    f"learning, it {_verdicts(exploration[no_pose], 'exploration tasks')}; with virtual objects in "
                    f"real recordings its mean first-encounter AUC is {_auc_place(objects, no_pose)} ring detectors"),
        "paper": (f"the paper's claims the tests check hold on seeds 0-9; frozen it is near chance: ROC AUC "
                  f"{_auc_rank(detection, BY_KEY['paper'].use)} on the detection suite"),
        "long-term": (f"flags and habituates on {_on(_where(long_term, 'both'), len(long_term), 'exploration tasks')}; "
                      f"{len(both)} of the suite's {len(exploration)} detectors {'does' if len(both) == 1 else 'do'} both on any "
                      "task"),
        "baseline": f"ROC AUC {_auc_rank(detection, BY_KEY['baseline'].use)} on the detection suite",
    }


def answers_table(results: Callable[[str], list[dict]]) -> str:
    """The table of the README and the guide: what you want, the one detector, what was measured."""
    measured = facts(results)
    lines = ["| you want | use | measured |", "| --- | --- | --- |"]
    lines += [f"| {a.want} | `{a.use}` | {measured[a.key]} |" for a in ANSWERS]
    return "\n".join(lines)


def _registered() -> list[str]:
    from novelty.registry import detectors

    return detectors.names()


def count_text() -> str:
    """How many detectors the package registers (plugins and detectors registered at run time aside)."""
    from novelty.registry import detectors

    own = [n for n in detectors.names() if getattr(detectors.get(n), "__module__", "").startswith("novelty.")]
    return f"{len(own)} detectors are registered (`novelty list detectors`)."


# ------------------------------------------------------------------ each answer's evidence
def _paired(rows: list[dict], detector: str, reference: str) -> str:
    """``+0.002 ± 0.004 over the 8 tasks (4 won, 0 tied, 4 lost)``: per-task differences of ROC AUC."""
    import numpy as np
    from novelty.bench.stats.aggregate import task_table

    table = task_table(rows, detectors=[detector, reference]).complete()
    diff = table.row(detector) - table.row(reference)
    se = float(np.std(diff, ddof=1) / np.sqrt(diff.size))
    won, tied = int(np.sum(diff > 0)), int(np.sum(diff == 0))
    return (f"{float(diff.mean()):+.3f} ± {se:.3f} over the {diff.size} tasks ({won} won, {tied} tied, "
            f"{diff.size - won - tied} lost)")


def frozen_text(results: Callable[[str], list[dict]]) -> str:
    detection, inspection = results(DETECTION), results(OBJECTS_INSPECTION)
    use, baseline, paper = BY_KEY["frozen"].use, BY_KEY["baseline"].use, BY_KEY["paper"].use
    ranked = _ranked(detection)
    best_other = next(d for d in ranked if d not in (use, baseline))
    aucs = [r["roc_auc"] for r in _ranked(inspection).values()]
    return "\n".join([
        f"- **Use `{use}`**: ROC AUC {_auc_rank(detection, use)} on the detection suite "
        f"({len(_tasks(detection))} tasks x {_seeds(detection)}), level with `{baseline}` "
        f"({_auc_rank(detection, baseline)}; paired, {_paired(detection, use, baseline)}) and ahead of "
        f"`{best_other}` ({_auc_rank(detection, best_other)}); {BY_KEY['frozen'].chosen}.",
        f"- **With virtual objects in real recordings** ([the objects guide](objects.md); "
        f"{len(_tasks(inspection))} Radish logs x {_seeds(inspection)}) it scores {_auc_rank(inspection, use)}, "
        f"and every detector lies within {_span(aucs)}: frozen, no detector finds the objects.",
        f"- **Not the paper's `{paper}`** for this: frozen, it scores {_auc_rank(detection, paper)}.",
    ])


def learning_text(results: Callable[[str], list[dict]]) -> str:
    exploration, objects = _exploration(results(EXPLORATION)), _exploration(results(OBJECTS_EXPLORATION))
    maps, guard = _exploration(results(MAPS_EXPLORATION)), results(MAPS_DETECTION)
    detection = results(DETECTION)
    use, no_pose = BY_KEY["learning"].use, BY_KEY["no-pose"].use
    found, ring = maps[use], exploration[no_pose]
    ring_low, ring_low_task = _guard_low(detection, no_pose)
    low, low_task = _guard_low(guard, use)
    others = sorted(d for d in {r["detector"] for r in guard} if d != use)
    # an answer is a detector the reader can make: a registered name, not one the benchmark alone runs
    registered = {r["detector"] for r in results(EXPLORATION)
                  if r.get("detector_name", r["detector"]) in _registered()}
    most = max(sorted(registered & set(exploration)), key=lambda d: len(_where(exploration[d], "flags")))
    habituating = [d for d, f in objects.items() if _where(f, "habituates")]
    flagging = [d for d, f in objects.items() if _where(f, "flags")]

    firsts = ", ".join(f"{_short(task)} {record['auc']:.2f}" for task, record in sorted(found.items()))

    def guard_of(detector: str) -> str:
        value, task = _guard_low(guard, detector)
        return f"`{detector}` {value:.3f} ({task}{_chance(value)})"

    return "\n".join([
        f"- **Use `{use}`** (`novelty.make(\"{use}\")`: {BY_KEY['learning'].what}), "
        f"{BY_KEY['learning'].chosen}. On seeds 0-4 it {_verdicts(found, 'exploration tasks it runs')}: "
        f"{firsts} at first sight; its mean first-encounter AUC is {_auc_place(maps, use)} of the detectors "
        "given the same rows.",
        f"- **Frozen** (the hold-out tasks with poses, {_seeds(guard)}) its lowest mean ROC AUC is {low:.3f} "
        f"({low_task}); " + "; ".join(guard_of(d) for d in others) + ".",
        f"- **Without a pose** (the sonar ring alone) use `{no_pose}` ({BY_KEY['no-pose'].what}), "
        f"{BY_KEY['no-pose'].chosen}. On seeds 0-4 it {_verdicts(ring, 'exploration tasks')}: "
        + ", ".join(f"{_short(task)} {record['auc']:.2f}" for task, record in sorted(ring.items()))
        + f" at first sight; with virtual objects in real recordings its mean first-encounter AUC is "
        f"{_auc_place(objects, no_pose)} ring detectors (`{BEFORE}`, the answer before, {_auc_place(objects, BEFORE)}; "
        f"it fell below chance frozen on the guard's seeds 105-109); of those, "
        f"{_plural(len(flagging), 'flags', 'flag')} on any objects task and "
        f"{_plural(len(habituating), 'habituates', 'habituate')} on any"
        + (f" ({', '.join(f'`{d}`' for d in habituating)})." if habituating else ".")
        + f" Frozen, its lowest mean ROC AUC on the detection suite ({_seeds(detection)}) is {ring_low:.3f} "
        f"({ring_low_task}{_chance(ring_low)}).",
        f"- **If only first sight matters**: `{most}` flags on the most, "
        f"{_on(_where(exploration[most], 'flags'), len(exploration[most]), 'exploration tasks')}, and "
        f"habituates on {_count(_where(exploration[most], 'habituates'))}.",
    ])


def paper_text(results: Callable[[str], list[dict]]) -> str:
    use = BY_KEY["paper"].use
    detection, found = results(DETECTION), _exploration(results(EXPLORATION))[BY_KEY["paper"].use]
    return (f"- **Use `{use}`**: {BY_KEY['paper'].chosen}. Frozen it scores ROC AUC {_auc_rank(detection, use)} on "
            f"the detection suite; learning as it explores it habituates on "
            f"{_on(_where(found, 'habituates'), len(found), 'exploration tasks')} and flags first sight on "
            f"{_count(_where(found, 'flags'))}.")


def long_term_text(results: Callable[[str], list[dict]]) -> str:
    exploration = _exploration(results(EXPLORATION))
    use, door = BY_KEY["long-term"].use, "exploration-open-door"

    def on_door(detector: str) -> str:
        r = exploration[detector][door]
        ratio = "no ratio" if r["ratio"] != r["ratio"] else f"3rd/1st {r['ratio']:.2f}"
        return f"`{detector}` AUC {r['auc']:.2f}, {ratio}"

    return "\n".join([
        f"- **Use `{use}`** on a robot, or put the synapse in any filter: "
        f"`novelty.make(\"habituating\", clusterer=\"gwr\", synapse=\"wang-hsu\")`. It flags and habituates "
        f"on {_on(_where(exploration[use], 'both'), len(exploration[use]), 'exploration tasks')}.",
        f"- **The synapse alone does not make a recurring feature familiar**: on `{door}`, "
        f"{on_door(use)}; {on_door('som-wang-hsu')}; {on_door('gwr-wang-hsu')}.",
    ])


def _side_by_side(found: dict) -> str:
    """``0.912 / 0.431 (intel 0.93 / 0.40, ...)``: seen / unseen over the recordings, then each recording's."""
    logs = [k for k in found["seen"] if k != "mean"]

    def pair(key: str, digits: int) -> str:
        return " / ".join("-" if v != v else f"{v:.{digits}f}" for v in (found["seen"][key], found["unseen"][key]))

    return f"{pair('mean', 3)} ({', '.join(f'{log} {pair(log, 2)}' for log in logs)})"


def _below_chance(found: dict) -> list[str]:
    return [log for log, v in found["unseen"].items() if log != "mean" and v == v and v < CHANCE]


def places_text(results: Callable[[str], list[dict]]) -> str:
    from novelty.bench.reports.place_tables import place_means

    inspection, exploration = place_means(results(MAPS_INSPECTION)), place_means(results(MAPS_EXPLORATION))
    detectors = list(dict.fromkeys([*inspection, *exploration]))
    lines = []
    for d in detectors:
        parts = []
        if d in inspection:
            parts.append(f"inspection ROC AUC {_side_by_side(inspection[d])}")
        if d in exploration:
            parts.append(f"first sight while learning {_side_by_side(exploration[d])}")
        lines.append(f"- `{d}`: " + "; ".join(parts) + ".")
    for d in MAPS:
        seen_i, seen_x = inspection[d]["seen"]["mean"], exploration[d]["seen"]["mean"]
        grid_i, grid_x = inspection[GRID]["seen"]["mean"], exploration[GRID]["seen"]["mean"]
        below = sorted(set(_below_chance(inspection[d])) | set(_below_chance(exploration[d])))
        checks = [
            (seen_i >= BAR_INSPECTION, f"inspection {seen_i:.3f} {'>=' if seen_i >= BAR_INSPECTION else '<'} "
                                       f"{BAR_INSPECTION}"),
            (seen_x >= BAR_FIRST_SIGHT, f"first sight {seen_x:.3f} {'>=' if seen_x >= BAR_FIRST_SIGHT else '<'} "
                                        f"{BAR_FIRST_SIGHT}"),
            (seen_i > grid_i and seen_x > grid_x, f"{'ahead of' if seen_i > grid_i and seen_x > grid_x else 'not ahead of'}"
                                                  f" `{GRID}` on both ({grid_i:.3f}, {grid_x:.3f})"),
            (not below, "never below chance on unseen places" if not below else
             f"below chance on unseen places on {', '.join(below)}"),
        ]
        met = all(ok for ok, _ in checks)
        lines.append(f"- **The bar for `{d}`** (seen places): {'met' if met else 'not met'}: "
                     + "; ".join(text for _, text in checks) + ".")
    return "\n".join(lines)


SECTIONS = {"frozen": frozen_text, "learning": learning_text, "places": places_text, "paper": paper_text,
            "long-term": long_term_text}


def region(name: str, results: Callable[[str], list[dict]]) -> str:
    """The text of the region ``which-detector/<name>`` (its caption first)."""
    caption = ("*Generated by `python benchmarks/tables.py` from `benchmarks/results/` "
               f"({', '.join(SUITES)}) and the answers named in `benchmarks/which_detector.py`.*")
    if name == "answers":
        return f"{caption}\n\n{answers_table(results)}\n"
    if name == "count":
        return f"{count_text()}\n"
    if name in SECTIONS:
        return f"{caption}\n\n{SECTIONS[name](results)}\n"
    raise KeyError(f"No region which-detector/{name!r}; regions: answers, count, {', '.join(SECTIONS)}.")
