"""Provenance of a run: the revision of the code, whatever the install."""

import re

from novelty.bench import results


def test_a_checkout_reports_its_commit():
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?", results.git_revision())


def test_an_installed_package_reports_the_revision_its_build_recorded(tmp_path, monkeypatch):
    package = tmp_path / "novelty"
    package.mkdir()
    (package / results.BUILD_REVISION_FILE).write_text("0123abcd\n")
    monkeypatch.setattr(results, "_SOURCE_ROOT", tmp_path / "site-packages")  # no .git there
    monkeypatch.setattr(results.resources, "files", lambda name: tmp_path / name)
    assert results.git_revision() == "0123abcd"


def test_without_git_or_a_recorded_revision_it_says_unknown(tmp_path, monkeypatch):
    monkeypatch.setattr(results, "_SOURCE_ROOT", tmp_path)
    monkeypatch.setattr(results.resources, "files", lambda name: tmp_path / name)
    assert results.git_revision() == "unknown"
    assert results.provenance()["git_revision"] == "unknown"


def test_provenance_records_the_versions_that_matter():
    import json

    versions = json.loads(results.provenance()["versions"])
    assert {"novelty", "numpy", "scipy", "scikit-learn", "numba", "python"} <= set(versions)
