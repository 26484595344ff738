"""The ``learned`` tracker's training procedure (``stripebench train``): renders in, weights out.

Plain functions; JAX, Flax and Optax are imported only inside them (the ``[learn]`` extra).

1. Samples: every frame of a training set (:mod:`bench.run.trainset`) and ``augment`` sheared
   copies of it (rows moved by whole pixels: slanted and curved stripes from the rendered ones),
   each with and without its laser-off frame; per row the candidates and features of
   :func:`trackers._learned_kernels.features` (the tracker's own code). A candidate is a
   stripe (label 1) when it is the row's candidate nearest the true column and within the
   hit rule's :data:`bench.evaluate.outcomes.HIT_PX`; its regression target is the true column
   minus its 3-point fit. Other candidates within ``HIT_PX`` of the truth carry no
   classification loss (either would be a hit); every other candidate is label 0.
2. Held-out renders: whole units (scenes) chosen by :func:`bench.run.trainset.holdout_of`.
3. The network (:class:`trackers.learned` forward): input standardisation (the training
   samples' mean and SD), two ReLU layers, a linear output (logit, offset), made symmetric under
   the left-right mirror of a candidate's patch (the logit the same, the offset negated; a
   symmetric profile gets no correction of its 3-point fit); loss: weighted
   binary cross-entropy plus ``offset_weight`` x Huber(offset - target) on the stripes; Adam.
4. The operating point: the probability threshold with the best F1 over held-out rows (a miss
   and a false report priced alike), with the tracker's own decision rule.
5. The weights (``.npz``, :data:`trackers.learned.FORMAT_VERSION`) record the data, seeds,
   architecture, hyper-parameters, held-out numbers, curves and provenance; a figure of the
   curves goes beside them.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from bench.errors import InputError
from bench.evaluate.outcomes import detection_figures, hits, outcome_counts, row_outcomes
from bench.store.files import atomic_write_bytes
from bench.store.provenance import git_revision, versions

__all__ = ["HyperParams", "frame_samples", "samples_from_frames", "train_network", "flax_forward",
           "choose_threshold", "evaluate_frames", "evaluate_candidates", "frame_candidates", "choose_operating_point",
           "save_weights", "plot_curves", "train_from_trainset", "operating_point_from_weights"]


@dataclass(frozen=True)
class HyperParams:
    """Architecture and training settings (chosen on renders only)."""

    hidden: tuple = (32, 16)
    epochs: int = 12
    batch: int = 1024
    learning_rate: float = 3e-3
    weight_decay: float = 1e-4
    offset_weight: float = 2.0
    huber_delta: float = 0.5
    pos_weight: float = 1.0
    seed: int = 0
    k: int = 6
    augment: int = 1  # sheared copies of each training frame (slanted and curved stripes)
    # the views of a colour frame trained on and held out (bench.run.trainset.tracker_view's channels): "auto" is
    # what a run gives a tracker, "laser" the laser's plain channel (a real set's `channel` column may ask for it)
    views: tuple = ("auto", "laser")
    # each frame (in each view) is also used once shrunk by a factor drawn from these (seeded; () for none): the
    # narrow stripes standing far above the noise of a camera app's shrunk frame (a phone's), where weights trained
    # without shrunk copies miss rows (docs/learned.md)
    shrink: tuple = (2, 4)
    thresholds: tuple = field(default_factory=lambda: tuple(np.round(np.arange(0.05, 0.96, 0.05), 2).tolist()))
    # the chain's costs searched with the threshold for the operating point (trackers.learned.choose; 0 and 0: each
    # row decided alone); wide enough that the chosen point is not on the grid's edge
    jump_costs: tuple = (0.0, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 4.0)
    switch_costs: tuple = (0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0)


def frame_samples(image, background, truth, k: int | None = None):
    """Features, labels, offset targets and classification weights of one frame's candidates.

    Returns
    -------
    x : float32 (N, F); y : float32 (N,) 1 for the stripe; target : float32 (N,) px (0 where y = 0);
    w : float32 (N,) 1, or 0 for a candidate within HIT_PX of the truth that is not the nearest.
    """
    from trackers import _learned_kernels as lk

    feats, cols, base = lk.features(image, background, lk.K if k is None else k)
    H, K, F = feats.shape
    truth = np.asarray(truth, np.float64)
    valid = cols >= 0
    tb = np.broadcast_to(truth[:, None], (H, K))
    within = valid & hits(np.where(valid, base, np.nan), tb)  # the hit rule (bench.evaluate.outcomes)
    d = np.where(within, np.abs(base - tb), np.inf)
    near = np.argmin(d, axis=1)
    rows = np.arange(H)
    pos = np.zeros((H, K), bool)
    ok = within[rows, near]
    pos[rows[ok], near[ok]] = True
    w = np.where(pos | ~within, 1.0, 0.0)
    target = np.where(pos, truth[:, None] - base, 0.0)
    m = valid.ravel()
    return (feats.reshape(H * K, F)[m], pos.ravel()[m].astype(np.float32), target.ravel()[m].astype(np.float32),
            w.ravel()[m].astype(np.float32))


def shear(image, background, truth, shifts):
    """A frame with row ``r`` moved right by the whole number of pixels ``shifts[r]`` (edge pixels repeated):
    a slanted or curved stripe made from a rendered one, pixel values unchanged; the truth moves with it.

    >>> img = np.array([[0, 9, 0, 0], [0, 9, 0, 0]], np.uint8)
    >>> on, off, truth = shear(img, None, np.array([1.0, 1.0]), np.array([0, 2]))
    >>> on.tolist(), off, truth.tolist()
    ([[0, 9, 0, 0], [0, 0, 0, 9]], None, [1.0, 3.0])
    """
    H, W = image.shape
    idx = np.clip(np.arange(W)[None, :] - np.asarray(shifts, np.int64)[:, None], 0, W - 1)
    move = lambda a: None if a is None else np.take_along_axis(np.asarray(a), idx, axis=1)  # noqa: E731
    return move(image), move(background), np.asarray(truth, np.float64) + shifts


def augment_shifts(H: int, rng) -> np.ndarray:
    """Seeded whole-pixel row shifts: a slope of up to 1.5 px per row, or a sine of up to 25 px."""
    r = np.arange(H) - H / 2
    if rng.random() < 0.5:
        s = rng.uniform(-1.5, 1.5) * r
    else:
        s = rng.uniform(5, 25) * np.sin(2 * np.pi * r / rng.uniform(0.5 * H, 3 * H) + rng.uniform(0, 2 * np.pi))
    return np.rint(s).astype(np.int64)


def samples_from_frames(frames, k: int | None = None, *, augment: int = 0, seed: int = 0):
    """:func:`frame_samples` of (image, background, truth) triples, each with and without its background;
    with ``augment`` > 0, also that many sheared copies of each frame (:func:`shear`, seeded by ``seed``)."""
    parts = []
    rng = np.random.default_rng(seed)
    for img, off, truth in frames:
        copies = [(img, off, truth)]
        for _ in range(augment):
            copies.append(shear(img, off, truth, augment_shifts(np.asarray(img).shape[0], rng)))
        for i2, o2, t2 in copies:
            parts.append(frame_samples(i2, o2, t2, k))
            parts.append(frame_samples(i2, None, t2, k))
    out = []
    for i in range(4):  # one array at a time, each part's share freed as it is copied: a peak of one array more
        out.append(np.concatenate([p[i] for p in parts]))
        parts = [tuple(None if j == i else a for j, a in enumerate(p)) for p in parts]
    return tuple(out)


def _model(hidden):
    import flax.linen as nn

    class MLP(nn.Module):
        hidden: tuple

        @nn.compact
        def __call__(self, z):
            for i, h in enumerate(self.hidden):
                z = nn.relu(nn.Dense(h, name=f"dense{i}")(z))
            return nn.Dense(2, name="out")(z)

    return MLP(tuple(hidden))


def flax_forward(params: dict, x) -> np.ndarray:
    """The network of ``params`` (:data:`trackers.learned.PARAM_KEYS`) through Flax: (N, 2) float32."""
    import jax.numpy as jnp

    model = _model((params["w1"].shape[1], params["w2"].shape[1]))
    return np.asarray(_symmetric(model, _to_flax(params), jnp.asarray(x, jnp.float32), params["mu"], params["sd"]))


def _symmetric(model, fparams, x, mu, sd):
    """The network made mirror-symmetric, as :func:`trackers._learned_kernels._mlp` computes it."""
    import jax.numpy as jnp

    from trackers._learned_kernels import mirror

    perm, sign = mirror()
    a = model.apply(fparams, (x - mu) / sd)
    b = model.apply(fparams, (x[:, perm] * sign - mu) / sd)
    return jnp.stack([0.5 * (a[:, 0] + b[:, 0]), 0.5 * (a[:, 1] - b[:, 1])], axis=1)


def _to_flax(p):
    return {"params": {"dense0": {"kernel": p["w1"], "bias": p["b1"]}, "dense1": {"kernel": p["w2"], "bias": p["b2"]},
                       "out": {"kernel": p["w3"], "bias": p["b3"]}}}


def _from_flax(fp, mu, sd) -> dict:
    q = fp["params"]
    f = lambda a: np.asarray(a, np.float32)  # noqa: E731
    return {"mu": f(mu), "sd": f(sd), "w1": f(q["dense0"]["kernel"]), "b1": f(q["dense0"]["bias"]),
            "w2": f(q["dense1"]["kernel"]), "b2": f(q["dense1"]["bias"]), "w3": f(q["out"]["kernel"]),
            "b3": f(q["out"]["bias"])}


def _standardisation(x, chunk: int = 1 << 18) -> tuple[np.ndarray, np.ndarray]:
    """Per-feature mean and SD (at least 1e-3) of ``x`` (N, F), float32, in two chunked float64 passes: no
    full-size temporary (``x.std`` makes two, which a set of 10 M candidates cannot afford here).

    >>> x = np.random.default_rng(0).normal(3.0, 2.0, (1000, 2)).astype(np.float32)
    >>> mu, sd = _standardisation(x, chunk=64)
    >>> bool(np.allclose(mu, x.mean(axis=0), atol=1e-5) and np.allclose(sd, x.std(axis=0), atol=1e-5))
    True
    """
    n = max(len(x), 1)
    total = np.zeros(x.shape[1])
    for i in range(0, len(x), chunk):
        total += x[i:i + chunk].sum(axis=0, dtype=np.float64)
    mean = total / n
    sq = np.zeros(x.shape[1])
    for i in range(0, len(x), chunk):
        sq += np.square(x[i:i + chunk].astype(np.float64) - mean).sum(axis=0)
    return mean.astype(np.float32), np.maximum(np.sqrt(sq / n), 1e-3).astype(np.float32)


def train_network(train, val, hp: HyperParams, *, say=lambda m: None):
    """Fit the network on ``train`` = (x, y, target, w) and track the loss on ``val``; returns
    (params as float32 numpy arrays, curves: per epoch train loss, val loss, val classification accuracy)."""
    import jax
    import jax.numpy as jnp
    import optax

    if len(hp.hidden) != 2:
        raise ValueError("the tracker's forward pass has two hidden layers: `hidden` must have two sizes")
    x, y, t, w = train
    mu, sd = _standardisation(x)
    model = _model(hp.hidden)
    key = jax.random.PRNGKey(hp.seed)
    fparams = model.init(key, jnp.zeros((1, x.shape[1]), jnp.float32))
    opt = optax.adamw(optax.cosine_decay_schedule(hp.learning_rate, hp.epochs * max(1, len(x) // hp.batch)),
                      weight_decay=hp.weight_decay)
    state = opt.init(fparams)
    mu_j, sd_j = jnp.asarray(mu), jnp.asarray(sd)

    def loss_fn(p, xb, yb, tb, wb):
        out = _symmetric(model, p, xb, mu_j, sd_j)
        logit, off = out[:, 0], out[:, 1]
        cw = wb * jnp.where(yb > 0, hp.pos_weight, 1.0)
        bce = jnp.sum(cw * optax.sigmoid_binary_cross_entropy(logit, yb)) / jnp.maximum(jnp.sum(cw), 1.0)
        reg = jnp.sum(yb * optax.huber_loss(off, tb, delta=hp.huber_delta)) / jnp.maximum(jnp.sum(yb), 1.0)
        return bce + hp.offset_weight * reg, (bce, reg)

    @jax.jit
    def step(p, s, xb, yb, tb, wb):
        (loss, _), g = jax.value_and_grad(loss_fn, has_aux=True)(p, xb, yb, tb, wb)
        upd, s = opt.update(g, s, p)
        return optax.apply_updates(p, upd), s, loss

    evaluate = jax.jit(loss_fn)

    def full_loss(p, data):
        xs, ys, ts, ws = data
        tot = np.zeros(3)
        n = 0
        for i in range(0, len(xs), 65536):
            sl = slice(i, i + 65536)
            loss, (bce, reg) = evaluate(p, xs[sl], ys[sl], ts[sl], ws[sl])
            m = len(xs[sl])
            tot += m * np.array([float(loss), float(bce), float(reg)])
            n += m
        return tot / max(n, 1)

    rng = np.random.default_rng(hp.seed)
    curves = {"epoch": [], "train_loss": [], "val_loss": [], "val_bce": [], "val_offset_huber": []}
    nb = max(1, len(x) // hp.batch)
    for epoch in range(hp.epochs):
        perm = rng.permutation(len(x))
        losses = []
        for b in range(nb):
            idx = perm[b * hp.batch:(b + 1) * hp.batch]
            fparams, state, loss = step(fparams, state, x[idx], y[idx], t[idx], w[idx])
            losses.append(float(loss))
        vl = full_loss(fparams, val)
        curves["epoch"].append(epoch + 1)
        curves["train_loss"].append(float(np.mean(losses)))
        curves["val_loss"].append(float(vl[0]))
        curves["val_bce"].append(float(vl[1]))
        curves["val_offset_huber"].append(float(vl[2]))
        say(f"  epoch {epoch + 1}/{hp.epochs}: train loss {np.mean(losses):.4f}, held-out loss {vl[0]:.4f}")
    return _from_flax(fparams, mu, sd), curves


def _figures(pred, t) -> dict:
    counts = outcome_counts(row_outcomes(pred, t))
    stripe = np.isfinite(t)
    hit = stripe & hits(pred, t)
    return {**counts, **detection_figures(counts), "hit_rate": float(hit.sum() / max(stripe.sum(), 1)),
            "mae_hits_px": float(np.mean(np.abs(pred - t)[hit])) if hit.any() else float("nan")}


def frame_candidates(frames, net: dict) -> list:
    """(candidates, truth) of each (image, background, truth) frame (:func:`trackers.learned.candidates`)."""
    from trackers.learned import candidates

    return [(candidates(img, off, net), np.asarray(truth, np.float64)) for img, off, truth in frames]


def evaluate_candidates(cands, thresholds, *, jump_cost: float = 0.0, switch_cost: float = 0.0) -> dict:
    """Row outcomes of :func:`frame_candidates`' output with the tracker's decision
    (:func:`trackers.learned.choose`) at each threshold and the given chain costs: per threshold the counts
    and F1, precision, recall, hit rate (hits / stripe rows) and the mean |error| of the hits (px)."""
    from trackers.learned import choose

    t = np.concatenate([truth for _, truth in cands]) if cands else np.zeros(0)
    out = {}
    for thr in thresholds:
        preds = []
        for (logit, col, base), _ in cands:
            c, _, ok = choose(logit, col, base, float(thr), jump_cost, switch_cost)
            preds.append(np.where(ok, c, np.nan))
        out[float(thr)] = _figures(np.concatenate(preds) if preds else np.zeros(0), t)
    return out


def evaluate_frames(frames, net: dict, thresholds, *, jump_cost: float = 0.0, switch_cost: float = 0.0) -> dict:
    """:func:`evaluate_candidates` of (image, background, truth) frames under the network ``net``."""
    return evaluate_candidates(frame_candidates(frames, net), thresholds, jump_cost=jump_cost,
                               switch_cost=switch_cost)


def choose_operating_point(cands, hp: "HyperParams") -> tuple[dict, dict]:
    """The operating point of best F1 over the held-out rows (a miss and a false report priced alike),
    searched jointly over ``hp.thresholds``, ``hp.jump_costs`` and ``hp.switch_costs`` (ties: the lowest
    jump cost, then switch cost, then threshold). Returns (``{"threshold", "jump_cost", "switch_cost"}``,
    ``{(jump_cost, switch_cost): evaluate_frames table}``)."""
    tables = {}
    for jc in hp.jump_costs:
        for sc in hp.switch_costs:
            tables[(float(jc), float(sc))] = evaluate_candidates(cands, hp.thresholds, jump_cost=float(jc),
                                                                 switch_cost=float(sc))
    best = max(((jc, sc, thr) for (jc, sc), tab in tables.items() for thr in tab),
               key=lambda k: (np.nan_to_num(tables[k[:2]][k[2]]["f1"], nan=-1.0), -k[0], -k[1], -k[2]))
    return {"jump_cost": best[0], "switch_cost": best[1], "threshold": best[2]}, tables


def choose_threshold(table: dict) -> float:
    """The threshold of the best F1 (ties: the lowest threshold)."""
    best = max(table.items(), key=lambda kv: (np.nan_to_num(kv[1]["f1"], nan=-1.0), -kv[0]))
    return float(best[0])


def save_weights(path, net: dict, threshold: float, k: int, provenance: dict, *, jump_cost: float = 0.0,
                 switch_cost: float = 0.0) -> Path:
    """Write a weights file the ``learned`` tracker reads."""
    from trackers.learned import FORMAT_VERSION, PARAM_KEYS, feature_layout

    import io

    buf = io.BytesIO()
    np.savez_compressed(buf, format_version=np.int64(FORMAT_VERSION), threshold=np.float64(threshold),
                        jump_cost=np.float64(jump_cost), switch_cost=np.float64(switch_cost),
                        k=np.int64(k), layout=np.str_(json.dumps(feature_layout())),
                        provenance=np.str_(json.dumps(provenance, default=float)),
                        **{key: np.asarray(net[key], np.float32) for key in PARAM_KEYS})
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(path, buf.getvalue())
    return path


def plot_curves(curves: dict, table: dict, threshold: float, path) -> Path:
    """The training curves and the held-out F1 against the threshold, one PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(9, 3.4))
    ax[0].plot(curves["epoch"], curves["train_loss"], label="training loss")
    ax[0].plot(curves["epoch"], curves["val_loss"], label="held-out loss")
    ax[0].set_xlabel("epoch")
    ax[0].set_ylabel("BCE + offset Huber")
    ax[0].legend()
    thr = sorted(table)
    ax[1].plot(thr, [table[t]["f1"] for t in thr], label="F1 over rows")
    ax[1].plot(thr, [table[t]["hit_rate"] for t in thr], label="hit rate")
    ax[1].plot(thr, [table[t]["false_report_rate"] for t in thr], label="false-report rate")
    ax[1].axvline(threshold, color="k", lw=0.8, ls="--")
    ax[1].set_xlabel("probability threshold")
    ax[1].set_title("held-out renders")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _load_frames(root, rows, views=("auto",), shrink=(), seed: int = 0):
    """The (image, background, truth) of every row in every view (a mono frame once: its views are equal),
    and with ``shrink`` each of those once more, shrunk by a factor drawn from ``shrink`` (seeded by ``seed``
    and the frame's position: :func:`bench.run.trainset.tracker_view`'s ``downscale``)."""
    from bench.run.trainset import tracker_view

    out = []
    for i, r in enumerate(rows):
        for j, v in enumerate(views):
            if v != views[0] and r["camera"] != "rgb":
                continue
            out.append(tracker_view(root, r, v))
            if shrink:
                n = int(np.random.default_rng([int(seed), 5, i, j]).choice(np.asarray(shrink, np.int64)))
                out.append(tracker_view(root, r, v, downscale=n))
    return out


def train_from_trainset(trainset, out, *, hp: HyperParams = HyperParams(), holdout: float = 0.2,
                        holdout_seed: int = 0, say=lambda m: None) -> dict:
    """The whole procedure on a finished training set: the weights file ``out`` and its curves figure
    (``out`` with ``.png``); returns the provenance it records."""
    from bench.run.trainset import holdout_of, read_trainset

    t0 = time.perf_counter()
    doc, rows = read_trainset(trainset)
    val_rows = [r for r in rows if holdout_of(int(r["unit"]), holdout_seed, holdout)]
    tr_rows = [r for r in rows if not holdout_of(int(r["unit"]), holdout_seed, holdout)]
    if not val_rows or not tr_rows:
        raise InputError(f"the held-out split of {str(trainset)!r} left no training or no held-out frames "
                         f"({len(rows)} frames of {len({r['unit'] for r in rows})} units, holdout {holdout}): use more "
                         "units or another --holdout")
    say(f"stripebench train: {len(tr_rows)} training and {len(val_rows)} held-out frames")
    shrink = tuple(int(n) for n in hp.shrink)
    train = samples_from_frames(_load_frames(trainset, tr_rows, hp.views, shrink, hp.seed), hp.k, augment=hp.augment,
                                seed=hp.seed)  # the frames themselves are not kept: memory
    val_frames = _load_frames(trainset, val_rows, hp.views, shrink, hp.seed)
    val = samples_from_frames(val_frames, hp.k)
    t1 = time.perf_counter()
    say(f"  {len(train[0])} training candidates ({int(train[1].sum())} stripes), features in {t1 - t0:.1f} s")
    net, curves = train_network(train, val, hp, say=say)
    t2 = time.perf_counter()
    net_k = {**net, "k": hp.k}
    point, heldout, table = _operating_point(trainset, val_rows, val_frames, net_k, hp, say)
    prov = {"what": "stripebench learned tracker weights", "trained_on": "renders only (stripebench trainset)",
            "trainset": {"path": str(trainset), **{k: doc[k] for k in ("seed", "n_units", "angles_per_unit",
                                                                          "noise_draws", "width", "height", "frames",
                                                                          "seed_base", "code_revision")},
                         "draws": doc.get("draws", 1), "draw_rules": doc.get("draw_rules")},
            "split": {"rule": "held-out units: bench.run.trainset.holdout_of(unit, holdout_seed, holdout); with "
                              "hyper_parameters.shrink, each frame's shrunk copy goes with it",
                      "holdout": holdout, "holdout_seed": holdout_seed, "train_frames": len(tr_rows),
                      "heldout_frames": len(val_rows), "train_candidates": int(len(train[0])),
                      "heldout_candidates": int(len(val[0]))},
            "architecture": {"input": "trackers._learned_kernels features", "hidden": list(hp.hidden),
                             "activation": "relu", "output": ["stripe logit", "offset px from the 3-point fit"]},
            "hyper_parameters": asdict(hp), "threshold": point["threshold"], "operating_point": point,
            "heldout": heldout,
            "curves": curves, "train_s": round(t2 - t1, 1), "total_s": round(time.perf_counter() - t0, 1),
            "versions": {**versions(), **_learn_versions()}, "git_revision": git_revision(),
            "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    save_weights(out, net, point["threshold"], hp.k, prov, jump_cost=point["jump_cost"],
                 switch_cost=point["switch_cost"])
    plot_curves(curves, table, point["threshold"], Path(out).with_suffix(".png"))
    return prov


def _operating_point(trainset, val_rows, val_frames, net_k, hp, say):
    """The operating point on the held-out rows, with and without the laser-off frame
    (:func:`choose_operating_point`), and the held-out figures a weights file records."""
    both = [(i, o, t) for i, o, t in val_frames] + [(i, None, t) for i, o, t in val_frames]
    cands = frame_candidates(both, net_k)
    point, tables = choose_operating_point(cands, hp)
    thr, jc, sc = point["threshold"], point["jump_cost"], point["switch_cost"]
    n = len(val_frames)
    with_bg = evaluate_candidates(cands[:n], [thr], jump_cost=jc, switch_cost=sc)[thr]
    no_bg = evaluate_candidates(cands[n:], [thr], jump_cost=jc, switch_cost=sc)[thr]
    auto = _load_frames(trainset, val_rows) if tuple(hp.views) != ("auto",) or hp.shrink else val_frames
    auto_both = evaluate_frames(auto + [(i, None, t) for i, o, t in auto], net_k, [thr], jump_cost=jc,
                                switch_cost=sc)[thr]
    alone = tables[(0.0, 0.0)]
    best = tables[(jc, sc)][thr]
    say(f"  held-out rows at threshold {thr}, jump cost {jc}, switch cost {sc}: F1 {best['f1']:.3f}, hit rate "
        f"{best['hit_rate']:.3f} (with laser-off frame F1 {with_bg['f1']:.3f}, without {no_bg['f1']:.3f}; rows "
        f"alone at their best threshold {choose_threshold(alone)}: F1 {alone[choose_threshold(alone)]['f1']:.3f})")
    heldout = {"both": best, "with_background": with_bg, "without_background": no_bg, "auto_view_both": auto_both,
               "by_threshold": {str(k): v for k, v in alone.items()},
               "by_costs": {f"{a},{b}": {"best_threshold": choose_threshold(t), "f1": t[choose_threshold(t)]["f1"]}
                            for (a, b), t in tables.items()}}
    return point, heldout, alone


def operating_point_from_weights(trainset, weights, out, *, hp: HyperParams = HyperParams(), holdout: float = 0.2,
                                 holdout_seed: int = 0, say=lambda m: None) -> dict:
    """A weights file's network with its operating point chosen again (:func:`choose_operating_point`) on
    the held-out split of ``trainset`` (the split :func:`train_from_trainset` used, with ``hp``'s views and
    shrink): written to ``out`` with the provenance extended; returns it. No training."""
    from bench.run.trainset import holdout_of, read_trainset
    from trackers.learned import PARAM_KEYS, load_weights

    t0 = time.perf_counter()
    w = load_weights(weights)
    _, rows = read_trainset(trainset)
    val_rows = [r for r in rows if holdout_of(int(r["unit"]), holdout_seed, holdout)]
    if not val_rows:
        raise InputError(f"the held-out split of {str(trainset)!r} left no held-out frames (holdout {holdout}): use "
                         "more units or another --holdout")
    net_k = {**{k: w[k] for k in PARAM_KEYS}, "k": w["k"]}
    val_frames = _load_frames(trainset, val_rows, hp.views, tuple(int(n) for n in hp.shrink), hp.seed)
    point, heldout, table = _operating_point(trainset, val_rows, val_frames, net_k, hp, say)
    prov = dict(w["provenance"])
    prov["operating_point_history"] = list(prov.get("operating_point_history", [])) + [
        {"threshold": prov.get("threshold"), "operating_point": prov.get("operating_point"),
         "heldout_both": prov.get("heldout", {}).get("both")}]
    prov.update({"threshold": point["threshold"], "operating_point": point, "heldout": heldout,
                 "operating_point_chosen": {"by": "bench.studies.train.operating_point_from_weights",
                                            "trainset": str(trainset), "holdout": holdout,
                                            "holdout_seed": holdout_seed, "jump_costs": list(hp.jump_costs),
                                            "switch_costs": list(hp.switch_costs),
                                            "thresholds": list(hp.thresholds), "git_revision": git_revision(),
                                            "s": round(time.perf_counter() - t0, 1),
                                            "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}})
    save_weights(out, net_k, point["threshold"], w["k"], prov, jump_cost=point["jump_cost"],
                 switch_cost=point["switch_cost"])
    if prov.get("curves"):
        plot_curves(prov["curves"], table, point["threshold"], Path(out).with_suffix(".png"))
    return prov


def _learn_versions() -> dict:
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for dist in ("jax", "jaxlib", "flax", "optax"):
        try:
            out[dist] = version(dist)
        except PackageNotFoundError:
            out[dist] = "absent"
    return out
