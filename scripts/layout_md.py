"""Write (or check) the module list of ``docs/layout.md`` from the modules' own docstrings.

Run: ``.venv/bin/python scripts/layout_md.py`` rewrites the section between ``## Modules`` and the next
``## `` heading; ``--check`` exits 1 (naming the first difference) when the file is not current.
``tests/test_layout.py`` runs the check.
"""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "layout.md"
HEAD = "## Modules\n"


def _layers() -> tuple[str, ...]:
    """``bench.LAYERS``, read from the source (no import)."""
    tree = ast.parse((ROOT / "bench" / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "LAYERS" for t in node.targets):
            return tuple(ast.literal_eval(node.value))
    raise SystemExit("bench/__init__.py defines no LAYERS")


def _first_sentence(path: Path) -> str:
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    return " ".join(doc.split("\n\n")[0].split())


def modules_section() -> str:
    """The ``## Modules`` section: every module of bench/, layer by layer, with its docstring's first paragraph."""
    lines = [HEAD, "\n", "Written by `scripts/layout_md.py` from each module's docstring (a test checks that it is current).\n",
             "\n"]
    for layer in _layers():
        base = ROOT / "bench" / layer
        files = [ROOT / "bench" / f"{layer}.py"] if (ROOT / "bench" / f"{layer}.py").is_file() else \
            sorted(p for p in base.rglob("*.py"))
        if layer == "errors":
            files = [ROOT / "bench" / "__init__.py"] + files
        for f in files:
            lines.append(f"- `{f.relative_to(ROOT).as_posix()}`: {_first_sentence(f) or '(no docstring)'}\n")
    return "".join(lines) + "\n"


def current() -> tuple[str, str]:
    """(the file as it is, the file as it should be)."""
    text = DOC.read_text(encoding="utf-8")
    i = text.index(HEAD)
    j = text.index("\n## ", i + len(HEAD)) + 1
    return text, text[:i] + modules_section() + text[j:]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python scripts/layout_md.py", description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="exit 1 if docs/layout.md is not current")
    args = p.parse_args(argv)
    text, want = current()
    if args.check:
        if text != want:
            a, b = text.splitlines(), want.splitlines()
            k = next((n for n, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            print(f"docs/layout.md line {k + 1} is not current: run scripts/layout_md.py "
                  f"(want {b[k] if k < len(b) else '<end>'!r})", file=sys.stderr)
            return 1
        return 0
    DOC.write_text(want, encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
