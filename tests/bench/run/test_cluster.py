"""The local Dask cluster (:mod:`bench.run.cluster`): no dashboard and no numbered port, so sweeps, render-ahead
and training sets start while another cluster (or any program) holds port 8787, without a warning."""

import contextlib
import errno
import json
import socket
import warnings

import pytest

from bench.run.cluster import local_cluster

PORT = 8787  # distributed's default dashboard port


@contextlib.contextmanager
def _socket_on_8787():
    s = socket.socket()
    try:
        s.bind(("127.0.0.1", PORT))
        s.listen(1)
    except OSError as exc:  # another program holds it already: the condition under test holds too
        if exc.errno != errno.EADDRINUSE:
            raise
    try:
        yield
    finally:
        s.close()


@contextlib.contextmanager
def _cluster_on_8787():
    from dask.distributed import LocalCluster

    with warnings.catch_warnings():  # the holder itself may find 8787 taken by someone else: not under test
        warnings.simplefilter("ignore")
        holder = LocalCluster(n_workers=0, processes=False, dashboard_address=f":{PORT}")
    try:
        yield
    finally:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            holder.close()


HOLDERS = {"a socket": _socket_on_8787, "a LocalCluster": _cluster_on_8787}


@pytest.fixture(params=sorted(HOLDERS))
def port_8787_held(request):
    with HOLDERS[request.param]():
        yield request.param


def test_the_cluster_starts_without_a_dashboard_or_a_warning_while_8787_is_held(port_8787_held):
    from dask.distributed import Client

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cluster = local_cluster(1)
        try:
            with Client(cluster) as client:
                assert client.submit(sum, [1, 2]).result(timeout=60) == 3
            http = cluster.scheduler.http_server
            assert http.port != PORT and http.address == "127.0.0.1"
            assert "/status" not in {str(r.matcher.regex.pattern).rstrip("$") for r in
                                     cluster.scheduler.http_application.default_router.rules[0].target.rules}
        finally:
            cluster.close()


def test_sweep_trainset_and_render_ahead_run_while_8787_is_held(tmp_path, monkeypatch):
    """The three commands that start a local cluster, each on a tiny job, with a real LocalCluster on 8787."""
    import scenes
    from bench.config import parse
    from bench.run import renderahead
    from bench.run.sweep import parse_sweep, run_sweep
    from bench.run.trainset import build_trainset

    monkeypatch.setenv("STRIPEBENCH_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(renderahead, "MIN_PIXEL_SAMPLES", 0)  # tiny frames: start the helper all the same
    cfg = parse({"name": "port", "seed": 2, "trackers": ["threshold"], "baselines": ["threshold"], "dp": [],
                 "n_samples": 15, "n_boot": 20, "render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
                 "experiments": [{"scene": "plane", "material": "patchy", "n_angles": 2}]})
    with _cluster_on_8787(), warnings.catch_warnings():
        warnings.simplefilter("error")
        out = run_sweep(cfg, parse_sweep({"ambient_lux": [0, 400]}, cfg), tmp_path / "sweep", workers=1,
                        progress=False, quiet=True, timeout_s=300, connect_timeout_s=60)
        assert json.loads((out / "summary.json").read_text())["engine"]["engine"] == "local"
        root = build_trainset(tmp_path / "ts", n_units=1, angles_per_unit=1, noise_draws=1, width=64, height=60,
                              workers=1, quiet=True)
        assert (root / "trainset.json").is_file()
        plane = scenes.make("plane", width=64, height=60, spp=1, ambient_spp=1)
        helper = renderahead.RenderAhead([plane, plane], [[0.5, 1.5], [2.5]], 5, nice=0)
        assert helper.start() and helper.wait(1, timeout_s=120) >= 1
        result = helper.stop()
    assert result["started"] and result["error"] == "", result
