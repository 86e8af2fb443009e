"""Checking a suite's detectors and tasks against the registries before anything runs."""

from __future__ import annotations

from typing import Any

from .._component import Component
from ..datasets import load, registry
from ..io.tables.table import check_data_file
from ..registry import RegistryError, check_parameters
from .build import build_detector
from .exploration.prequential import check_policy, default_policy
from .specs import FILE_OPTIONS, FILES_TASK, DetectorSpec, SuiteError, TaskSpec

__all__ = ["check_detector", "check_task", "check_threshold", "with_policy"]


def check_threshold(rule: Any) -> None:
    """Refuse an alarm-threshold rule other than ``"max"`` or a quantile in (0, 1]."""
    if rule == "max":
        return
    if isinstance(rule, (int, float)) and not isinstance(rule, bool) and 0 < rule <= 1:
        return
    raise SuiteError(f"threshold must be \"max\" or a quantile in (0, 1]; got {rule!r}.")


def check_detector(spec: DetectorSpec):
    """Build the detector once: the registry refuses unknown names and parameters."""
    try:
        det = build_detector(spec)
        _validate_tree(det)
    except RegistryError as exc:
        raise SuiteError(str(exc)) from None
    except (ValueError, TypeError, ImportError) as exc:
        raise SuiteError(f"Detector {spec.label!r}: {exc}") from None
    return det


def _validate_tree(component) -> None:
    """Run the parameter checks of a component and of the components it holds.

    A ``random_state`` is checked here too (estimators check it only when
    they fit, which would fail every cell): None or an int seed.
    """
    # the bench's own seed rule first: a seed the harness cannot pass on is named as such,
    # before a component's broader rule (a Generator, any size) answers instead
    get_params = getattr(component, "get_params", None)
    params = get_params(deep=False) if get_params is not None else {}
    seed = params.get("random_state")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**32):
        raise ValueError(f"random_state must be None or an int seed in [0, 2**32); got {seed!r}.")
    validate = getattr(component, "_validate_params", None)
    if validate is not None:
        validate()
    for value in params.values():
        if isinstance(value, Component):  # not another library's objects: theirs is their own business
            _validate_tree(value)


def with_policy(spec: DetectorSpec, det) -> DetectorSpec:
    """The spec with its policy checked; a batch-only detector's default shown in its label."""
    if spec.policy:
        check_policy(spec.policy, det)
        return spec
    policy = default_policy(det)
    if policy == "online":
        return spec
    return DetectorSpec(spec.name, spec.params, f"{spec.label} ({policy})", policy, spec.instance)


def check_task(spec: TaskSpec) -> None:
    """Check a task's name and option names; load a task that is the same in every cell.

    A task read from files the suite names (``path``, ``test_path``) and the
    same in every cell (it takes no seed), or the ``files`` task (whose seed
    only draws its split), is loaded once here, so that a
    wrong column, label or split is refused before the run, with the message
    :func:`novelty.datasets.files.read_scans` gives (as ``novelty run``
    prints it), rather than failing every cell. Generated tasks, and data
    sets found through ``NOVELTY_DATA_DIR``, are built in the cells only.
    """
    if spec.data is not None:  # a task object of the Python API: nothing to look up
        return
    try:
        valid = registry.parameters(spec.name)
        if valid is not None:
            check_parameters(f"task '{spec.name}'", spec.options, valid)
    except RegistryError as exc:
        raise SuiteError(str(exc)) from None
    if spec.name == FILES_TASK:
        if "path" not in spec.options:
            raise SuiteError(f"Task {spec.label!r}: the {FILES_TASK!r} task needs path= (a .csv or .npz file).")
        for key in FILE_OPTIONS:
            if key in spec.options:
                try:  # the reader's own check: the same message as novelty run's
                    check_data_file(str(spec.options[key]))
                except (OSError, ValueError) as exc:
                    raise SuiteError(f"Task {spec.label!r}: {exc}") from None
    # a task read from the suite's files is loaded once now (with seed 0 if its split is drawn per seed)
    if valid is not None and any(key in spec.options for key in FILE_OPTIONS) and (
            "seed" not in valid or spec.name == FILES_TASK):
        try:
            load(spec.name, **spec.options)
        except (ValueError, TypeError, OSError) as exc:
            raise SuiteError(f"Task {spec.label!r}: {exc}") from None
