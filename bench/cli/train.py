"""``stripebench trainset`` and ``train``: rendered training sets and the ``learned`` tracker's training."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from bench.cli.common import Command, UsageError
from bench.cli.options import add_quiet, add_seed, arg_type
from bench.config import ConfigError
from bench.config.options import finite_float, positive_int, scheduler_address, size_value, workers_value

__all__ = ["COMMANDS"]

#: The largest ``--units``, ``--angles`` and ``--noise-draws`` (a training set of 10**6 frames is days of renders).
MAX_COUNT = 100_000


def _count(name: str, text) -> int:
    return positive_int(name, text, MAX_COUNT)


def _holdout(name: str, text) -> float:
    """The share of units held out: a number in (0, 1)."""
    x = finite_float(name, text, low=0, low_open=True, high=1)
    if x >= 1:
        raise ConfigError(f"{name} must be a finite number > 0 and < 1, got {text!r}")
    return x


def _views(name: str, text) -> tuple:
    """Distinct comma-separated views of a colour frame (:func:`bench.run.trainset.tracker_view`'s channels):
    ``"auto,laser"`` gives ``("auto", "laser")``."""
    views = tuple(v.strip() for v in str(text).split(",") if v.strip())
    from bench.run.trainset import VIEWS as known

    if not views or any(v not in known for v in views) or len(set(views)) < len(views):
        raise ConfigError(f"{name} must be distinct names among {', '.join(known)}, got {text!r}")
    return views


def _shrink(name: str, text) -> tuple:
    """Distinct comma-separated integer factors >= 2, or ``none`` (no shrunk copies)."""
    t = str(text).strip().lower()
    if t == "none":
        return ()
    try:
        factors = tuple(int(v) for v in t.split(",") if v.strip())
    except ValueError:
        factors = ()
    if not factors or any(f < 2 for f in factors) or len(set(factors)) < len(factors):
        raise ConfigError(f"{name} must be distinct integers >= 2 separated by commas, or none, got {text!r}")
    return factors


def _add_trainset(p) -> None:
    p.add_argument("--out", type=Path, required=True, help="training-set folder (a rerun resumes it)")
    p.add_argument("--units", type=arg_type(_count, "--units"), default=30, help="scenes drawn (default 30)")
    p.add_argument("--angles", type=arg_type(_count, "--angles"), default=4,
                   help="mirror angles per scene (default 4)")
    p.add_argument("--noise-draws", type=arg_type(_count, "--noise-draws"), default=2,
                   help="sensor-noise draws per angle (default 2)")
    add_seed(p, "seed of the draws", default=1)
    p.add_argument("--draws", type=int, choices=(1, 2, 3), default=2,
                   help="draw rules (bench.run.trainset.DRAW_RULES): 1 the first weights' (one level per scene), "
                        "2 per-frame levels with saturated stripes and wide lines (default 2), 3 as 2 with a "
                        "distractor in half the units (scenes.distractors)")
    p.add_argument("--size", type=arg_type(size_value, "--size"), default=(512, 480), metavar="WxH",
                   help="WIDTHxHEIGHT (default 512x480)")
    p.add_argument("--workers", type=arg_type(workers_value, "--workers"), default=None,
                   help="render on a local Dask cluster of this many processes (default: in this process)")
    p.add_argument("--scheduler", type=arg_type(lambda n, v: scheduler_address(v, n), "--scheduler"), default=None,
                   help="a Dask scheduler's address to render on (tcp://HOST:PORT; \"sync\": in this process)")
    add_quiet(p, "no progress notes")


def _trainset(args) -> int:
    from bench.run.trainset import build_trainset

    w, h = args.size
    scheduler = None if args.scheduler == "sync" else args.scheduler
    root = build_trainset(args.out, n_units=args.units, angles_per_unit=args.angles, seed=args.seed,
                          noise_draws=args.noise_draws, width=w, height=h, workers=args.workers,
                          scheduler=scheduler, quiet=args.quiet, draws=args.draws)
    print(f"stripebench: training set at {root}")
    return 0


def default_weights_out(trainset: Path, seed: int) -> Path:
    """Where ``train`` writes without ``--out``: ``RUNS/learned/<training set's folder>-seed<N>.npz`` (never the
    shipped weights)."""
    from bench.store.files import runs_root

    return runs_root() / "learned" / f"{Path(trainset).resolve().name}-seed{seed}.npz"


def _add_train(p) -> None:
    p.add_argument("trainset", type=Path, help="a finished training set (stripebench trainset)")
    p.add_argument("--out", type=Path, default=None,
                   help="weights file; its curves go beside it as .png (default: RUNS/learned/TRAINSET-seedN.npz "
                        "under the runs folder; the shipped trackers/models/learned.npz changes only when named "
                        "here)")
    p.add_argument("--epochs", type=arg_type(_count, "--epochs"), default=None,
                   help="training epochs (default: HyperParams)")
    add_seed(p, "seed of the initialisation and the batches", default=0)
    p.add_argument("--views", type=arg_type(_views, "--views"), default=("auto", "laser"),
                   help="comma-separated views of a colour frame to train and hold out on: auto (what a run gives a "
                        "tracker), laser (the laser's plain channel), r, g, b, gray (default auto,laser)")
    p.add_argument("--shrink", type=arg_type(_shrink, "--shrink"), default=None, metavar="N,N|none",
                   help="each frame also used once shrunk by a factor drawn from these (a phone's narrow, clean "
                        "stripes); none: no shrunk copies (default: HyperParams, 2,4)")
    p.add_argument("--from-weights", type=Path, default=None, metavar="NPZ",
                   help="no training: take this weights file's network and choose only its operating point "
                        "(threshold and chain costs) on the training set's held-out units")
    p.add_argument("--holdout", type=arg_type(_holdout, "--holdout"), default=0.2,
                   help="share of units held out, in (0, 1) (default 0.2)")
    add_quiet(p, "no progress notes")


def _train(args) -> int:
    import importlib.util
    from dataclasses import replace

    missing = [m for m in ("jax", "flax", "optax") if importlib.util.find_spec(m) is None]
    if missing:
        raise UsageError(f"stripebench train needs JAX, Flax and Optax ({', '.join(missing)} missing): "
                         "pip install -e '.[learn]'")
    if args.from_weights is not None:  # checked whole before any work (and before JAX is imported)
        from trackers.learned import WeightsError, load_weights

        try:
            load_weights(args.from_weights)
        except WeightsError as exc:
            raise UsageError(f"--from-weights: {exc}") from None
    from bench.studies.train import HyperParams, operating_point_from_weights, train_from_trainset

    hp = HyperParams(seed=args.seed, views=args.views)
    if args.epochs is not None:
        hp = replace(hp, epochs=args.epochs)
    if args.shrink is not None:
        hp = replace(hp, shrink=args.shrink)
    say = (lambda m: None) if args.quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    if args.out is None:
        args.out = default_weights_out(args.trainset, args.seed)
    t0 = time.perf_counter()
    if args.from_weights is not None:
        prov = operating_point_from_weights(args.trainset, args.from_weights, args.out, hp=hp, holdout=args.holdout,
                                            say=say)
    else:
        prov = train_from_trainset(args.trainset, args.out, hp=hp, holdout=args.holdout, say=say)
    h, op = prov["heldout"]["both"], prov["operating_point"]
    print(f"stripebench: weights at {args.out} (threshold {op['threshold']}, jump cost {op['jump_cost']}, switch "
          f"cost {op['switch_cost']}; held-out F1 {h['f1']:.3f}, hit rate {h['hit_rate']:.3f}; "
          f"{time.perf_counter() - t0:.1f} s)")
    return 0


COMMANDS = (
    Command("trainset", "render a large seeded training set (frames, per-row truth) for learned trackers",
            _add_trainset, _trainset, renders=True),
    Command("train", "train the `learned` tracker on a rendered training set (JAX; the [learn] extra)",
            _add_train, _train),
)
