"""The registries: names, close matches, duplicates, decorators, lazy built-ins,
entry-point plugins and ``novelty.available()``."""

import subprocess
import sys
import textwrap
from importlib.metadata import EntryPoint
from pathlib import Path

import numpy as np
import pytest

import novelty
import novelty.registry as registry_module
from novelty.clusterers.som import SOM
from novelty.registry import InvalidParameterError, Registry, RegistryError, UnknownNameError

ROOT = Path(__file__).resolve().parents[1]


def square(side=1.0):
    """Area of a square.

    More text that is not the one-line description.
    """
    return side * side


@pytest.fixture
def reg():
    return Registry("widget", group="novelty.test-widgets")


@pytest.fixture
def plugin_module(tmp_path, monkeypatch):
    """A module on sys.path that records being imported."""
    name = "novelty_fake_plugin_mod"
    (tmp_path / f"{name}.py").write_text(textwrap.dedent('''
        """A fake third-party plugin."""
        def Widget(size=2):
            """A widget from a plugin."""
            return ("plugin widget", size)
    '''))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, name, raising=False)
    yield name
    sys.modules.pop(name, None)


# ------------------------------------------------------------- look-ups
def test_unknown_name_lists_close_matches_and_known_names():
    with pytest.raises(UnknownNameError) as info:
        novelty.make("hsm")
    msg = str(info.value)
    assert msg.startswith("Unknown detector 'hsm'. Did you mean 'hsom'")
    known = msg.split(" Known detectors: ")[1].rstrip(".").split(", ")
    assert {"habituating", "hsom"} <= set(known) and known == sorted(known)
    # usable both as a KeyError (a look-up) and a ValueError (bad argument)
    assert isinstance(info.value, KeyError) and isinstance(info.value, ValueError)


def test_unknown_name_without_close_match_still_lists_known_names():
    with pytest.raises(UnknownNameError, match=r"Unknown clusterer 'zzzz'\. Known clusterers: .*som"):
        registry_module.clusterers.get("zzzz")
    with pytest.raises(UnknownNameError, match=r"Did you mean 'stanley'"):
        novelty.make("habituating", synapse="stanly")


def test_unknown_parameter_names_the_valid_ones(reg):
    reg.register("square", square)
    with pytest.raises(InvalidParameterError) as info:
        reg.make("square", sid=3.0)
    assert str(info.value) == (
        "Unknown parameter 'sid' (did you mean 'side'?) for widget 'square'. Valid parameters: side."
    )
    with pytest.raises(InvalidParameterError, match=r"'n_row' \(did you mean 'n_rows'\?\) for clusterer 'som'.*"
                                                    r"Valid parameters: decay, .*learning_rate, .*n_columns, n_rows, .*radius"):
        registry_module.clusterers.make("som", n_row=3)
    with pytest.raises(InvalidParameterError, match=r"Unknown parameters 'a', 'b'"):
        reg.make("square", a=1, b=2)


def test_make_builds_with_params(reg):
    reg.register("square", square)
    assert reg.make("square", side=3.0) == 9.0
    som = registry_module.clusterers.make("som", n_rows=3)
    assert isinstance(som, SOM) and som.n_rows == 3


def test_factory_with_var_kwargs_checks_for_itself(reg):
    reg.register("anything", lambda **kw: kw)
    assert reg.parameters("anything") is None
    assert reg.make("anything", x=1) == {"x": 1}


# ----------------------------------------------------------- registration
def test_duplicates_refused_unless_replace(reg):
    reg.register("square", square)
    with pytest.raises(RegistryError, match=r"A widget named 'square' is already registered; pass replace=True"):
        reg.register("square", lambda side=1.0: 0.0)
    assert reg.make("square", side=2.0) == 4.0
    reg.register("square", lambda side=1.0: -side, replace=True)
    assert reg.make("square", side=2.0) == -2.0


def test_builtins_cannot_be_overwritten_by_accident():
    with pytest.raises(RegistryError, match="already registered"):
        novelty.register_clusterer("som", SOM)
    with pytest.raises(RegistryError, match="already registered"):
        novelty.register_detector("hsom", lambda: None)


@pytest.mark.parametrize("name", ["", " padded", 3, None])
def test_invalid_names_refused(reg, name):
    with pytest.raises(RegistryError, match="must be a non-empty string"):
        reg.register(name, square)


def test_decorator_registration_returns_the_object(reg):
    @reg.register("cube", description="A cube.")
    def cube(side=1.0):
        return side**3

    assert cube(2.0) == 8.0  # the decorator gives the function back unchanged
    assert reg.get("cube") is cube
    assert reg.describe("cube") == "A cube."
    reg.register("square", square)
    assert reg.describe("square") == "Area of a square."  # first docstring line
    assert reg.names() == ["cube", "square"] and len(reg) == 2 and list(reg) == ["cube", "square"]
    assert "cube" in reg and "sphere" not in reg
    assert "cube" in repr(reg)


def test_top_level_decorators_register_in_the_project_registries():
    @novelty.register_synapse("test-registry-synapse", description="Only for this test.")
    class Quiet(novelty.StanleySynapse):
        pass

    try:
        assert registry_module.synapses.get("test-registry-synapse") is Quiet
        assert novelty.available("synapses")["test-registry-synapse"] == "Only for this test."
        assert registry_module.synapses.name_of(Quiet()) == "test-registry-synapse"
    finally:
        registry_module.synapses.unregister("test-registry-synapse")
    assert "test-registry-synapse" not in registry_module.synapses
    with pytest.raises(UnknownNameError):
        registry_module.synapses.unregister("test-registry-synapse")


def test_name_of():
    assert registry_module.clusterers.name_of(SOM()) == "som"
    assert registry_module.clusterers.name_of(SOM) == "som"

    class Unregistered(SOM):
        pass

    assert registry_module.clusterers.name_of(Unregistered) is None


def test_string_registration_is_a_lazy_path(reg, plugin_module):
    reg.register("lazy", f"{plugin_module}:Widget")
    assert "lazy" in reg
    assert plugin_module not in sys.modules
    assert reg.make("lazy", size=5) == ("plugin widget", 5)
    assert plugin_module in sys.modules


# ------------------------------------------------------------ lazy imports
def run_python(code):
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


def test_importing_novelty_is_light():
    code = (
        "import novelty, sys; "
        "print('sklearn' in sys.modules, 'scipy' in sys.modules, 'novelty.clusterers.som' in sys.modules)"
    )
    assert run_python(code) == "False False False"


def test_builtins_are_imported_on_first_use():
    code = textwrap.dedent("""
        import sys, novelty
        from novelty import registry
        assert 'som' in registry.clusterers and 'stanley' in registry.synapses
        assert 'novelty.clusterers.som' not in sys.modules and 'sklearn' not in sys.modules
        registry.clusterers.get('som')
        print('novelty.clusterers.som' in sys.modules)
    """)
    assert run_python(code) == "True"


# ------------------------------------------------------ entry-point plugins
def test_entry_point_plugins_are_read_on_first_lookup(reg, plugin_module, monkeypatch):
    calls = []

    def fake_entry_points(group):
        calls.append(group)
        return [EntryPoint(name="plugged", value=f"{plugin_module}:Widget", group=group)]

    monkeypatch.setattr(registry_module, "entry_points", fake_entry_points)
    fresh = Registry("widget", group="novelty.test-widgets")
    assert calls == []  # not at construction
    assert "plugged" in fresh
    assert calls == ["novelty.test-widgets"]
    assert plugin_module not in sys.modules  # advertised, not yet imported
    assert fresh.make("plugged", size=3) == ("plugin widget", 3)
    assert fresh.describe("plugged") == "A widget from a plugin."
    fresh.names()
    assert calls == ["novelty.test-widgets"]  # read once


def test_builtins_and_registrations_win_over_plugins(plugin_module, monkeypatch):
    monkeypatch.setattr(
        registry_module,
        "entry_points",
        lambda group: [EntryPoint(name="square", value=f"{plugin_module}:Widget", group=group),
                       EntryPoint(name="other", value=f"{plugin_module}:Widget", group=group)],
    )
    fresh = Registry("widget", group="novelty.test-widgets", builtins={"square": "math:sqrt"})
    import math

    assert fresh.get("square") is math.sqrt and plugin_module not in sys.modules
    assert fresh.names() == ["other", "square"]
    with pytest.raises(RegistryError, match="already registered"):
        fresh.register("other", square)
    fresh.register("other", square, replace=True)
    assert fresh.get("other") is square


def test_a_project_registry_reads_its_own_group(monkeypatch):
    groups = []
    monkeypatch.setattr(registry_module, "entry_points", lambda group: groups.append(group) or [])
    for reg in (registry_module.clusterers, registry_module.synapses, registry_module.detectors):
        fresh = Registry(reg.kind, group=reg.group)
        fresh.names()
    assert groups == ["novelty.clusterers", "novelty.synapses", "novelty.detectors"]


# ----------------------------------------------------------------- available
def test_available_structure():
    everything = novelty.available()
    assert set(everything) == {"detectors", "clusterers", "synapses", "datasets"}
    for entries in everything.values():
        assert isinstance(entries, dict)
        for name, description in entries.items():
            assert isinstance(name, str) and name == name.lower() and name.strip() == name
            assert isinstance(description, str) and description and "\n" not in description
    assert {"hsom", "habituating"} <= set(everything["detectors"])
    assert "som" in everything["clusterers"] and "stanley" in everything["synapses"]
    assert everything["detectors"]["hsom"].startswith("The paper's Habituating SOM")
    assert novelty.available("clusterers") == everything["clusterers"]


def test_available_unknown_kind():
    with pytest.raises(ValueError, match=r"Unknown kind 'models'; expected one of detectors, clusterers, synapses, datasets"):
        novelty.available("models")


def test_descriptions_is_read_only(reg):
    reg.register("square", square)
    view = reg.descriptions()
    with pytest.raises(TypeError):
        view["square"] = "changed"


# ------------------------------------------------------- one registry per kind
def test_of_kind_finds_each_registry_by_the_kind_it_holds():
    from novelty import datasets

    assert registry_module.KINDS == ("detector", "clusterer", "synapse", "dataset")
    for kind in registry_module.KINDS:
        assert registry_module.of_kind(kind).kind == kind
    assert registry_module.of_kind("clusterer") is registry_module.clusterers
    assert registry_module.of_kind("dataset") is datasets.registry
    for bad in ("clusterers", "model", None):
        with pytest.raises(RegistryError, match="expected 'detector', 'clusterer', 'synapse' or 'dataset'"):
            registry_module.of_kind(bad)


def test_build_makes_a_name_and_clones_an_instance_without_touching_it():
    som = registry_module.build("clusterer", "som", n_rows=3, learning_rate=0.5)
    assert isinstance(som, SOM) and (som.n_rows, som.learning_rate) == (3, 0.5)
    som.initialize(np.zeros((2, 4)), random_state=0)
    copy = registry_module.build("clusterer", som, n_columns=2)
    assert isinstance(copy, SOM) and copy is not som
    assert (copy.n_rows, copy.n_columns, copy.learning_rate) == (3, 2, 0.5)
    assert som.n_columns == 10 and not hasattr(copy, "weights_"), "parameters copied, state and caller's object not"
    with pytest.raises(UnknownNameError, match="soom"):
        registry_module.build("clusterer", "soom")
