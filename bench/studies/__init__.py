"""Studies on synthetic frames: sub-pixel estimators, translucency, tuning procedures, speed benchmarks."""
