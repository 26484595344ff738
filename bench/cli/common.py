"""What every ``stripebench`` command shares: the command record, lazily built parsers, the usage error,
the checks of the environment. The option types themselves are :mod:`bench.config.options`."""

from __future__ import annotations

import argparse
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from bench.config.options import HelpFormatter, OneLineParser, first_paragraph
from bench.errors import StripebenchError

__all__ = ["Command", "UsageError", "LazyParser", "add_commands", "check_env", "check_out_folder", "check_variant"]


class UsageError(StripebenchError, ValueError):
    """A bad command-line value or combination: one line for the user, exit status 2."""


@dataclass(frozen=True)
class Command:
    """One ``stripebench`` command: its name, one-line help, options and action.

    ``add_arguments(parser)`` adds the options (called only when the command is
    parsed or its help shown, so a command's heavy imports cost nothing to the
    others); ``run(args) -> int`` does the work. ``description`` (plain text,
    default the help) heads ``stripebench NAME -h``; ``renders`` marks commands that
    use Mitsuba (``$STRIPEBENCH_VARIANT`` is checked before them).
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


def check_out_folder(out, option: str = "--out") -> None:
    """``--out`` may be missing (it is created) or a folder, never a file."""
    if out is not None and Path(out).exists() and not Path(out).is_dir():
        raise UsageError(f"{option} must be a folder, got {str(out)!r} (a file)")


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
