"""The shared command-line options (bench/cli/options.py): argparse types from the value checks, one-line errors,
the configuration syntax of ``--trackers``, the real runs' defaults."""

import argparse
import math

import pytest

from bench.cli import options as O
from bench.config import ConfigError
from bench.config.options import REAL_DEFAULTS, finite_float, plain_tracker_names


def test_arg_type_gives_argparse_its_message_without_the_name(capsys):
    p = O.OneLineParser(prog="t")
    p.add_argument("--t", type=O.arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True), "--t"))
    assert math.isclose(p.parse_args(["--t", "2.5"]).t, 2.5)
    with pytest.raises(SystemExit) as exc:
        p.parse_args(["--t", "nan"])
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and err == ["stripebench: error: argument --t: must be a finite number > 0, "
                                           "got 'nan' (see `t -h`)"]


def test_trackers_option_is_the_configuration_syntax():
    p = argparse.ArgumentParser()
    O.add_trackers(p, "h")
    specs = p.parse_args(["--trackers", 'threshold,{label="d",name="dp4",params={h_weight=1.0}}']).trackers
    assert [(s.label, s.name, s.params) for s in specs] == [("threshold", "threshold", {}),
                                                            ("d", "dp4", {"h_weight": 1.0})]
    with pytest.raises(ConfigError, match="give plain names"):
        plain_tracker_names(specs)
    assert plain_tracker_names(specs[:1]) == ["threshold"]


def test_real_defaults_are_the_real_commands_defaults():
    p = argparse.ArgumentParser()
    O.add_tol(p)
    O.add_n_boot(p)
    args = p.parse_args([])
    assert args.tol == REAL_DEFAULTS["tol_px"] and args.n_boot == REAL_DEFAULTS["n_boot"]
