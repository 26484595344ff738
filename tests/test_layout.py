"""The importable packages are this repository's, not PyPI's namesakes."""

import importlib
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name", ["trackers", "bench", "scenes"])
def test_package_comes_from_this_repository(name):
    module = importlib.import_module(name)
    assert pathlib.Path(module.__file__).resolve().is_relative_to(REPO), module.__file__


def test_import_trackers_is_light():
    code = (
        "import sys, trackers; trackers.available(); "
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista', 'numba') if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == "", f"import trackers imported {out.stdout.strip()}"


def test_making_a_tracker_does_not_import_the_renderer():
    code = (
        "import sys, trackers; [trackers.make(n) for n in trackers.available()]; "
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista') if m in sys.modules]; print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == ""


# -- import rules, checked on the source (module-level and function-level imports) -------------------
import ast  # noqa: E402


def _imports(path: pathlib.Path, package: str, root: pathlib.Path = REPO) -> set[str]:
    """Absolute names of every module imported anywhere in ``path`` (relative imports resolved)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    parts = path.relative_to(root).with_suffix("").parts
    here = list(parts[:-1]) if parts[-1] != "__init__" else list(parts[:-1])
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
                if node.module is None:
                    out.update(f"{mod}.{a.name}" for a in node.names)
                else:
                    out.add(mod)
                    out.update(f"{mod}.{a.name}" for a in node.names)
            else:
                out.add(node.module)
                out.update(f"{node.module}.{a.name}" for a in node.names)
    return out


def _files(pkg):
    return sorted(p for p in (REPO / pkg).rglob("*.py") if "__pycache__" not in p.parts)


@pytest.mark.parametrize("pkg, banned", [
    ("trackers", ("mitsuba", "drjit", "matplotlib", "pyvista", "scenes", "bench")),
    ("scenes", ("trackers", "bench")),
])
def test_lower_packages_never_import_upwards(pkg, banned):
    bad = []
    for f in _files(pkg):
        for name in _imports(f, pkg):
            if name.split(".")[0] in banned:
                bad.append(f"{f.relative_to(REPO)} imports {name}")
    assert not bad, bad


def test_bench_modules_import_only_their_own_layer_or_lower():
    from bench import LAYERS

    rank = {m: i for i, (_, mods) in enumerate(LAYERS.items()) for m in mods}
    bad = []
    for f in _files("bench"):
        rel = f.relative_to(REPO / "bench").with_suffix("").parts
        if rel == ("__init__",):
            continue
        own = rel[0]
        assert own in rank, f"bench/{'/'.join(rel)}.py is in no layer: add it to bench.LAYERS"
        for name in _imports(f, "bench"):
            parts = name.split(".")
            if parts[0] != "bench" or len(parts) < 2 or parts[1] not in rank:
                continue
            if rank[parts[1]] > rank[own]:
                bad.append(f"bench/{'/'.join(rel)}.py ({own}) imports {name}")
    assert not bad, bad


def test_the_layout_check_sees_function_level_imports(tmp_path):
    (tmp_path / "bench").mkdir()
    f = tmp_path / "bench" / "analysis.py"
    f.write_text("def g():\n    from .report import build_report\n    import bench.cli\n    return build_report\n")
    assert {"bench.report", "bench.cli"} <= _imports(f, "bench", root=tmp_path)
