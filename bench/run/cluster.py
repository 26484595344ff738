"""The local Dask cluster stripebench starts (sweeps, render-ahead, training sets): loopback only, no dashboard.

``LocalCluster(dashboard_address=None)`` still gives the scheduler an HTTP server, on port 8787 by
default: where another cluster holds that port, distributed warns ("Port 8787 is already in use") and
moves on, and under ``filterwarnings = error`` the warning fails the command. :func:`local_cluster`
turns the dashboard off (the scheduler's ``dashboard=False``: no Bokeh application) and puts the HTTP
server it always starts on an ephemeral loopback port (``127.0.0.1:0``), so no port is asked for by
number, none is shared with another cluster, and nothing listens beyond this machine.
"""

from __future__ import annotations

import logging

__all__ = ["local_cluster", "HTTP_ADDRESS"]

#: Where the scheduler's HTTP server (health and metrics routes; no dashboard) listens: any free loopback port.
HTTP_ADDRESS = "127.0.0.1:0"


def local_cluster(n_workers: int, env: dict | None = None):
    """A ``distributed.LocalCluster`` of ``n_workers`` single-threaded worker processes on 127.0.0.1, without
    a dashboard, its logs silenced below ERROR.

    Parameters
    ----------
    n_workers : int
        Worker processes (>= 1).
    env : dict or None
        Environment variables of the worker processes (the Mitsuba variant the caller chose).

    Returns
    -------
    distributed.LocalCluster
        The caller closes it (``cluster.close()``).
    """
    from dask.distributed import LocalCluster

    return LocalCluster(n_workers=int(n_workers), threads_per_worker=1, processes=True, host="127.0.0.1",
                        dashboard_address=None, worker_dashboard_address=None, env=dict(env or {}),
                        silence_logs=logging.ERROR,
                        scheduler_kwargs={"dashboard": False, "dashboard_address": HTTP_ADDRESS})
