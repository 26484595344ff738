"""Shared pytest configuration."""

import os

# numba's on-disk cache lives next to the sources; keep test runs from
# writing elsewhere unless the user chose a cache directory.
os.environ.setdefault("NUMBA_CACHE_DIR", os.path.join(os.path.dirname(__file__), "..", ".cache", "numba"))
