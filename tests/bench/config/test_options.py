"""The option values' checks and limits (bench/config/options.py; the argparse side: tests/bench/cli/test_options.py)."""

import math

import pytest

from bench.config import ConfigError
from bench.config import options as O


@pytest.mark.parametrize("value", ["0", "-1", "1.5", "x", "1" + "0" * 400, True, 2.0])
def test_positive_int_refuses_what_is_not_a_positive_integer(value):
    with pytest.raises(ConfigError, match="--n must be an integer >= 1"):
        O.positive_int("--n", value)


def test_int_in_range_and_seed_bounds():
    assert O.int_in_range("--n", "5", 0, 5) == 5
    with pytest.raises(ConfigError, match=r"--n must be an integer 0 \.\. 5, got '6'"):
        O.int_in_range("--n", "6", 0, 5)
    assert O.seed_value("--seed", str(2**63 - 1)) == 2**63 - 1
    with pytest.raises(ConfigError, match=r"at most 2\*\*63 - 1"):
        O.seed_value("--seed", str(2**63))


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e400", "x", None])
def test_finite_float_refuses_non_finite_values(value):
    with pytest.raises(ConfigError, match="must be a finite number"):
        O.finite_float("--t", value)


def test_finite_float_bounds_and_lists():
    assert O.finite_float("--t", "0", low=0) == 0.0
    with pytest.raises(ConfigError, match="> 0"):
        O.finite_float("--t", "0", low=0, low_open=True)
    with pytest.raises(ConfigError, match="<= 10"):
        O.finite_float("--t", "11", high=10)
    assert O.finite_floats("--s", "1, 2,3") == [1.0, 2.0, 3.0]
    for bad in ("", ",", "1,nan", "1,1"):
        with pytest.raises(ConfigError):
            O.finite_floats("--s", bad)


def test_workers_are_bounded_by_this_machines_cpus():
    n = O.cpu_count()
    assert O.workers_value("--workers", str(n)) == n and O.workers_value("--workers", "0") == 0
    with pytest.raises(ConfigError, match=rf"--workers must be an integer 0 \.\. {n}, got '{n + 1}'"):
        O.workers_value("--workers", str(n + 1))


@pytest.mark.parametrize("good", ["sync", "tcp://127.0.0.1:8786", "tls://sched.example.org:1", "tcp://[::1]:65535"])
def test_scheduler_addresses_that_parse(good):
    assert O.scheduler_address(good) == good


@pytest.mark.parametrize("bad", ["", "tcp://", "tcp://127.0.0.1", "tcp://127.0.0.1:", "tcp://127.0.0.1:notaport",
                                 "tcp://127.0.0.1:0", "tcp://127.0.0.1:65536", "tcp://:8786", "localhost:8786",
                                 "inproc://x", "http://127.0.0.1:8786", "tcp://h ost:1", "tcp://127.0.0.1:٣"])
def test_scheduler_addresses_that_do_not(bad):
    with pytest.raises(ConfigError, match="--scheduler must be 'sync' or an address like tcp://HOST:PORT"):
        O.scheduler_address(bad)


def test_size_value():
    assert O.size_value("--size", "256X240") == (256, 240)
    for bad in ("256", "0x240", "axb", "100000x10"):
        with pytest.raises(ConfigError, match="--size"):
            O.size_value("--size", bad)


def test_plain_tracker_names_refuses_settings_and_takes_names():
    from bench.config import parse_trackers_arg

    specs = parse_trackers_arg('threshold,{label="d",name="dp4",params={h_weight=1.0}}', "--trackers")
    with pytest.raises(ConfigError, match="give plain names"):
        O.plain_tracker_names(specs)
    assert O.plain_tracker_names(specs[:1]) == ["threshold"] and O.plain_tracker_names(["dp4"]) == ["dp4"]


def test_spp_value_takes_auto_or_a_count():
    from bench.config.options import spp_value

    assert spp_value("--spp", "auto") == "auto" and spp_value("--spp", "16") == 16
    for bad in ("0", "65537", "Auto", "x", "1.5"):
        with pytest.raises(ConfigError, match=r'--spp must be "auto" or an integer 1 \.\. 65536, got'):
            spp_value("--spp", bad)
