"""Pure evaluation: arrays and tables in, numbers out (triangulation, restoration, metrics, statistics, tables, curves)."""
