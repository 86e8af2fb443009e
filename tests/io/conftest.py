"""Where the Radish CARMEN logs are: beside the repository (``<repo>/../shared/datasets``), a level
further up for a checkout in a sub-folder, or ``$NOVELTY_DATA_DIR``; tests that need them skip without."""

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
RADISH = "radish-carmen-logs"


def radish_folder() -> Path | None:
    candidates = [Path(os.environ["NOVELTY_DATA_DIR"]) / RADISH] if os.environ.get("NOVELTY_DATA_DIR") else []
    candidates += [REPO.parent / "shared" / "datasets" / RADISH, REPO.parent.parent / "shared" / "datasets" / RADISH]
    return next((c for c in candidates if (c / "intel-corrected.log.gz").is_file()), None)


@pytest.fixture(scope="session")
def radish():
    folder = radish_folder()
    if folder is None:
        pytest.skip("the Radish CARMEN logs (shared/datasets/radish-carmen-logs beside the repository, "
                    "or $NOVELTY_DATA_DIR) are not on this machine")
    return folder
