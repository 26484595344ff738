"""``stripebench track`` and ``stripebench real``: trackers on photographs, and on a real set with references."""

from __future__ import annotations

import sys
from pathlib import Path

from bench.cli.common import Command, UsageError, check_out_folder
from bench.cli.options import add_force, add_n_boot, add_out, add_quiet, add_seed, add_tol, add_trackers
from bench.config.options import REAL_DEFAULTS

__all__ = ["COMMANDS"]


def _specs(args):
    if args.trackers is not None:
        return args.trackers
    from bench.config import parse_trackers

    return parse_trackers([])


def _add_track(p) -> None:
    from bench.store.realset import CHANNELS, LASERS, ROTATIONS

    p.add_argument("images", nargs="+", type=Path, metavar="IMAGE", help="image files (8/16-bit, grey or colour)")
    add_out(p, "output folder", required=True)
    add_force(p, "; replace outputs written for another input")
    add_trackers(p, "tracker names or settings as for `run` (default: every registered tracker)")
    p.add_argument("--background", type=Path, metavar="OFF_IMAGE", help="a laser-off frame used for every image")
    p.add_argument("--no-pair", action="store_true", help="do not use NAME_off.EXT beside NAME.EXT as background")
    p.add_argument("--channel", default="auto", choices=CHANNELS,
                   help="what the trackers see of a colour image (auto: excess of the laser's colour)")
    p.add_argument("--laser", default="red", choices=LASERS, help="laser colour (default red)")
    p.add_argument("--rotate", type=int, default=0, choices=ROTATIONS,
                   help="turn the image counter-clockwise first (for horizontal stripes)")


def _track(args) -> int:
    """Trackers on photographs (exit 1 if a file failed)."""
    from bench.run.real import track_images
    from bench.store import realset as real

    specs = _specs(args)
    check_out_folder(args.out)
    if args.background is not None:
        try:
            real.read_image(args.background)
        except real.ImageError as exc:
            raise UsageError(f"--background: {exc}") from None
    from bench.report.real import legend, overlay_png

    failed = track_images(args.images, args.out, specs, background=args.background, pair=not args.no_pair,
                          channel=args.channel, laser=args.laser, rotate_deg=args.rotate, force=args.force,
                          draw=overlay_png, legend=legend)
    return 1 if failed else 0


def real_table(summary: dict, labels) -> str:
    """The console table of a real run: per tracker (in the order of ``labels``) F1 over rows with its 95 %
    interval, the false-report rate with its false and stripe-less rows, then the hit rate with its interval,
    MAE on the hits and coverage."""
    def f(v, fmt=".3f"):
        return format(v, fmt) if isinstance(v, (int, float)) and v == v else "–"

    lines = [f"{'tracker':<16}{'F1':>7}{'95 % CI':>16}{'false reports':>15}{'false/none':>12}{'hit rate':>10}"
             f"{'95 % CI':>16}{'MAE px':>8}{'coverage':>10}"]
    for lab in labels:
        s = summary["trackers"][lab]
        d, h = s.get("detection") or {}, s["hit_rate"]
        ci = f"[{f(d.get('f1_lo'))}, {f(d.get('f1_hi'))}]"
        rows = f"{d.get('n_false', 0)}/{d.get('n_false', 0) + d.get('n_quiet', 0)}"
        lines.append(f"{lab:<16}{f(d.get('f1')):>7}{ci:>16}{f(d.get('false_report_rate')):>15}{rows:>12}"
                     f"{f(h['mean']):>10}{'[' + f(h['lo']) + ', ' + f(h['hi']) + ']':>16}"
                     f"{f(s['mae_px']['mean'], '.2f'):>8}{f(s['coverage']['mean']):>10}")
    return "\n".join(lines)


def _add_real(p) -> None:
    p.add_argument("dataset", type=Path, help="real-set folder (e.g. bench/data/real)")
    add_out(p, "run folder (default: results/runs/real-<dataset name>)")
    add_force(p)
    add_trackers(p, "tracker names or settings as for `run` (default: every registered tracker)")
    add_tol(p)
    add_n_boot(p)
    add_seed(p, "bootstrap seed", default=REAL_DEFAULTS["seed"])
    p.add_argument("--check", action="store_true", help="only validate the dataset (one line per problem, exit 2)")
    p.add_argument("--by-rig", action="store_true",
                   help="also print F1, false-report rate and hit rate per rig (the manifest's `rig`), with 95 %% "
                        "intervals over each rig's photographs and, for all rigs, over rigs")
    p.add_argument("--predict", action="store_true",
                   help="also predict the figures from frames made for the photographs (as `stripebench predict`, "
                        "into RUN/predict) and compare them with the measured ones")
    add_quiet(p)


def _real(args) -> int:
    """Trackers evaluated on a real set: every value and the whole set checked before tracking."""
    from bench.run.real import run_real
    from bench.store import realset as real

    specs = _specs(args)
    dataset = args.dataset
    _, problems = real.validate_dataset(dataset)
    extra = real.ignored_columns(dataset)
    if extra:  # sets made elsewhere carry more columns: listed once, then ignored
        print(f"stripebench real: manifest.csv: ignored column(s): {', '.join(extra)}", file=sys.stderr)
    if args.check:  # one line per problem
        from bench.errors import one_line

        for line in problems:
            print(f"stripebench real: {one_line(line)}", file=sys.stderr)
        if problems:
            return 2
        print(f"stripebench real: {dataset} is a valid real set")
        return 0
    if problems:
        more = f" (and {len(problems) - 1} more; `--check` lists them)" if len(problems) > 1 else ""
        raise UsageError(f"DATASET {str(dataset)!r} is not a valid real set: {problems[0]}{more}")
    if args.out is None:
        from bench.store.files import runs_root

        args.out = runs_root() / f"real-{dataset.resolve().name}"
    check_out_folder(args.out, inputs=[("DATASET", dataset)])
    from bench.report.real import build_real_report, overlay_png

    out = run_real(dataset, args.out, specs, tol_px=args.tol, n_boot=args.n_boot, seed=args.seed, quiet=args.quiet,
                   force=args.force, draw=overlay_png)
    build_real_report(out)
    if not args.quiet:
        from bench.store.realrun import load_real_run

        from bench.report.real import images_by_f1, ranked_trackers

        saved = load_real_run(out)
        summary = saved["summary"]
        print(real_table(summary, ranked_trackers(summary)))
        per = images_by_f1(saved["metrics"], list(summary["trackers"]))
        hard = [(n, float(per.loc[n].mean())) for n in per.index[:3] if per.loc[n].notna().any()]
        if hard:
            print("hardest photographs (mean F1 over the trackers): "
                  + ", ".join(f"{n} {v:.3f}" for n, v in hard))
    if args.by_rig:  # asked for: printed with --quiet too
        from bench.store.realrun import load_real_run

        print(by_rig_table(load_real_run(out)["summary"]))
    print(f"stripebench: report at {out / 'report.html'}")
    if args.predict:
        _predict_and_compare(args, specs, out)
    return 0


def by_rig_table(summary: dict) -> str:
    """``real --by-rig``'s lines: per tracker, each rig's photographs, F1, false-report rate and hit rate with their
    intervals (``summary.json``'s ``rigs``, :func:`bench.evaluate.loro.rig_figures`), then all rigs."""
    from bench.evaluate.formats import estimate

    def cell(d, k):
        return estimate(d[k], d[f"{k}_lo"], d[f"{k}_hi"])

    lines = ["per rig (95 % intervals over the rig's photographs; over all rigs, over rigs; none from one photograph):"]
    for lab, s in summary["trackers"].items():
        rigs = s.get("rigs")
        if not rigs:
            continue
        wide = max(len(g) for g in [*rigs["rigs"], "all rigs"]) + 2
        lines.append(f"{lab}")
        lines.append(f"  {'rig':<{wide}}{'photos':>7}  {'F1':<22}{'false-report rate':<24}{'hit rate':<22}")
        for g, d in [*rigs["rigs"].items(), ("all rigs", rigs["all"])]:
            lines.append(f"  {g:<{wide}}{d['n_photos']:>7}  {cell(d, 'f1'):<22}{cell(d, 'false_report_rate'):<24}"
                         f"{cell(d, 'recall'):<22}")
    return "\n".join(lines)


def _predict_and_compare(args, specs, out) -> None:
    """``real --predict``: the prediction into ``RUN/predict``, then predicted beside measured."""
    import math

    from bench.evaluate.prediction import COMPARED
    from bench.report.predict import build_predict_report
    from bench.run.real import predict_real

    say = (lambda m: None) if args.quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    res = predict_real(args.dataset, out, specs, n_boot=args.n_boot, seed=args.seed, say=say)
    build_predict_report(res["result"])
    names, cmp, rigs = res["doc"]["photographs"], res["result"]["comparison"], res["result"]["comparison_rigs"]
    print(f"predicted vs measured on the {len(names)} photographs in range (measured rows pooled):")
    print(f"{'tracker':<16}{'hit rate pred':>14}{'measured':>10}{'F1 pred':>9}{'measured':>10}")
    f1 = {r["tracker"]: r for r in cmp["f1"]["table"]}
    for r in cmp["hit_rate"]["table"]:
        g = f1.get(r["tracker"], {"synthetic": float("nan"), "real": float("nan")})
        print(f"{r['tracker']:<16}{r['synthetic']:>14.3f}{r['real']:>10.3f}{g['synthetic']:>9.3f}{g['real']:>10.3f}")
    span = res["doc"]["rank_interval"]
    for k in COMPARED:
        v = cmp[k]
        within = "" if not span else (f"; 95 % of resampled photograph sets {span[k]['interval'][0]:.2f} to "
                                      f"{span[k]['interval'][1]:.2f}")
        print(f"{k}: Spearman rho {v['spearman_rho']:.3f} (p = {v['spearman_p']:.2g}, n = {v['n']}{within}), "
              f"mean |predicted - measured| {v['mean_abs_diff']:.3f}")
    rel = res["doc"]["measured_reliability"]
    if rel:
        def whole(v):  # NaN: the halves do not agree, nothing to step up
            return f"{v:.2f}" if math.isfinite(v) else "none"

        print("measured ranks' own repeatability (Spearman rho between random halves of the photographs; for all of "
              "them, stepped up): " + "; ".join(f"{k} {rel[k]['split_half_rho']:.2f} ({whole(rel[k]['full_set'])})"
                                                 for k in COMPARED))
    print("per rig (rows of its photographs pooled on both sides): Spearman rho / mean |predicted - measured|")
    wide = max([34, *(len(str(g)) + 2 for g in rigs)])
    print(f"{'rig':<{wide}}{'photos':>7}{'hit rate':>17}{'F1':>17}   measured ranks repeat (hit rate, F1)")
    for g, v in rigs.items():
        cells = "".join(f"{v[k]['spearman_rho']:>9.3f} / {v[k]['mean_abs_diff']:.3f}" for k in ("hit_rate", "f1"))
        rr = res["doc"]["rigs"][g]["measured_reliability"]
        rep = "" if not rr else f"   {rr['hit_rate']['split_half_rho']:.2f}, {rr['f1']['split_half_rho']:.2f}"
        print(f"{g:<{wide}}{len(v['photographs']):>7}{cells}{rep}")
    print(f"stripebench: prediction at {out / 'predict' / 'report.html'} (per photograph: compare.json)")


COMMANDS = (
    Command("track", "run trackers on photographs (PNG/JPEG/TIFF/BMP): a CSV and an overlay per image", _add_track,
            _track),
    Command("real", "evaluate trackers on a real set (manifest.csv, NAME.png, NAME_ref.csv)", _add_real, _real),
)
