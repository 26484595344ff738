"""The exception base (bench/errors.py): every expected failure of every layer derives from it."""

import pytest

from bench.errors import ConfigError, InputError, StripebenchError


def test_every_layers_error_is_a_stripebench_error():
    from bench.cli.common import UsageError
    from bench.config import ConfigError as config_error
    from bench.run.sweep import SweepError
    from bench.store.realset import DatasetError, ImageError
    from bench.store.runfolder import RunFolderError

    assert config_error is ConfigError
    for cls in (ConfigError, InputError, RunFolderError, ImageError, DatasetError, SweepError, UsageError):
        assert issubclass(cls, StripebenchError), cls


def test_the_errors_module_imports_nothing_of_bench():
    import ast
    import pathlib

    import bench.errors

    tree = ast.parse(pathlib.Path(bench.errors.__file__).read_text())
    assert not [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) and
                getattr(n, "module", "") != "__future__"]


def test_messages_are_the_one_line_given():
    with pytest.raises(StripebenchError, match=r"^`seed` must be an integer >= 0, got -1$"):
        raise ConfigError("`seed` must be an integer >= 0, got -1")
