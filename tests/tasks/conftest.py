"""The Radish logs' fixture of the readers' tests, for the tasks built on them."""

from ..io.conftest import radish  # noqa: F401
