"""The examples in the trackers' docstrings run and print what they show."""

import doctest
import importlib

import pytest

MODULES = ["trackers", "trackers.threshold", "trackers.gauss3", "trackers.parabolic", "trackers.blais_rioux",
           "trackers.com_bg", "trackers.dp", "trackers._validation"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, extraglobs={"np": importlib.import_module("numpy")}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0, f"{name} has no docstring examples"
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"
