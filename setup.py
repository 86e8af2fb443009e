"""Build hook: record the git revision the package is built from.

Everything else is in pyproject.toml. A non-editable install has no .git
beside the code, so the build writes ``novelty/_revision.txt`` (the commit,
``+dirty`` if the tree was modified), which ``novelty.bench.results.git_revision``
reads; built without git (from a source archive), the file is left out and the
revision reads "unknown".
"""

import subprocess
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


def _git(*args: str) -> str:
    if not (ROOT / ".git").exists():  # an unpacked source archive, maybe inside someone else's repository
        return ""
    try:
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True,
                              timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


class BuildWithRevision(build_py):
    def run(self):
        super().run()
        revision = _git("rev-parse", "HEAD")
        # An editable install reads the checkout's .git instead (and builds no package folder here).
        if revision and not self.dry_run and not getattr(self, "editable_mode", False):
            dirty = _git("status", "--porcelain", "--untracked-files=no")
            target = Path(self.build_lib) / "novelty" / "_revision.txt"
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(revision + ("+dirty" if dirty else "") + "\n", encoding="utf-8")


setup(cmdclass={"build_py": BuildWithRevision})
