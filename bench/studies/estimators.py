"""Sub-pixel estimator study (``stripebench estimators``).

Every registered sub-pixel tracker (``trackers.make(name).subpixel``) runs,
with its default parameters, on analytic Gaussian stripes over a grid of
stripe width (Gaussian sigma, px), peak level (DN above the background),
noise (DN) and sub-pixel phase, in the manner of the classic comparisons of
sub-pixel peak detectors (Fisher & Naidu 1996; Naidu & Fisher 1991).

The frames (:func:`stripe_frame`) imitate an 8-bit camera: each pixel holds
the Gaussian line profile integrated over its width, on a constant background,
plus seeded Gaussian noise, rounded and clipped to 0..255. The stripe is
tilted by one pixel over the frame's height, so its rows sweep the sub-pixel
phase uniformly (plus a random offset per frame); a laser-off frame with its
own noise is passed as ``background`` (only ``com_bg`` uses it).

Outputs, in ``--out`` (default ``results/runs/estimators``): ``estimators.csv``
with one line per (tracker, sigma, peak, noise) and ``estimators.png``, mean
absolute error against sigma, one line per tracker, one panel per noise level.
"""

from __future__ import annotations

import csv
import pathlib

import numpy as np

__all__ = ["stripe_frame", "run_study", "write_csv", "plot", "study", "FIELDS", "DEFAULTS", "MAX_FRAMES",
           "BACKGROUND_DN"]

#: Columns of the table, in order.
FIELDS = ("tracker", "sigma_px", "peak_dn", "noise_dn", "rows", "reported", "mean_abs_px", "rmse_px", "bias_px",
          "p95_abs_px", "outliers")

_BACKGROUND = 10.0
_OUTLIER_PX = 1.0


def stripe_frame(sigma: float, peak: float, noise: float, rng: np.random.Generator, *, height: int = 64,
                 width: int = 128, background: float = _BACKGROUND):
    """One 8-bit frame with a near-vertical Gaussian stripe, its truth and a laser-off frame.

    Parameters
    ----------
    sigma : float
        Standard deviation of the stripe's profile, px.
    peak : float
        Peak of the (continuous) profile above the background, DN.
    noise : float
        Standard deviation of the additive Gaussian noise, DN.
    rng : numpy.random.Generator
        Source of the phase offset and the noise.
    height, width : int
        Frame size; the stripe's centre moves by one pixel from the first row
        to the last, so the rows cover every sub-pixel phase.
    background : float
        Background level, DN.

    Returns
    -------
    image : ndarray of uint8, shape (height, width)
    truth : ndarray of float64, shape (height,)
        The stripe's centre in each row (pixel-centre convention).
    laser_off : ndarray of uint8, shape (height, width)
        The background with independent noise.
    """
    from trackers.testing import stripe_profile

    truth = width / 2.0 + rng.uniform(-0.5, 0.5) + np.arange(height) / height
    profile = stripe_profile(truth, width, sigma, peak)

    def camera(signal):
        return np.clip(np.rint(background + signal + rng.normal(0.0, noise, signal.shape)), 0, 255).astype(np.uint8)

    return camera(profile), truth, camera(np.zeros_like(profile))


def _subpixel_trackers(names=None):
    import trackers

    names = names if names is not None else trackers.available()
    out = []
    for name in names:
        t = trackers.make(name)
        if t.subpixel:
            out.append(t)
    return out


def run_study(sigmas, peaks, noises, *, frames: int = 8, seed: int = 0, tracker_names=None) -> list[dict]:
    """Run every sub-pixel tracker over the grid; one dict per cell (see :data:`FIELDS`).

    Each (sigma, peak, noise) cell uses ``frames`` frames from its own seed
    (derived from ``seed`` and the cell's index, so adding trackers does not
    change the frames). ``mean_abs_px``, ``rmse_px``, ``bias_px`` and
    ``p95_abs_px`` are over the reported rows (NaN if none); ``reported`` is
    the fraction of rows reported; ``outliers`` the fraction of reported rows
    more than 1 px off.
    """
    tracker_list = _subpixel_trackers(tracker_names)
    results = []
    cell = 0
    for sigma in sigmas:
        for peak in peaks:
            for noise in noises:
                rng = np.random.default_rng([seed, cell])
                cell += 1
                data = [stripe_frame(sigma, peak, noise, rng) for _ in range(frames)]
                for t in tracker_list:
                    errors = []
                    rows = 0
                    for image, truth, off in data:
                        cols = t.track(image, background=off).columns
                        rows += cols.size
                        ok = ~np.isnan(cols)
                        errors.append(cols[ok] - truth[ok])
                    err = np.concatenate(errors)
                    a = np.abs(err)
                    results.append({
                        "tracker": t.name, "sigma_px": float(sigma), "peak_dn": float(peak), "noise_dn": float(noise),
                        "rows": rows, "reported": err.size / rows,
                        "mean_abs_px": float(a.mean()) if a.size else np.nan,
                        "rmse_px": float(np.sqrt(np.mean(err**2))) if a.size else np.nan,
                        "bias_px": float(err.mean()) if a.size else np.nan,
                        "p95_abs_px": float(np.percentile(a, 95)) if a.size else np.nan,
                        "outliers": float(np.mean(a > _OUTLIER_PX)) if a.size else np.nan,
                    })
    return results


def write_csv(results: list[dict], path) -> None:
    """Write the table (columns :data:`FIELDS`)."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for r in results:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def _params(name: str) -> dict:
    import trackers

    return trackers.make(name).get_params()


def _label(name: str) -> str:
    est = _params(name).get("estimator")
    return f"{name} ({est})" if est else name


def plot(results: list[dict], path, peak: float) -> None:
    """Mean |error| against sigma at one peak level: one line per tracker,
    one panel per noise level (log scale). matplotlib is imported here, Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in results if r["peak_dn"] == peak]
    noises = sorted({r["noise_dn"] for r in rows})
    names = list(dict.fromkeys(r["tracker"] for r in rows))
    fig, axes = plt.subplots(1, len(noises), figsize=(3.2 * len(noises) + 1.6, 3.4), sharey=True, squeeze=False)
    markers = "os^vDxP*h"
    for ax, noise in zip(axes[0], noises):
        for k, name in enumerate(names):
            pts = sorted((r["sigma_px"], r["mean_abs_px"]) for r in rows if r["tracker"] == name and r["noise_dn"] == noise)
            x = [p[0] for p in pts]
            y = [max(p[1], 1e-4) for p in pts]
            # a hybrid refining with another tracker's estimator overlays it: dashed, on top
            hybrid = "estimator" in _params(name)
            ax.plot(x, y, "--" if hybrid else "-", marker=None if hybrid else markers[k % len(markers)], ms=3.5,
                    lw=2.0 if hybrid else 1.2, zorder=3 if hybrid else 2, label=_label(name))
        ax.set_yscale("log")
        ax.set_title(f"noise {noise:g} DN", fontsize=9)
        ax.set_xlabel("stripe sigma (px)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.tick_params(labelsize=8)
    axes[0][0].set_ylabel("mean |error| (px)", fontsize=9)
    axes[0][-1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.02, 0.5), frameon=False)
    fig.suptitle(f"Sub-pixel estimators on Gaussian stripes, peak {peak:g} DN over {_BACKGROUND:g} DN, 8-bit",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _summary(results, peak, noise, sigmas) -> str:
    names = list(dict.fromkeys(r["tracker"] for r in results))
    head = f"mean |error| px at peak {peak:g} DN, noise {noise:g} DN:"
    lines = [head, f"{'tracker':<14}" + "".join(f"{'s=' + format(s, 'g'):>9}" for s in sigmas)]
    for name in names:
        vals = {r["sigma_px"]: r["mean_abs_px"] for r in results
                if r["tracker"] == name and r["peak_dn"] == peak and r["noise_dn"] == noise}
        lines.append(f"{name:<14}" + "".join(f"{vals.get(s, np.nan):>9.4f}" for s in sigmas))
    return "\n".join(lines)


#: The study's grid by default: stripe sigmas (px), peak levels (DN above the background), noise sigmas (DN).
DEFAULTS = {"sigmas": [0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0], "peaks": [30.0, 100.0, 200.0],
            "noises": [0.0, 1.0, 2.0, 4.0], "frames": 8, "seed": 0, "out": "results/runs/estimators"}
MAX_FRAMES = 10_000  # 64-row frames per cell
#: The frames' background level, DN.
BACKGROUND_DN = _BACKGROUND


def study(*, out=DEFAULTS["out"], sigmas=DEFAULTS["sigmas"], peaks=DEFAULTS["peaks"], noises=DEFAULTS["noises"],
          frames: int = DEFAULTS["frames"], seed: int = DEFAULTS["seed"], trackers=None, plot_peak=None,
          no_plot: bool = False) -> int:
    """Run the study and write its table and figure into ``out`` (``stripebench estimators``).

    Parameters
    ----------
    out : path
        Output folder (created).
    sigmas, peaks, noises : list of float
        The grid: stripe sigmas (px, > 0), peak levels (DN above :data:`BACKGROUND_DN`, > 0),
        noise sigmas (DN, >= 0).
    frames : int
        64-row frames per cell.
    seed : int
        Seed of the frames.
    trackers : sequence of str or :class:`bench.config.TrackerSpec`, optional
        Plain tracker names (default: every sub-pixel tracker).
    plot_peak : float, optional
        The peak level plotted (one of ``peaks``; default the middle one).
    no_plot : bool
        Write the table only.

    Returns
    -------
    int
        0. Every bad value raises :class:`bench.config.ConfigError` before any work.
    """
    from bench.config import ConfigError
    from bench.config.options import plain_tracker_names

    names = plain_tracker_names(trackers) if trackers else None
    if not _subpixel_trackers(names):
        raise ConfigError("--trackers: none of the selected trackers is a sub-pixel tracker")
    if plot_peak is None:
        plot_peak = sorted(peaks)[len(peaks) // 2]
    if plot_peak not in peaks:
        raise ConfigError(f"--plot-peak {plot_peak:g} is not one of --peaks")
    results = run_study(sigmas, peaks, noises, frames=frames, seed=seed, tracker_names=names)
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(results, out / "estimators.csv")
    print(f"wrote {out / 'estimators.csv'} ({len(results)} lines)")
    if not no_plot:
        plot(results, out / "estimators.png", plot_peak)
        print(f"wrote {out / 'estimators.png'}")
    for noise in noises:
        print(_summary(results, plot_peak, noise, sigmas))
    return 0
