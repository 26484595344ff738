"""Every file a run writes or reads, each format versioned.

``files`` (atomic writes that name their file, npz/JSON readers that say why, checksums),
``runfolder`` (the run folder of every kind: identity, lock, ``--force``, recovery, the tables and readers of
a finished run), ``checkpoint`` (scan checkpoints, :class:`ScanResult`), ``figdata`` (Fig. 7's frame, the
failure gallery), ``summary`` (``summary.json`` of every kind), ``sweepfiles`` (sweep units and tables),
``realrun`` (``track`` and ``real`` outputs), ``realset`` (the real-set layout and image readers),
``provenance`` (versions, git revision, source fingerprints).
"""
