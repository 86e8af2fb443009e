from pathlib import Path

import pytest

#: The project's shared folder of public data, beside the repository.
SHARED = (Path(__file__).resolve().parents[2] / ".." / "shared" / "datasets").resolve()


@pytest.fixture(scope="session")
def shared_data() -> Path:
    if not SHARED.is_dir():
        pytest.skip(f"the shared data folder {SHARED} is absent (it lives beside the repository)")
    return SHARED
