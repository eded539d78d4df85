"""Shared by the package's tests: the plugin comes from the package's entry point (the build
tree's ldoem-*.dist-info on PYTHONPATH), as it would for a user."""

import os
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.fixture
def scenes():
    return Path(os.environ.get("LDOEM_SCENES", HERE.parent.parent / "scenes"))
