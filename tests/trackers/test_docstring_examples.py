"""The examples in the trackers' docstrings run and print what they show."""

import doctest
import importlib

import pytest

MODULES = ["trackers", "trackers.threshold", "trackers.gauss3", "trackers.parabolic", "trackers.blais_rioux",
           "trackers.com_bg", "trackers.dp", "trackers._validation"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    import numpy as np

    module = importlib.import_module(name)
    # other libraries imported in the same session (colour-science) change numpy's
    # print options globally; the examples show numpy's defaults
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0, f"{name} has no docstring examples"
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"
