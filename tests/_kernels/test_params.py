"""The parameters of a component as its compiled steps read them: one record, a named field each.

Each field's name and type follow from the parameter's rule (the table of
:mod:`novelty._kernels.params`); these tests write the expected records by hand.
"""

from __future__ import annotations

import numbers

import numpy as np
import pytest

from novelty import KernelSpec, registry
from novelty._kernels.params import pack, param_names
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.clusterers.kmeans import OnlineKMeans
from novelty.clusterers.som import SOM
from novelty.habituation.base import SCHEDULE, Synapse
from novelty.habituation.stanley import StanleySynapse
from novelty.rules import Interval, Options, option_code


class Every(Synapse):
    """A synapse taking one parameter of each kind the table names."""

    _parameter_rules = {
        "count": Interval(numbers.Integral, 1, None),
        "rate": Interval(numbers.Real, 0, 1, allow_none=True),
        "flag": Options((True, False)),
        "mode": Options(("slow", "fast")),
        "step": (Options(("auto", "off")), Interval(numbers.Real, 0, None)),
        "start": Interval(numbers.Real, 0, None),
    }
    _kernel = KernelSpec(steps="unused", params=("count", "rate", "flag", "mode", "step", "level_"),
                         ignores=("start",), fitted=(("level_", float),))
    resting_efficacy = 0.5

    def __init__(self, count=3, rate=None, flag=True, mode="fast", step="off", start=0.0):
        self.count, self.rate, self.flag, self.mode, self.step, self.start = (
            count, rate, flag, mode, step, start)
        self.level_ = 2

    def _advance(self, rows, stimulus, tau, dt):
        pass

    def _fresh(self, n):
        return {"efficacy_": np.ones(n)}


def test_each_kind_of_parameter_has_its_named_typed_fields():
    record = pack(Every(others="forget", tau_forget=None))
    assert record.shape == (1,)
    assert [(name, record.dtype[name].str) for name in record.dtype.names] == [
        ("tau_winner", "<f8"), ("tau_neighbour", "<f8"), ("others", "<i8"),  # the schedule's
        ("tau_forget", "<f8"), ("has_tau_forget", "|b1"),
        ("count", "<i8"), ("rate", "<f8"), ("has_rate", "|b1"), ("flag", "|b1"), ("mode", "<i8"),
        ("step", "<f8"), ("step_is_auto", "|b1"), ("step_is_off", "|b1"), ("level_", "<f8")]
    assert record[0].tolist() == (3.33, 14.3, 1, 0.0, False, 3, 0.0, False, True, 1, 0.0, False,
                                  True, 2.0)
    record = pack(Every(rate=0.25, flag=False, mode="slow", step=1.5, tau_forget=7))
    assert record[0].tolist() == (3.33, 14.3, 0, 7.0, True, 3, 0.25, True, False, 0, 1.5, False,
                                  False, 2.0)


def test_option_codes_are_positions_among_the_rules_strings():
    assert [option_code(Every, "mode", m) for m in ("slow", "fast")] == [0, 1]
    assert [option_code(Every, "step", m) for m in ("auto", "off")] == [0, 1]
    assert option_code(SOM, "decay", "asymptotic") == 2
    with pytest.raises(ValueError, match="'medium' is not an option of Every.mode"):
        option_code(Every, "mode", "medium")


def test_a_som_record_reads_as_its_parameters():
    som = SOM(n_rows=3, n_columns=4, learning_rate=0.5, decay="linear", decay_steps=20)
    record = pack(som)[0]
    assert record["n_rows"] == 3 and record["n_columns"] == 4 and record["learning_rate"] == 0.5
    assert record["decay"] == option_code(SOM, "decay", "linear") == 1
    assert not record["has_neighbour_learning_rate"] and record["neighbour_learning_rate"] == 0.0
    record = pack(SOM(neighbour_learning_rate=0.125))[0]
    assert record["has_neighbour_learning_rate"] and record["neighbour_learning_rate"] == 0.125


def test_count_or_a_rate_and_a_fitted_radius():
    kmeans = OnlineKMeans(learning_rate="count", init="first")
    kmeans.placement_radius_ = 0.75
    record = pack(kmeans)[0]
    assert record["learning_rate_is_count"] and record["learning_rate"] == 0.0
    assert record["init"] == option_code(OnlineKMeans, "init", "first")
    assert record["placement_radius_"] == 0.75
    kmeans.learning_rate = 0.5
    assert pack(kmeans)[0][["learning_rate", "learning_rate_is_count"]].tolist() == (0.5, False)


def test_a_nested_component_is_a_record_of_its_own():
    gwr = GrowWhenRequired(max_units=40, new_unit_wins=True)
    gwr.activity_threshold_ = 0.5
    gwr.firing_ = StanleySynapse(tau_winner=2.5, method="exact")
    record = pack(gwr)[0]
    assert record["max_units"] == 40 and record["has_max_units"] and record["new_unit_wins"]
    assert record["firing_"]["tau_winner"] == 2.5 and record["firing_"]["alpha"] == 1.05
    assert record["firing_"]["method"] == option_code(StanleySynapse, "method", "exact")
    assert record.dtype["firing_"] == pack(gwr.firing_).dtype


def test_values_no_field_can_hold_are_refused():
    with pytest.raises(ValueError, match="Every.mode = 'medium' is not among its options"):
        pack(Every(mode="medium"))
    with pytest.raises(ValueError, match="Every.count = 18446744073709551616 is not an int64"):
        pack(Every(count=2**64))

    class Unruled(Every):
        _kernel = KernelSpec(steps="unused", params=("start", "undeclared"))

    unruled = Unruled()
    unruled.undeclared = 1.0
    with pytest.raises(TypeError, match="'undeclared', which has no rule"):
        pack(unruled)


@pytest.mark.parametrize("registry_", [registry.clusterers, registry.synapses], ids=lambda r: r.kind)
def test_every_registered_component_packs_a_field_per_parameter(registry_):
    for name in registry_.names():
        component = registry_.make(name)
        if "_kernel" not in vars(type(component)):
            continue
        if isinstance(component, GrowWhenRequired):
            component.initialize(np.zeros((2, 3)), 0)  # its fitted threshold and firing counters
        if isinstance(component, OnlineKMeans):
            component.placement_radius_ = 0.0
        fields = pack(component).dtype.names
        names = param_names(component)
        assert all(n in fields for n in names), (name, names, fields)
        if registry_ is registry.synapses:
            assert names[:len(SCHEDULE)] == tuple(SCHEDULE)
