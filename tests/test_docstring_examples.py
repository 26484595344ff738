"""Every docstring example of every module of trackers, scenes and bench runs and
prints what it shows (modules are found by walking the packages, not listed by hand)."""

import doctest
import importlib
import pathlib
import pkgutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]


def _modules():
    out = []
    for pkg in ("trackers", "scenes", "bench"):
        out.append(pkg)
        for info in pkgutil.walk_packages([str(REPO / pkg)], prefix=f"{pkg}."):
            if info.name.rpartition(".")[2] != "__main__":  # runs the program when imported
                out.append(info.name)
    return sorted(out)


MODULES = _modules()


def test_the_walk_finds_the_modules_the_old_list_skipped():
    assert {"bench.evaluate.metrics", "bench.evaluate.restore", "trackers.testing", "bench.store.runfolder", "scenes.cache"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    import numpy as np

    module = importlib.import_module(name)
    # other libraries imported in the same session (colour-science) change numpy's
    # print options globally; the examples show numpy's defaults
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np}, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"
