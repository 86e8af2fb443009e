"""The README's Python examples run as written."""

import re
from pathlib import Path

import pytest

import novelty

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_python_block_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the examples write model files
    names_before = set(novelty.registry.clusterers.names())
    try:
        exec(compile(BLOCKS[index], f"README.md[python block {index}]", "exec"), {})
    finally:
        for name in set(novelty.registry.clusterers.names()) - names_before:
            novelty.registry.clusterers.unregister(name)


def test_readme_custom_clusterer_passes_conformance():
    namespace = {}
    block = next(b for b in BLOCKS if "register_clusterer" in b)
    try:
        exec(block, namespace)
        from novelty.testing import check_conformance

        check_conformance(namespace["TinyKMeans"]())
        det = namespace["det"]
        import numpy as np

        out = det.stream(np.tile(np.full(16, 0.3), (5, 1)))
        assert out[0] == 1.0 and np.all(np.diff(out) < 0), "a repeated scan habituates"
    finally:
        novelty.registry.clusterers.unregister("tiny-kmeans")
