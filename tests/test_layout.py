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
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista', 'numba', 'jax', 'flax', 'optax', 'torch') "
        "if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == "", f"import trackers imported {out.stdout.strip()}"


def test_making_a_tracker_does_not_import_the_renderer():
    code = (
        "import sys, trackers; [trackers.make(n) for n in trackers.available() + ['learned']]; "
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista', 'jax', 'flax', 'optax', 'torch') "
        "if m in sys.modules]; print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == ""


# -- import rules, checked on the source (module-level and function-level imports) -------------------
import ast  # noqa: E402
import re  # noqa: E402


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
    ("trackers", ("mitsuba", "drjit", "matplotlib", "pyvista", "scenes", "bench", "jax", "flax", "optax", "torch")),
    ("scenes", ("trackers", "bench")),
])
def test_lower_packages_never_import_upwards(pkg, banned):
    bad = []
    for f in _files(pkg):
        for name in _imports(f, pkg):
            if name.split(".")[0] in banned:
                bad.append(f"{f.relative_to(REPO)} imports {name}")
    assert not bad, bad


def _bench_graph(root: pathlib.Path = REPO) -> dict[str, set[str]]:
    """Module -> the bench modules it imports (dotted names under ``bench``, packages as their ``__init__``)."""
    mods = {}
    for f in sorted(p for p in (root / "bench").rglob("*.py") if "__pycache__" not in p.parts):
        parts = f.relative_to(root).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        mods[name] = f
    graph = {}
    for name, f in mods.items():
        deps = set()
        for imp in _imports(f, "bench", root=root):
            # the longest known module that the imported name starts with
            bits = imp.split(".")
            for k in range(len(bits), 0, -1):
                cand = ".".join(bits[:k])
                if cand in mods:
                    if cand != name:
                        deps.add(cand)
                    break
        graph[name] = deps
    return graph


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def test_every_bench_module_is_in_a_layer():
    from bench import LAYERS

    bad = [m for m in _bench_graph() if m != "bench" and _layer(m) not in LAYERS]
    assert not bad, f"bench modules in no layer (add their package to bench.LAYERS): {bad}"


def test_bench_modules_import_only_their_own_layer_or_lower():
    from bench import LAYERS

    rank = {layer: i for i, layer in enumerate(LAYERS)}
    bad = []
    for mod, deps in _bench_graph().items():
        if mod == "bench":
            continue
        for dep in deps:
            if dep != "bench" and rank[_layer(dep)] > rank[_layer(mod)]:
                bad.append(f"{mod} ({_layer(mod)}) imports {dep} ({_layer(dep)})")
    assert not bad, bad


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every strongly connected component of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_bench_has_no_import_cycles():
    # a package's __init__ importing its own modules is not a cycle worth reporting; everything else is
    graph = {m: {d for d in deps if not m.startswith(d + ".")} for m, deps in _bench_graph().items()}
    assert _cycles(graph) == []


def test_the_cycle_check_finds_a_cycle_inside_a_layer(tmp_path):
    (tmp_path / "bench" / "run").mkdir(parents=True)
    (tmp_path / "bench" / "__init__.py").write_text("")
    (tmp_path / "bench" / "run" / "__init__.py").write_text("")
    (tmp_path / "bench" / "run" / "a.py").write_text("def f():\n    from bench.run import b\n")
    (tmp_path / "bench" / "run" / "b.py").write_text("from .a import f\n")
    assert _cycles(_bench_graph(tmp_path)) == [["bench.run.a", "bench.run.b"]]


def test_the_layout_check_sees_function_level_imports(tmp_path):
    (tmp_path / "bench").mkdir()
    f = tmp_path / "bench" / "analysis.py"
    f.write_text("def g():\n    from .report import build_report\n    import bench.cli\n    return build_report\n")
    assert {"bench.report", "bench.cli"} <= _imports(f, "bench", root=tmp_path)


def _argparse_outside_cli(root: pathlib.Path = REPO) -> list[str]:
    """``file: what`` for every module of ``bench`` outside ``bench/cli/`` that imports argparse or defines
    an ``add_arguments`` (issue 36: every argparse part lives in the command layer)."""
    bad = []
    for f in sorted(p for p in (root / "bench").rglob("*.py") if "__pycache__" not in p.parts):
        rel = f.relative_to(root)
        if rel.parts[:2] == ("bench", "cli"):
            continue
        if any(name == "argparse" or name.startswith("argparse.") for name in _imports(f, "bench", root=root)):
            bad.append(f"{rel}: imports argparse")
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == "add_arguments":
                bad.append(f"{rel}:{node.lineno}: defines add_arguments")
    return bad


def test_only_the_command_layer_knows_argparse():
    """Studies and the library expose plain functions; their options are bench/cli's (one module per group)."""
    assert _argparse_outside_cli() == []


def test_the_argparse_check_finds_a_parser_outside_the_command_layer(tmp_path):
    (tmp_path / "bench" / "studies").mkdir(parents=True)
    (tmp_path / "bench" / "cli").mkdir()
    (tmp_path / "bench" / "studies" / "x.py").write_text("def add_arguments(parser):\n    import argparse\n")
    (tmp_path / "bench" / "cli" / "x.py").write_text("import argparse\n\ndef add_arguments(parser):\n    pass\n")
    assert _argparse_outside_cli(tmp_path) == ["bench/studies/x.py: imports argparse",
                                               "bench/studies/x.py:1: defines add_arguments"]


# -- one home for the scoring rules (bench.evaluate.outcomes) ------------------------------------------
_TOLERANCES = {"tol_px", "hit_px", "HIT_PX", "threshold_px", "OUTLIER_PX", "within_mm", "WITHIN_MM", "gross_mm",
               "GROSS_MM"}


def _compared_tolerances(path: pathlib.Path) -> list[str]:
    """``file:line`` of every comparison in ``path`` with a tolerance of the scoring rules as an operand."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Compare):
            names = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
            names |= {n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute)}
            if names & _TOLERANCES:
                out.append(f"{path.relative_to(REPO)}:{node.lineno}")
    return out


def test_the_scoring_rules_are_applied_in_one_home():
    """The hit rule, the ±5 mm band and gross errors are applied only by bench.evaluate.outcomes (hits, within,
    gross, row_outcomes); every other module calls them. Validating a tolerance argument is not applying it."""
    home = REPO / "bench" / "evaluate" / "outcomes.py"
    found = []
    for path in sorted((REPO / "bench").rglob("*.py")):
        if path != home:
            found += [where for where in _compared_tolerances(path)]
    checks = []
    for where in found:
        file, line = where.rsplit(":", 1)
        text = (REPO / file).read_text(encoding="utf-8").splitlines()[int(line) - 1]
        if "raise" in text or "must be" in text or re.search(r"not\s*\(|if not|>= 0|> 0|math.isfinite", text):
            continue
        checks.append(f"{where}: {text.strip()}")
    assert not checks, "a scoring tolerance compared outside bench.evaluate.outcomes:\n" + "\n".join(checks)


def test_the_one_home_check_finds_a_copy_of_the_rule(tmp_path):
    copy = REPO / "bench" / "_probe_copy_of_the_hit_rule.py"  # inside the repository: paths are reported from it
    copy.write_text("def f(e, tol_px):\n    return abs(e) <= tol_px\n")
    try:
        assert _compared_tolerances(copy) == ["bench/_probe_copy_of_the_hit_rule.py:2"]
    finally:
        copy.unlink()


def test_layout_md_lists_every_module_from_its_docstring():
    """docs/layout.md's module list is written by scripts/layout_md.py from the code (issue 36)."""
    out = subprocess.run([sys.executable, str(REPO / "scripts" / "layout_md.py"), "--check"], capture_output=True,
                         text=True, cwd=REPO)
    assert out.returncode == 0, out.stderr


# -- bench uses scenes through its public interface (scenes.__all__ and scenes.PUBLIC_MODULES) -------------------
def _scenes_modules_used(path: pathlib.Path, root: pathlib.Path = REPO) -> list[tuple[int, str]]:
    """``(line, module)`` for every scenes submodule ``path`` imports (``import scenes.x``, ``from scenes.x import
    ...``, ``from scenes import x``) or reaches as an attribute (``scenes.x.y``)."""
    submodules = {p.stem for p in (root / "scenes").glob("*.py") if p.stem != "__init__"}
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name.split(".")[1]) for a in node.names if a.name.startswith("scenes.")]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").split(".")[0] == "scenes":
            if node.module == "scenes":
                out += [(node.lineno, a.name) for a in node.names if a.name in submodules]
            else:
                out.append((node.lineno, node.module.split(".")[1]))
        elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "scenes"
              and node.attr in submodules):
            out.append((node.lineno, node.attr))
    return sorted(out)


def test_bench_uses_only_the_public_interface_of_scenes():
    """bench imports of scenes only the names of ``scenes.__all__`` and the modules of ``scenes.PUBLIC_MODULES``
    (issue 36): the rest of scenes can move without touching bench."""
    import scenes

    bad = [f"{f.relative_to(REPO)}:{line} uses scenes.{mod}" for f in _files("bench")
           for line, mod in _scenes_modules_used(f) if mod not in scenes.PUBLIC_MODULES]
    assert not bad, "bench reaches into scenes outside scenes.__all__ / scenes.PUBLIC_MODULES:\n" + "\n".join(bad)
    missing = [n for n in scenes.__all__ if not hasattr(scenes, n)]
    assert not missing and set(scenes.PUBLIC_MODULES) <= {p.stem for p in (REPO / "scenes").glob("*.py")}, missing


def test_the_scenes_interface_check_finds_a_private_module(tmp_path):
    (tmp_path / "scenes").mkdir()
    for name in ("__init__", "scene", "variant", "masks"):
        (tmp_path / "scenes" / f"{name}.py").write_text("")
    f = tmp_path / "user.py"
    f.write_text("import scenes\nfrom scenes import variant, make\n\ndef g():\n    from scenes.scene import render_pass\n"
                 "    import scenes.masks\n    return scenes.variant, scenes.make, scenes.masks.grow\n")
    assert _scenes_modules_used(f, root=tmp_path) == [(2, "variant"), (5, "scene"), (6, "masks"), (7, "masks"),
                                                      (7, "variant")]
