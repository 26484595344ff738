"""``stripebench trainset`` and ``train``: rendered training sets and the ``learned`` tracker's training."""

from __future__ import annotations

import sys
from pathlib import Path

from bench.cli.common import Command, UsageError

__all__ = ["COMMANDS"]


def _add_trainset(p) -> None:
    p.add_argument("--out", type=Path, required=True, help="training-set folder (a rerun resumes it)")
    p.add_argument("--units", type=int, default=30, help="scenes drawn (default 30)")
    p.add_argument("--angles", type=int, default=4, help="mirror angles per scene (default 4)")
    p.add_argument("--noise-draws", type=int, default=2, help="sensor-noise draws per angle (default 2)")
    p.add_argument("--seed", type=int, default=1, help="seed of the draws (default 1)")
    p.add_argument("--size", default="512x480", help="WIDTHxHEIGHT (default 512x480)")
    p.add_argument("--workers", type=int, default=None,
                   help="render on a local Dask cluster of this many processes (default: in this process)")
    p.add_argument("--scheduler", default=None, help="a Dask scheduler's address to render on")
    p.add_argument("--quiet", action="store_true", help="no progress notes")


def _size(text: str) -> tuple[int, int]:
    """``WIDTHxHEIGHT`` as two ints.

    >>> _size("512x480")
    (512, 480)
    """
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise UsageError(f"--size must be WIDTHxHEIGHT, got {text!r}") from None
    if w < 8 or h < 8:
        raise UsageError(f"--size must be at least 8x8, got {text!r}")
    return w, h


def _trainset(args) -> int:
    from bench.run.trainset import build_trainset

    for name in ("units", "angles", "noise_draws"):
        if getattr(args, name) < 1:
            raise UsageError(f"--{name.replace('_', '-')} must be >= 1, got {getattr(args, name)}")
    if args.seed < 0:
        raise UsageError(f"--seed must be >= 0, got {args.seed}")
    w, h = _size(args.size)
    root = build_trainset(args.out, n_units=args.units, angles_per_unit=args.angles, seed=args.seed,
                          noise_draws=args.noise_draws, width=w, height=h, workers=args.workers,
                          scheduler=args.scheduler, quiet=args.quiet)
    print(f"stripebench: training set at {root}")
    return 0


def _add_train(p) -> None:
    p.add_argument("trainset", type=Path, help="a finished training set (stripebench trainset)")
    p.add_argument("--out", type=Path, default=Path("trackers/models/learned.npz"),
                   help="weights file (default trackers/models/learned.npz); its curves go beside it as .png")
    p.add_argument("--epochs", type=int, default=None, help="training epochs (default: HyperParams)")
    p.add_argument("--seed", type=int, default=0, help="seed of the initialisation and the batches (default 0)")
    p.add_argument("--holdout", type=float, default=0.2, help="share of units held out (default 0.2)")
    p.add_argument("--quiet", action="store_true", help="no progress notes")


def _train(args) -> int:
    try:
        import flax  # noqa: F401
        import jax  # noqa: F401
        import optax  # noqa: F401
    except ImportError:
        raise UsageError("stripebench train needs JAX, Flax and Optax: pip install -e '.[learn]'") from None
    from dataclasses import replace

    from bench.studies.train import HyperParams, train_from_trainset

    if not 0 < args.holdout < 1:
        raise UsageError(f"--holdout must be in (0, 1), got {args.holdout}")
    hp = HyperParams(seed=args.seed)
    if args.epochs is not None:
        if args.epochs < 1:
            raise UsageError(f"--epochs must be >= 1, got {args.epochs}")
        hp = replace(hp, epochs=args.epochs)
    say = (lambda m: None) if args.quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    prov = train_from_trainset(args.trainset, args.out, hp=hp, holdout=args.holdout, say=say)
    h = prov["heldout"]["both"]
    print(f"stripebench: weights at {args.out} (threshold {prov['threshold']}, held-out F1 {h['f1']:.3f}, "
          f"hit rate {h['hit_rate']:.3f}; {prov['total_s']} s)")
    return 0


COMMANDS = (
    Command("trainset", "render a large seeded training set (frames, per-row truth) for learned trackers",
            _add_trainset, _trainset, renders=True),
    Command("train", "train the `learned` tracker on a rendered training set (JAX; the [learn] extra)",
            _add_train, _train),
)
