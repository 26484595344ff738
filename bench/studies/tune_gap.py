"""Choose ``dp_gap``'s default off level and switch cost by a fixed procedure (``stripebench tune dp_gap``).

The profile (default ``bench/config/profiles/tune_dp_gap.toml``) lists the
experiments (scene, material, optional scene-parameter overrides), the render
settings, the seed, the grid of ``off_rel`` and ``switch_rows`` values and
reference trackers scored alongside (``dp4``, ``dp8``). Every experiment is
one scan (:func:`bench.scan.run_scan`, renders cached, one checkpoint per
experiment under ``OUT/checkpoints``) tracked by ``dp_gap`` at every grid
point and by the references, each given the scan's laser-off frame as the
benchmark gives it.

Criterion (written in the profile before any result was seen). In an
experiment, over all its frames and rows:

* *hit fraction* ``h``: lit object rows (truth on the object) where the
  tracker's column is within ``hit_px`` of the truth, over the lit object
  rows (a row not reported is a miss);
* *wrong fraction* ``w``: rows, anywhere in the frame, where the tracker
  reports a column that is not within ``hit_px`` of that row's truth (or
  where the row has no truth at all: no lit visible stripe), over the same
  number of lit object rows;
* the experiment's *score* is ``h - w``: a right column gains what a wrong
  one loses, and leaving a row out is neutral.

The score of a grid point is the mean score over the experiments; the
default is the best grid point, ties (within ``tie``) going to the smallest
``off_rel`` and then to the largest ``switch_rows`` (the setting that leaves
out the fewest rows: closest to the paper's DP, which never does).

Output in ``OUT`` (default ``results/runs/tune_dp_gap/``): ``tune_gap.csv``
(columns off_rel, switch_rows, tracker, experiment, hit_fraction,
wrong_fraction, score, rows), ``tune_dp_gap.png`` (the grid's scores) and the
chosen values with a per-experiment table of the references and the chosen
``dp_gap`` on stdout.
"""

from __future__ import annotations

import csv
import pathlib
import sys

import numpy as np

from bench.config.tune import GAP_DEFAULT_PROFILE as DEFAULT_PROFILE, GapProfile, load_gap_profile as load_profile  # noqa: F401

__all__ = ["GapProfile", "load_profile", "gap_score", "choose", "run", "main"]

def gap_score(columns, truth_columns, on_object, hit_px: float) -> tuple[float, float, int]:
    """Hit fraction, wrong fraction and the number of lit object rows (see the module notes).

    Parameters
    ----------
    columns, truth_columns : array_like (F, H) or (H,), float, px
        Tracked and true columns (NaN: not reported / no lit visible stripe).
    on_object : array_like, same shape, bool
    hit_px : float

    Returns
    -------
    hit, wrong : float
        NaN if there is no lit object row.
    rows : int
        Lit object rows.

    Examples
    --------
    >>> gap_score([10.0, 50.0, np.nan, 7.0], [10.5, 20.0, 30.0, np.nan], [True, True, True, False], 3.0)
    (0.3333333333333333, 0.6666666666666666, 3)
    """
    cols = np.asarray(columns, float)
    truth = np.asarray(truth_columns, float)
    lit = np.asarray(on_object, bool) & np.isfinite(truth)
    n = int(lit.sum())
    if n == 0:
        return float("nan"), float("nan"), 0
    with np.errstate(invalid="ignore"):
        near = np.abs(cols - truth) <= hit_px  # NaN compares False
    reported = np.isfinite(cols)
    return float((near & lit).sum() / n), float((reported & ~near).sum() / n), n


def choose(scores: dict[tuple[float, float], float], tie: float) -> tuple[float, float]:
    """The (off_rel, switch_rows) with the best score; scores within ``tie`` of
    the best go to the smallest off_rel, then the largest switch_rows.

    Examples
    --------
    >>> choose({(0.1, 10.0): 0.50, (0.2, 10.0): 0.503, (0.1, 30.0): 0.499}, tie=0.005)
    (0.1, 30.0)
    """
    best = max(scores.values())
    near = [k for k, s in scores.items() if s >= best - tie]
    return min(near, key=lambda k: (k[0], -k[1]))


def _label(name: str, off: float, sw: float) -> str:
    return f"{name}@off={off:g},sw={sw:g}"


def run(profile: GapProfile, out: pathlib.Path, *, progress: bool = True):
    """Run the tuning scans and score them.

    Returns
    -------
    chosen : (float, float)
        The chosen ``(off_rel, switch_rows)``.
    scores : dict (off_rel, switch_rows) -> float
        Mean score over experiments.
    records : list of dict
        One per (tracker label, experiment): ``off_rel``, ``switch_rows`` (NaN
        for the references), ``hit_fraction``, ``wrong_fraction``, ``score``, ``rows``.
    """
    import scenes
    import trackers

    from bench.run.scan import run_scan

    out.mkdir(parents=True, exist_ok=True)
    grid = [(o, s) for o in profile.off_rel for s in profile.switch_rows]
    tr = {_label(profile.tracker, o, s): trackers.make(profile.tracker, off_rel=o, switch_rows=s) for o, s in grid}
    for ref in profile.references:
        tr[ref] = trackers.make(ref)
    r = profile.render
    records = []
    for k, e in enumerate(profile.experiments):
        overrides = {key: v for key, v in e.items() if key not in ("scene", "material")}
        scene = scenes.make(e["scene"], material=e["material"], seed=profile.seed, width=r["width"],
                            height=r["height"], spp=r["spp"], **overrides)
        angles = scene.object.default_angles(scene.rig.zeta_deg, r["n_angles"])
        key = "".join([f"{e['scene']}-{e['material']}"] + [f"_{a}={b}" for a, b in sorted(overrides.items())])
        if progress:
            print(f"[{k + 1}/{len(profile.experiments)}] {key}: {len(angles)} frames", file=sys.stderr, flush=True)
        res = run_scan(key, scene, angles, tr, spp=r["spp"], seed=profile.seed,
                          checkpoint=out / "checkpoints" / f"{key}.npz", progress=progress)
        for label in tr:
            hit, wrong, rows = gap_score(res.columns[label], res.truth_columns, res.on_object, profile.hit_px)
            o, s = next(((o, s) for o, s in grid if _label(profile.tracker, o, s) == label), (np.nan, np.nan))
            records.append({"off_rel": o, "switch_rows": s, "tracker": label, "experiment": key,
                            "hit_fraction": hit, "wrong_fraction": wrong, "score": hit - wrong, "rows": rows})
    scores = {}
    for o, s in grid:
        vals = [rec["score"] for rec in records if rec["tracker"] == _label(profile.tracker, o, s)
                and np.isfinite(rec["score"])]
        scores[o, s] = float(np.mean(vals)) if vals else float("nan")
    finite = {k: v for k, v in scores.items() if np.isfinite(v)}
    if not finite:
        raise ValueError("`profile` gives no lit object row in any experiment: nothing to score")
    chosen = choose(finite, profile.tie)
    with open(out / "tune_gap.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["off_rel", "switch_rows", "tracker", "experiment", "hit_fraction",
                                           "wrong_fraction", "score", "rows"])
        w.writeheader()
        w.writerows(records)
    _plot(profile, scores, chosen, out / "tune_dp_gap.png")
    return chosen, scores, records


def _plot(profile, scores, chosen, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    offs = sorted(profile.off_rel)
    sws = sorted(profile.switch_rows)
    z = np.array([[scores[o, s] for s in sws] for o in offs])
    fig, ax = plt.subplots(figsize=(6.0, 4.0), dpi=120)
    im = ax.imshow(z, origin="lower", cmap="viridis", aspect="auto")
    for i in range(len(offs)):
        for j in range(len(sws)):
            bold = (offs[i], sws[j]) == tuple(chosen)
            ax.text(j, i, f"{z[i, j]:.3f}", ha="center", va="center", fontsize=7,
                    color="w" if z[i, j] < np.nanmean(z) else "k", weight="bold" if bold else "normal")
    ax.set_xticks(range(len(sws)), [f"{s:g}" for s in sws])
    ax.set_yticks(range(len(offs)), [f"{o:g}" for o in offs])
    ax.set_xlabel("switch_rows (switch cost in rows of the off cost)")
    ax.set_ylabel("off_rel (off level)")
    ax.set_title(f"{profile.name}: mean (hit - wrong); chosen off_rel={chosen[0]:g}, switch_rows={chosen[1]:g}",
                 fontsize=8)
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def summary_lines(profile: GapProfile, chosen, records) -> list[str]:
    """A per-experiment table (hit / wrong) of the references and the chosen ``dp_gap``."""
    best = _label(profile.tracker, *chosen)
    labels = list(profile.references) + [best]
    exps = list(dict.fromkeys(rec["experiment"] for rec in records))
    head = f"{'experiment':<44}" + "".join(f"{lab.split('@')[0]:>16}" for lab in labels)
    lines = [head + "   (hit / wrong)"]
    for e in exps + ["mean"]:
        cells = []
        for lab in labels:
            rs = [rec for rec in records if rec["tracker"] == lab and (e == "mean" or rec["experiment"] == e)]
            h = np.nanmean([rec["hit_fraction"] for rec in rs])
            w = np.nanmean([rec["wrong_fraction"] for rec in rs])
            cells.append(f"{h:>8.3f} /{w:>6.3f}")
        lines.append(f"{e:<44}" + "".join(f"{c:>16}" for c in cells))
    return lines


DEFAULT_OUT = "results/runs/tune_dp_gap"


def add_arguments(parser) -> None:
    """The procedure's options (``stripebench tune dp_gap``; ``python -m bench.studies.tune_gap``)."""
    from bench.config.options import add_out, add_quiet

    parser.add_argument("--profile", type=pathlib.Path, default=DEFAULT_PROFILE, metavar="TOML",
                        help="tuning profile (default: bench/config/profiles/tune_dp_gap.toml)")
    add_out(parser, "output folder", default=DEFAULT_OUT)
    add_quiet(parser, "no progress bars")


def command(args) -> int:
    """Run the procedure with parsed options; a bad profile raises :class:`bench.config.ConfigError`
    (one line) before any scan."""
    profile = load_profile(args.profile)
    out = pathlib.Path(args.out)
    chosen, scores, records = run(profile, out, progress=not args.quiet)
    for line in summary_lines(profile, chosen, records):
        print(line)
    print(f"chosen off_rel = {chosen[0]:g}, switch_rows = {chosen[1]:g} (mean score {scores[chosen]:.3f}); "
          f"{out / 'tune_gap.csv'}")
    return 0


def main(argv=None) -> int:
    """``python -m bench.studies.tune_gap``: ``stripebench tune dp_gap`` with the same options."""
    from bench.config.options import study_main

    return study_main("python -m bench.studies.tune_gap", __doc__, add_arguments, command, argv)


if __name__ == "__main__":
    raise SystemExit(main())
