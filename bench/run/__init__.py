"""Running: scans, experiments, render-ahead, real-photograph runs, sweeps and the regression gate."""
