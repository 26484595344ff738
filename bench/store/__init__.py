"""Every file a run writes or reads: atomic writes, run folders, checkpoints, baselines, the real-set layout."""
