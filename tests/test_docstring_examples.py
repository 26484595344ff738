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


def _source(name: str) -> str:
    path = REPO / (name.replace(".", "/") + ".py")
    return (path if path.exists() else REPO / name.replace(".", "/") / "__init__.py").read_text(encoding="utf-8")


ALL_MODULES = _modules()
#: The modules with docstring examples: only these are tested here (a module without one passes nothing).
MODULES = [m for m in ALL_MODULES if ">>> " in _source(m)]
#: Modules without an example yet (numba kernels, command-line plumbing, package markers, studies that
#: render). The list is checked both ways: a new module without an example, or an example added to one
#: listed here, fails ``test_the_modules_without_examples_are_the_listed_ones`` until the list is updated.
WITHOUT_EXAMPLES = {
    "trackers._base", "trackers._stripe_kernels", "trackers._dp_gap", "trackers._dp_kernels", "trackers._dp_rows", "trackers._peak",
    "trackers._registry", "trackers._stats", "trackers._subpixel", "trackers.centroid", "trackers.dp_subpixel",
    "trackers.processes", "scenes", "scenes._checks", "scenes.contact_sheet", "scenes.laser", "scenes.params",
    "scenes.radiometry", "scenes.registry", "scenes.rows", "scenes.truth", "bench", "bench.api", "bench.cli",
    "bench.cli.common", "bench.cli.field_sheet", "bench.cli.gate_spread", "bench.cli.perf", "bench.cli.predict",
    "bench.cli.translucency_profile", "bench.cli.tune", "bench.cli.info", "bench.cli.real", "bench.cli.run", "bench.cli.studies", "bench.cli.submit",
    "bench.cli.sweep", "bench.cli.train", "bench.config.profiles", "bench.evaluate", "bench.evaluate._ap_kernel",
    "bench.evaluate.triangulation", "bench.report", "bench.report.simreal", "bench.report.sweep",
    "bench.run", "bench.run.cluster", "bench.run.plan", "bench.run.real", "bench.run.scan", "bench.run.score",
    "bench.run.sweep", "bench.store", "bench.store.figdata", "bench.studies",
    "bench.studies.estimators", "bench.studies.field_sheet", "bench.studies.perf", "bench.studies.perf.lit",
    "bench.studies.perf.mis", "bench.studies.perf.scenes", "bench.studies.perf.shiny", "bench.studies.perf.sweep",
    "bench.studies.perf.trackers",
}


def test_the_walk_finds_the_modules_the_old_list_skipped():
    assert {"bench.evaluate.metrics", "bench.evaluate.restore", "trackers.testing", "bench.store.runfolder", "scenes.cache"} <= set(MODULES)


def test_the_modules_without_examples_are_the_listed_ones():
    assert set(ALL_MODULES) - set(MODULES) == WITHOUT_EXAMPLES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    import numpy as np

    module = importlib.import_module(name)
    # other libraries imported in the same session (colour-science) change numpy's
    # print options globally; the examples show numpy's defaults
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0, f"{name} has '>>> ' in its source but doctest found no example"
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"
