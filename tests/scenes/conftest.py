"""Shared fixtures: a private render cache for the whole test session."""

import os

import pytest


@pytest.fixture(scope="session", autouse=True)
def _private_cache(tmp_path_factory):
    old = os.environ.get("STRIPEBENCH_CACHE_DIR")
    os.environ["STRIPEBENCH_CACHE_DIR"] = str(tmp_path_factory.mktemp("stripebench-cache"))
    yield
    if old is None:
        os.environ.pop("STRIPEBENCH_CACHE_DIR", None)
    else:
        os.environ["STRIPEBENCH_CACHE_DIR"] = old
