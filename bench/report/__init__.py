"""Reports from saved runs: figures and HTML pages (runs, real runs, sweeps)."""
