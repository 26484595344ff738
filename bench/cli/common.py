"""What every ``stripebench`` command shares: the command record, lazily built parsers, the usage error,
the checks of the environment. The option types themselves are :mod:`bench.cli.options`."""

from __future__ import annotations

import argparse
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from bench.cli.options import HelpFormatter, OneLineParser, first_paragraph
from bench.errors import StripebenchError

__all__ = ["Command", "UsageError", "LazyParser", "add_commands", "check_env", "check_out_folder", "check_variant", "call",
           "study_command", "standalone"]


class UsageError(StripebenchError, ValueError):
    """A bad command-line value or combination: one line for the user, exit status 2."""


@dataclass(frozen=True)
class Command:
    """One ``stripebench`` command: its name, one-line help, options and action.

    ``add_arguments(parser)`` adds the options (called only when the command is
    parsed or its help shown, so a command's heavy imports cost nothing to the
    others); ``run(args) -> int`` does the work. ``description`` (plain text,
    default the help) heads ``stripebench NAME -h``; ``renders`` marks commands that
    use Mitsuba (``$STRIPEBENCH_VARIANT`` is checked before them); ``calls`` (``"module:function"``)
    names the plain function a study command calls with its options (:func:`study_command`).
    """

    name: str
    help: str
    add_arguments: Callable
    run: Callable
    description: str | Callable[[], str] | None = None
    epilog: str | None = None
    renders: bool = False
    subcommands: tuple = ()
    default_subcommand: str | None = None
    calls: str | None = None


class LazyParser(OneLineParser):
    """A sub-parser whose options are added on first use (parsing or help)."""

    def __init__(self, *args, loader: Callable | None = None, description_loader: Callable | None = None, **kw):
        super().__init__(*args, **kw)
        self._loader = loader
        self._description_loader = description_loader

    def _load(self) -> None:
        if self._loader is not None:
            loader, self._loader = self._loader, None
            loader(self)
        if self._description_loader is not None:
            loader, self._description_loader = self._description_loader, None
            self.description = loader()

    def parse_known_args(self, args=None, namespace=None):
        self._load()
        return super().parse_known_args(args, namespace)

    def format_help(self):
        self._load()
        return super().format_help()


def add_commands(sub, commands) -> None:
    """Add ``commands`` (:class:`Command`) to the sub-parsers action ``sub``; a command with
    ``subcommands`` gets its own sub-parsers (``default_subcommand`` runs when none is named)."""
    for c in commands:
        desc = c.description if isinstance(c.description, str) else None
        lazy_desc = c.description if callable(c.description) else None
        p = sub.add_parser(c.name, help=c.help, description=desc or (None if lazy_desc else c.help),
                           epilog=c.epilog, formatter_class=HelpFormatter, loader=_loader(c),
                           description_loader=lazy_desc)
        p.set_defaults(func=c.run, command_renders=c.renders)


def _loader(c: Command):
    def load(parser):
        c.add_arguments(parser)
        if c.subcommands:
            inner = parser.add_subparsers(dest=f"{c.name}_command", metavar="WHAT", parser_class=LazyParser)
            inner.required = c.default_subcommand is None
            add_commands(inner, c.subcommands)
            if c.default_subcommand is not None:
                default = next(s for s in c.subcommands if s.name == c.default_subcommand)

                def run_default(args, _default=default):
                    # `stripebench perf` alone: the default sub-command with its own defaults (and
                    # `--strict` when the parent command has that flag and it was given)
                    p = LazyParser(prog=f"{parser.prog} {_default.name}", loader=_default.add_arguments)
                    return _default.run(p.parse_args(["--strict"] if getattr(args, "strict", False) else []))

                parser.set_defaults(func=run_default, command_renders=default.renders)

    return load


def check_env() -> None:
    """The folders named by environment variables must be folders (or creatable), and writable, and
    ``$STRIPEBENCH_LLVM_TARGET`` well formed."""
    from scenes import variant

    try:
        variant.parse_llvm_target(os.environ.get(variant.ENV_LLVM_TARGET, ""))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    for var in ("STRIPEBENCH_CACHE_DIR", "STRIPEBENCH_RUNS"):
        value = os.environ.get(var)
        if not value:
            continue
        p = Path(value)
        if p.exists() and not p.is_dir():
            raise UsageError(f"${var} must name a folder, got {value!r} (a file)")
        if p.is_dir() and not os.access(p, os.W_OK | os.X_OK):
            raise UsageError(f"${var} names a folder this user cannot write: {value!r}")


def check_out_folder(out, option: str = "--out", *, inputs=()) -> None:
    """``--out`` may be missing (it is created) or a folder, never a file; and none of ``inputs`` (pairs
    ``(what, path)``: the configuration, the data set, the submission) may be the folder or lie inside it,
    where the command's outputs could overwrite it and ``--force`` would delete it."""
    if out is None:
        return
    if Path(out).exists() and not Path(out).is_dir():
        raise UsageError(f"{option} must be a folder, got {str(out)!r} (a file)")
    o = Path(out).resolve()
    for what, path in inputs:
        if path is not None and (Path(path).resolve() == o or o in Path(path).resolve().parents):
            raise UsageError(f"{what} {str(path)!r} is inside the output folder {str(out)!r}: the outputs (and "
                             f"--force, which clears the folder) could overwrite or delete it; choose another {option}")


def check_variant() -> None:
    """``$STRIPEBENCH_VARIANT``, when set, must name a Mitsuba variant that renders on this machine
    (:func:`scenes.variant.check_forced`: a name among the variants, then a probe in a child process)."""
    from scenes import variant

    try:
        variant.check_forced()
    except variant.VariantError as exc:
        raise UsageError(str(exc)) from None


def description_of(module_name: str) -> Callable[[], str]:
    """A lazy description: the first paragraph of a module's docstring, as plain text."""

    def load():
        import importlib

        return first_paragraph(importlib.import_module(module_name).__doc__)

    return load


def namespace(**kw) -> argparse.Namespace:
    """An ``argparse.Namespace`` (for calling a command's ``run`` from code)."""
    return argparse.Namespace(**kw)


def study_command(name: str, help: str, add_arguments: Callable, calls: str, *, renders: bool = False,
                  description: str | Callable[[], str] | None = None, epilog: str | None = None) -> Command:
    """A command that calls a study's plain function (``calls``: ``"module:function"``) with its options
    (:func:`call`); the module is imported only when the command runs or its help is shown, and the
    first paragraph of its docstring is the command's description unless ``description`` is given."""
    module, _, function = calls.partition(":")

    def run(args):
        import importlib

        return call(getattr(importlib.import_module(module), function), args)

    return Command(name, help, add_arguments, run, description=description or description_of(module), epilog=epilog,
                   renders=renders, calls=calls)


def call(fn: Callable, args: argparse.Namespace, **extra):
    """``fn(**options)``: a study's plain function called with the parsed options it names (each
    keyword parameter of ``fn`` is the ``dest`` of an option; ``extra`` adds or overrides some).
    The namespace's other entries (the command tree's own, a parent command's options) are not passed."""
    import inspect

    params = inspect.signature(fn).parameters
    kw = {k: v for k, v in vars(args).items() if k in params}
    return fn(**{**kw, **extra})


def options_of(add_arguments: Callable) -> list[str]:
    """The ``dest`` of every option ``add_arguments(parser)`` adds (a test checks them against the plain
    function each command calls)."""
    parser = OneLineParser(prog="t", add_help=False)
    add_arguments(parser)
    return [a.dest for a in parser._actions]


def standalone(command: Command, prog: str, argv=None) -> int:
    """Run one command outside the tree (a ``python -m bench.cli.NAME`` entry point): its parser alone,
    the same one-line errors and plain-text help; an expected failure
    (:class:`bench.errors.StripebenchError`) is one line on stderr and exit status 2."""
    import sys

    parser = LazyParser(prog=prog, formatter_class=HelpFormatter, loader=command.add_arguments,
                        description=command.description if isinstance(command.description, str) else command.help,
                        description_loader=command.description if callable(command.description) else None,
                        epilog=command.epilog)
    args = parser.parse_args(argv)
    try:
        return int(command.run(args) or 0)
    except StripebenchError as exc:
        print(f"stripebench: error: {exc}", file=sys.stderr)
        return 2
