"""The ``learned`` tracker's compiled parts: candidate peaks, their feature vectors and the MLP forward pass.

Training (:mod:`bench.studies.train`) computes its features with the very same
:func:`features` as the tracker, so the network sees at inference exactly what
it saw in training. Everything here is symmetric under an upside-down flip of
the frame (a row's features use its own statistics and symmetric pairs of the
rows around it), so the conformance suite's flip check holds exactly.

Feature vector of one candidate (``N_FEATURES`` float32 values):

* for each channel (the frame minus its row median, then the laser-on minus laser-off
  difference minus its row median; zeros without a laser-off frame): the columns
  ``c - HALF_W .. c + HALF_W`` of the centre row, of the means of the row pairs
  ``r -/+ k`` and of their absolute differences (``k`` in :data:`ROW_OFFSETS`), divided by
  the candidate's contrast (at least 3 noise units) and clipped to [-4, 4];
* scalars (:data:`SCALARS`).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ._detect import _select

__all__ = ["K", "HALF_W", "ROW_OFFSETS", "N_FEATURES", "SCALARS", "DN_MAX", "MIN_SPAN_DN", "BORDER_RUN_PX", "in_dn", "frame_stats",
           "features", "mlp_forward", "decode"]

K = 6  #: candidates per row
HALF_W = 5  #: half-width of a candidate's patch, columns
ROW_OFFSETS = (1, 2, 4)  #: the symmetric row pairs of a patch
_NR = 1 + 2 * len(ROW_OFFSETS)  # rows of features per channel
_NP = _NR * (2 * HALF_W + 1)  # patch features per channel
SCALARS = ("log_snr", "contrast_ratio", "rank", "peak_level", "row_level", "has_background", "log_snr_difference",
           "subpixel_base", "log_half_width")
N_FEATURES = 2 * _NP + len(SCALARS)
_CLIP = 4.0
DN_MAX = 255.0  #: the network's pixel units: 8-bit digital numbers, 0 .. DN_MAX
#: a candidate at the first or last column must fall below half its contrast within this many px of the border:
#: the half of a stripe of up to about 8 px at half maximum (a wider bright band at the border, seen in one row,
#: is as likely a lit edge of the scene as a stripe, and the patch would not hold its fall)
BORDER_RUN_PX = 4
MIN_SPAN_DN = 1.0  #: a frame in [0, DN_MAX] spanning no more than this is not in 8-bit units (a [0, 1] float frame)


def frame_stats(signal: np.ndarray, int_range=None) -> tuple[np.ndarray, float]:
    """Row medians (H,) and the frame's noise (the median over rows of each row's median absolute
    difference of adjacent pixels / 0.954, the Gaussian sigma; at least 0.3, an 8-bit frame's
    quantisation); both from half of each row's pixels (:func:`_row_stats`).

    >>> med, noise = frame_stats(np.array([[1.0, 5.0, 3.0, 4.0], [2.0, 2.0, 2.0, 2.0]]))
    >>> med.tolist(), round(noise, 3)  # the median of the rows' 2.5 and 0, over 0.954
    ([2.0, 2.0], 1.31)
    """
    sig = np.ascontiguousarray(signal, dtype=np.float64)
    if int_range is not None:  # integer values in [lo, lo + n): the same medians by counting
        med, mad = _row_stats_int(sig, int(int_range[0]), int(int_range[1]))
    else:
        med, mad = _row_stats(sig)
    noise = float(np.median(mad)) / 0.954 if signal.shape[1] > 1 else 0.0
    return med, max(noise, 0.3)


@nb.njit(cache=True)
def _hist_median(cnt, n):
    """The median (numpy's: the mean of the two middle values for an even count) of ``n`` values counted in
    ``cnt`` (value ``i`` counted at ``cnt[i]``)."""
    lo_rank = (n - 1) // 2
    hi_rank = n // 2
    acc = 0
    lo_v = -1
    for i in range(cnt.shape[0]):
        acc += cnt[i]
        if lo_v < 0 and acc > lo_rank:
            lo_v = i
        if acc > hi_rank:
            return 0.5 * (lo_v + i)
    return float(lo_v)


@nb.njit(cache=True)
def _row_stats_int(sig, lo, n):
    """:func:`_row_stats` of an integer-valued frame with values in [lo, lo + n), by counting."""
    H, W = sig.shape
    med = np.empty(H)
    mad = np.zeros(H)
    cnt = np.zeros(n, np.int64)
    cnt2 = np.zeros(n, np.int64)
    ne = (W + 1) // 2
    n2 = W // 2
    for r in range(H):
        cnt[:] = 0
        for j in range(0, W, 2):
            cnt[int(sig[r, j]) - lo] += 1
        med[r] = _hist_median(cnt, ne) + lo
        if n2 > 0:
            cnt2[:] = 0
            for j in range(n2):
                cnt2[int(abs(sig[r, 2 * j + 1] - sig[r, 2 * j]))] += 1
            mad[r] = _hist_median(cnt2, n2)
    return med, mad


@nb.njit(cache=True)
def _row_stats(sig):
    """Each row's median (of its even columns) and median absolute difference of the pixel pairs
    (2j, 2j + 1): half the pixels, for speed."""
    H, W = sig.shape
    med = np.empty(H)
    mad = np.zeros(H)
    n2 = W // 2
    ne = (W + 1) // 2
    buf = np.empty(max(ne, 1))
    for r in range(H):
        for j in range(ne):
            buf[j] = sig[r, 2 * j]
        med[r] = _median(buf, ne)
        if n2 > 0:
            for j in range(n2):
                buf[j] = abs(sig[r, 2 * j + 1] - sig[r, 2 * j])
            mad[r] = _median(buf, n2)
    return med, mad


@nb.njit(cache=True)
def _median(a, n):
    """numpy's median of ``a[:n]`` (reordered in place): the upper middle value by :func:`trackers._detect._select`
    (which leaves the smaller values before it), and for an even count the mean with the largest value below it."""
    k = n // 2
    _select(a, n, k)
    v = a[k]
    if n % 2 == 1:
        return v
    m = a[0]
    for i in range(1, k):
        if a[i] > m:
            m = a[i]
    return 0.5 * (m + v)


@nb.njit(cache=True)
def _smooth_row(x, out):
    """``out[j] = (x[j-1] + 2 x[j] + x[j+1]) / 4``, the row's ends repeated past them."""
    W = x.shape[0]
    for j in range(W):
        a = x[j - 1] if j > 0 else x[j]
        b = x[j + 1] if j < W - 1 else x[j]
        out[j] = 0.25 * a + 0.5 * x[j] + 0.25 * b


@nb.njit(cache=True)
def _candidates(sig, med, K):
    """Per row the K strongest local maxima of the [1, 2, 1]-smoothed signal (contrast over the row median),
    strongest first: column (the middle of a plateau, floored), contrast, plateau half-length. -1 where none.
    Only columns 1 .. W - 2 (the first and last columns: :func:`_border_candidates`)."""
    H, W = sig.shape
    cols = np.full((H, K), -1, np.int64)
    con = np.zeros((H, K))
    plat = np.zeros((H, K))
    sm = np.empty(W)
    for r in range(H):
        _smooth_row(sig[r], sm)
        j = 1
        while j < W - 1:
            if sm[j] > sm[j - 1]:
                k = j
                while k + 1 < W and sm[k + 1] == sm[j]:
                    k += 1
                if k + 1 < W and sm[k + 1] < sm[j]:
                    c = sm[j] - med[r]
                    mid = (j + k) // 2
                    # insert into the sorted top-K (strongest first; ties: leftmost first)
                    pos = K
                    for q in range(K):
                        if cols[r, q] < 0 or c > con[r, q]:
                            pos = q
                            break
                    if pos < K:
                        for q in range(K - 1, pos, -1):
                            cols[r, q] = cols[r, q - 1]
                            con[r, q] = con[r, q - 1]
                            plat[r, q] = plat[r, q - 1]
                        cols[r, pos] = mid
                        con[r, pos] = c
                        plat[r, pos] = 0.5 * (k - j)
                j = k + 1
            else:
                j += 1
    return cols, con, plat


@nb.njit(cache=True)
def _border_candidates(sig, med, max_run):
    """Per row a candidate at the first column (slot 0) and at the last (slot 1), or -1: a maximum of the
    [1, 2, 1]-smoothed signal that lies on the border (above the one neighbour, or a plateau from the border
    that then falls), above the row median, whose raw signal falls below half its contrast within
    ``max_run`` px of the border. Seen mirrored about the border pixel it is a peak centred there: column
    (the border's), contrast, plateau half-length (mirrored: the plateau's whole length from the border)."""
    H, W = sig.shape
    cols = np.full((H, 2), -1, np.int64)
    con = np.zeros((H, 2))
    plat = np.zeros((H, 2))
    if W < 3:
        return cols, con, plat
    sm = np.empty(W)
    for r in range(H):
        _smooth_row(sig[r], sm)
        for side in range(2):
            e = 0 if side == 0 else W - 1
            step = 1 if side == 0 else -1
            k = 0  # the plateau's length beyond the border pixel
            while k + 1 < W - 1 and sm[e + step * (k + 1)] == sm[e]:
                k += 1
            nxt = e + step * (k + 1)
            c = sm[e] - med[r]
            if not (sm[nxt] < sm[e] and c > 0):
                continue
            half = med[r] + 0.5 * c
            run = 0
            while run < W and sig[r, e + step * run] > half:
                run += 1
            if run > max_run:
                continue
            cols[r, side] = e
            con[r, side] = c
            plat[r, side] = float(k)
    return cols, con, plat


@nb.njit(cache=True)
def _features(img, imed, dif, dmed, has_bg, sig, smed, noise_img, noise_dif, noise_sig, cols, con, plat,
              offsets, half_w, n_inner, out, base):
    """Feature vectors of the candidates ``cols`` (H, n_inner + border slots): the first ``n_inner`` per row
    are the inner ones (ranked by contrast), the rest at the first or last column, seen mirrored about it."""
    H, W = img.shape
    Kc = n_inner
    nw = 2 * half_w + 1
    nr = 1 + 2 * offsets.shape[0]
    npatch = nr * nw
    for r in range(H):
        cmax = con[r, 0] if cols[r, 0] >= 0 else 0.0
        for q in range(cols.shape[1]):
            c = cols[r, q]
            edge = q >= Kc  # a border candidate: columns beyond the border mirror those inside
            f = out[r, q]
            if c < 0:
                for i in range(f.shape[0]):
                    f[i] = 0.0
                base[r, q] = np.nan
                continue
            den = max(con[r, q], 3.0 * noise_sig)
            # the sub-pixel base: a Gaussian 3-point fit on the signal above its row median (a plateau: its middle)
            if plat[r, q] > 0:
                b0 = c + (plat[r, q] - np.floor(plat[r, q]))
            else:
                # at the first or last column the missing neighbour mirrors the other: the fit stays on that pixel
                lo = sig[r, c - 1] - smed[r] if c > 0 else (sig[r, c + 1] - smed[r] if W > 1 else 0.0)
                mi = sig[r, c] - smed[r]
                hi = sig[r, c + 1] - smed[r] if c < W - 1 else (sig[r, c - 1] - smed[r] if W > 1 else 0.0)
                b0 = float(c)
                if lo > 0 and mi > 0 and hi > 0:
                    dd = np.log(lo) - 2.0 * np.log(mi) + np.log(hi)
                    if dd < 0:
                        b0 = c + 0.5 * (np.log(lo) - np.log(hi)) / dd
                else:
                    dd = lo - 2.0 * mi + hi
                    if dd < 0:
                        b0 = c + 0.5 * (lo - hi) / dd
                b0 = min(max(b0, c - 1.0), c + 1.0)
            base[r, q] = b0
            for ch in range(2):
                if ch == 1 and not has_bg:
                    for i in range(npatch, 2 * npatch):
                        f[i] = 0.0
                    continue
                for jj in range(nw):
                    j = c - half_w + jj
                    if edge:
                        j = abs(j) if j < 0 else (2 * (W - 1) - j if j > W - 1 else j)
                    j = min(max(j, 0), W - 1)
                    if ch == 0:
                        v0 = img[r, j] - imed[r]
                    else:
                        v0 = dif[r, j] - dmed[r]
                    idx = ch * npatch + jj
                    f[idx] = min(max(v0 / den, -4.0), 4.0)
                    for t in range(offsets.shape[0]):
                        k = offsets[t]
                        ra = max(r - k, 0)
                        rb = min(r + k, H - 1)
                        if ch == 0:
                            va = img[ra, j] - imed[r]
                            vb = img[rb, j] - imed[r]
                        else:
                            va = dif[ra, j] - dmed[r]
                            vb = dif[rb, j] - dmed[r]
                        m = 0.5 * (va + vb)
                        a = abs(va - vb)
                        f[ch * npatch + (1 + t) * nw + jj] = min(max(m / den, -4.0), 4.0)
                        f[ch * npatch + (1 + offsets.shape[0] + t) * nw + jj] = min(max(a / den, -4.0), 4.0)
            s = 2 * npatch
            ci = img[r, c] - imed[r]
            f[s + 0] = np.log1p(max(ci, 0.0) / noise_img)
            if edge:  # ranked among the inner candidates as its contrast would be
                rank = 0
                for i in range(Kc):
                    if cols[r, i] >= 0 and con[r, i] >= con[r, q]:
                        rank += 1
                top = max(cmax, con[r, q])
                f[s + 1] = con[r, q] / top if top > 0 else 0.0
                f[s + 2] = min(rank, Kc - 1) / Kc
            else:
                f[s + 1] = con[r, q] / cmax if cmax > 0 else 0.0
                f[s + 2] = q / Kc
            f[s + 3] = min(max(img[r, c] / 255.0, -2.0), 2.0)
            f[s + 4] = min(max(imed[r] / 255.0, -2.0), 2.0)
            f[s + 5] = 1.0 if has_bg else 0.0
            f[s + 6] = np.log1p(max(dif[r, c] - dmed[r], 0.0) / noise_dif) if has_bg else 0.0
            f[s + 7] = b0 - c
            # half-width of the run above half the candidate's contrast in the signal
            half = smed[r] + 0.5 * con[r, q]
            lft = c
            while lft > 0 and sig[r, lft - 1] > half:
                lft -= 1
            rgt = c
            while rgt < W - 1 and sig[r, rgt + 1] > half:
                rgt += 1
            width = rgt - lft + 1
            if edge:  # the run from the border, mirrored about the border pixel
                width = 2 * width - 1
            f[s + 8] = np.log1p(0.5 * width)


def _is_8bit(a) -> bool:
    a = np.asarray(a)
    if a.dtype == np.uint8:
        return True
    return bool(a.size and a.min() >= 0 and a.max() <= 255 and np.array_equal(a, np.floor(a)))


def in_dn(image: np.ndarray, background: np.ndarray | None = None):
    """A frame (and its laser-off frame) in the network's units, 8-bit DN: (image, background) as float64.

    A pair of 8-bit values (whole numbers in [0, :data:`DN_MAX`]: uint8 frames and copies of them) is
    returned as it is, and so is a pair of other values in [0, DN_MAX] that spans more than
    :data:`MIN_SPAN_DN` (the colour views of an 8-bit photograph, what every training frame is). Any
    other pair (a 16-bit or 12-bit frame, a float frame in [0, 1], negative values, a frame times
    1e300 or 1e-300) is mapped by one affine map onto [0, DN_MAX], its smallest value to 0 and its largest
    to DN_MAX (a constant pair to 0): the trackers of the threshold family judge each row by its own
    statistics, so the scale and offset of the pixel values do not matter to them, and this makes them not
    matter to the network either.

    >>> img = np.array([[0.0, 0.5, 1.0]])
    >>> in_dn(img)[0].tolist(), in_dn(img * 255)[0].tolist(), in_dn(img * 65535 - 300)[0].tolist()
    ([[0.0, 127.5, 255.0]], [[0.0, 127.5, 255.0]], [[0.0, 127.5, 255.0]])
    """
    return _in_dn(image, background)[:2]


def _in_dn(image, background):
    """:func:`in_dn`, and whether the pair holds 8-bit values (whole numbers in [0, DN_MAX])."""
    whole = _is_8bit(image) and (background is None or _is_8bit(background))
    img = np.asarray(image, dtype=np.float64)
    bg = None if background is None else np.asarray(background, dtype=np.float64)
    pair = (img,) if bg is None else (img, bg)
    lo = min(float(a.min()) for a in pair)
    hi = max(float(a.max()) for a in pair)
    if whole or (0.0 <= lo and hi <= DN_MAX and hi - lo > MIN_SPAN_DN):
        return img, bg, whole
    if not hi > lo:
        return np.zeros_like(img), None if bg is None else np.zeros_like(bg), False
    with np.errstate(over="ignore"):
        span = hi - lo
    if np.isfinite(span):
        scale = DN_MAX / span
        return (*(None if a is None else np.clip((a - lo) * scale, 0.0, DN_MAX) for a in (img, bg)), False)
    scale = DN_MAX / (0.5 * hi - 0.5 * lo)  # a span beyond the float range: halves
    return (*(None if a is None else np.clip((0.5 * a - 0.5 * lo) * scale, 0.0, DN_MAX) for a in (img, bg)), False)


def features(image: np.ndarray, background: np.ndarray | None = None, k: int = K):
    """Every candidate's feature vector.

    Parameters
    ----------
    image : ndarray (H, W)
        Any real pixel values: first put in the network's units (:func:`in_dn`).
    background : ndarray (H, W) or None
        The laser-off frame; candidates are then found on the difference.
    k : int
        Candidates per row.

    Returns
    -------
    feats : ndarray float32 (H, k + 2, N_FEATURES)
    cols : ndarray int64 (H, k + 2)
        Candidate columns (-1: no candidate): the ``k`` strongest inner maxima, then a candidate at the
        first column and one at the last (:data:`BORDER_RUN_PX`), whose patches mirror the frame about
        the border pixel (a stripe cut in half by the border, seen whole).
    base : ndarray float64 (H, k + 2)
        The sub-pixel base column of each candidate (NaN: none).
    """
    # 8-bit frames (or float copies of them): row medians by counting, the very numbers np.median gives
    img, background, whole = _in_dn(image, background)
    img = np.ascontiguousarray(img)
    has_bg = background is not None
    if has_bg:
        dif = img - background
        sig = dif
    else:
        dif = np.zeros((1, 1))
        sig = img
    imed, noise_img = frame_stats(img, (0, 256) if whole else None)
    if has_bg:
        dmed, noise_dif = frame_stats(dif, (-255, 511) if whole else None)
    else:
        dmed, noise_dif = np.zeros(img.shape[0]), 1.0
    smed, noise_sig = (dmed, noise_dif) if has_bg else (imed, noise_img)
    cols, con, plat = _candidates(sig, smed, k)
    bcols, bcon, bplat = _border_candidates(sig, smed, BORDER_RUN_PX)
    cols, con, plat = np.hstack([cols, bcols]), np.hstack([con, bcon]), np.hstack([plat, bplat])
    H = img.shape[0]
    out = np.empty((H, k + 2, N_FEATURES), np.float32)
    base = np.empty((H, k + 2))
    _features(img, imed, dif, dmed, has_bg, sig, smed, noise_img, noise_dif,
              noise_sig, cols, con, plat, np.asarray(ROW_OFFSETS, np.int64), HALF_W, k, out, base)
    return out, cols, base


def mirror() -> tuple[np.ndarray, np.ndarray]:
    """The left-right mirror of a feature vector about its candidate's column: ``x[perm] * sign``
    (patch columns reversed, the 3-point fit's offset negated)."""
    nw = 2 * HALF_W + 1
    perm = np.arange(N_FEATURES)
    for g in range(2 * _NR):
        perm[g * nw:(g + 1) * nw] = perm[g * nw:(g + 1) * nw][::-1]
    sign = np.ones(N_FEATURES, np.float32)
    sign[2 * _NP + SCALARS.index("subpixel_base")] = -1.0
    return perm.astype(np.int64), sign


_PERM, _SIGN = mirror()


def mlp_forward(x: np.ndarray, params: dict, *, has_background: bool = True) -> np.ndarray:
    """The network on feature rows ``x`` (N, N_FEATURES): (N, 2) float32, the stripe logit and the sub-pixel
    offset from the candidate's base. ``params``: ``mu``, ``sd`` (the input standardisation), ``w1, b1, w2, b2,
    w3, b3`` (two ReLU hidden layers, a linear output, made mirror-symmetric: :func:`_mlp`), all float32.

    ``has_background=False`` promises that the difference channel is all zeros (features of a frame
    without its laser-off frame): its constant share of the first layer is then folded into the bias
    and those inputs skipped (the same numbers to rounding, half the first layer's work)."""
    x = np.ascontiguousarray(x, dtype=np.float32)
    p = {k: np.ascontiguousarray(params[k], dtype=np.float32) for k in ("mu", "sd", "w1", "b1", "w2", "b2", "w3", "b3")}
    mu, sd, w1, b1 = p["mu"], p["sd"], p["w1"], p["b1"]
    if not has_background:
        ch2 = np.zeros(N_FEATURES, bool)
        ch2[_NP:2 * _NP] = True
        b1 = (b1 + ((0.0 - mu[ch2]) / sd[ch2]) @ w1[ch2]).astype(np.float32)
        keep = np.flatnonzero(~ch2)
        # the mirror maps the difference channel onto itself, so the kept inputs map among themselves
        pos = np.full(N_FEATURES, -1, np.int64)
        pos[keep] = np.arange(keep.size)
        perm, sign = pos[_PERM[keep]], _SIGN[keep]
        x, mu, sd, w1 = (np.ascontiguousarray(a) for a in (x[:, keep], mu[keep], sd[keep], w1[keep]))
    else:
        perm, sign = _PERM, _SIGN
    return _mlp(x, mu, sd, w1, b1, p["w2"], p["b2"], p["w3"], p["b3"], perm, sign)


@nb.njit(cache=True)
def _mlp(x, mu, sd, w1, b1, w2, b2, w3, b3, perm, sign):
    """The network, made mirror-symmetric: with ``g`` the plain MLP, logit = the mean of g(x) and
    g(mirror x), offset = half their difference. Candidates in blocks, the block innermost (it
    vectorises); every candidate's sums run in one order, wherever it sits in a block."""
    n, f = x.shape
    h1n = w1.shape[1]
    h2n = w2.shape[1]
    B = 64
    z = np.empty((f, B), np.float32)
    h1 = np.empty((h1n, B), np.float32)
    h2 = np.empty((h2n, B), np.float32)
    g = np.empty((2, 2, B), np.float32)
    out = np.empty((n, 2), np.float32)
    for s0 in range(0, n, B):
        m = min(B, n - s0)
        for side in range(2):
            for a in range(f):
                src = a if side == 0 else perm[a]
                sg = np.float32(1.0) if side == 0 else sign[a]
                for i in range(m):
                    z[a, i] = (x[s0 + i, src] * sg - mu[a]) / sd[a]
            for b in range(h1n):
                for i in range(m):
                    h1[b, i] = b1[b]
            for a in range(f):
                for b in range(h1n):
                    wab = w1[a, b]
                    for i in range(m):
                        h1[b, i] += z[a, i] * wab
            for b in range(h2n):
                for i in range(m):
                    h2[b, i] = b2[b]
            for a in range(h1n):
                for i in range(m):
                    h1[a, i] = max(h1[a, i], np.float32(0.0))
                for b in range(h2n):
                    wab = w2[a, b]
                    for i in range(m):
                        h2[b, i] += h1[a, i] * wab
            for o in range(2):
                for i in range(m):
                    g[side, o, i] = b3[o]
            for a in range(h2n):
                for i in range(m):
                    v = max(h2[a, i], np.float32(0.0))
                    g[side, 0, i] += v * w3[a, 0]
                    g[side, 1, i] += v * w3[a, 1]
        for i in range(m):
            out[s0 + i, 0] = np.float32(0.5) * (g[0, 0, i] + g[1, 0, i])
            out[s0 + i, 1] = np.float32(0.5) * (g[0, 1, i] - g[1, 1, i])
    return out


def decode(logit: np.ndarray, cols: np.ndarray, none_logit: float, jump_cost: float = 0.0,
           switch_cost: float = 0.0, jump_cap_px: float = 8.0) -> np.ndarray:
    """Each row's chosen candidate, or -1 for none: the best chain of states down the frame.

    A row's states are its candidates (node score: the stripe logit; ``-inf`` where none) and *none*
    (``none_logit``, the logit of the probability threshold). A chain scores the sum of its nodes minus
    ``jump_cost`` per px of column change between consecutive candidates (at most ``jump_cap_px`` px
    counted: an occlusion's jump costs no more than that) and ``switch_cost`` per change between
    a candidate and none. It is found exactly by dynamic programming over rows (Viterbi: a chain's best
    score up to row ``r`` in state ``s`` depends only on row ``r - 1``'s best scores, so keeping one
    per state is optimal). With both costs 0 the rows are independent and each row takes its best
    candidate when its logit is at least ``none_logit``: the plain threshold rule.

    Parameters
    ----------
    logit : ndarray (H, K)
        Candidates' stripe logits, ``-inf`` where a row has fewer than K.
    cols : ndarray (H, K)
        Candidates' columns (px).
    none_logit : float
        The node score of *none*.
    jump_cost, switch_cost, jump_cap_px : float
        Transition costs (logit units per px; logit units; px), >= 0.

    Returns
    -------
    ndarray (H,), int64
        The chosen candidate's index per row; -1: none.

    Examples
    --------
    >>> lg = np.array([[3.0, -1.0], [-0.5, 0.2], [3.0, -2.0]])   # row 1 is unsure, its weak twin is off-line
    >>> cl = np.array([[10.0, 40.0], [10.0, 40.0], [10.0, 40.0]])
    >>> decode(lg, cl, 0.0).tolist(), decode(lg, cl, 0.0, jump_cost=0.2, switch_cost=1.0).tolist()
    ([0, 1, 0], [0, 0, 0])
    """
    lg = np.ascontiguousarray(logit, dtype=np.float64)
    cl = np.ascontiguousarray(cols, dtype=np.float64)
    if lg.ndim != 2 or cl.shape != lg.shape:
        raise ValueError(f"`logit` and `cols` must be 2-D of one shape, got {lg.shape} and {cl.shape}")
    return _decode(lg, cl, float(none_logit), float(jump_cost), float(switch_cost), float(jump_cap_px))


@nb.njit(cache=True)
def _decode(lg, cl, none_logit, jump_cost, switch_cost, cap):
    """:func:`decode`'s chain (state K is none); ties go to the lowest state index, candidates before none."""
    H, K = lg.shape
    S = K + 1
    out = np.full(H, -1, np.int64)
    if H == 0:
        return out
    acc = np.empty((H, S))
    back = np.zeros((H, S), np.int64)
    for j in range(K):
        acc[0, j] = lg[0, j]
    acc[0, K] = none_logit
    for r in range(1, H):
        for j in range(S):
            node = none_logit if j == K else lg[r, j]
            if node == -np.inf:
                acc[r, j] = -np.inf
                continue
            best = -np.inf
            arg = 0
            for i in range(S):
                prev = acc[r - 1, i]
                if prev == -np.inf:
                    continue
                if i < K and j < K:
                    t = jump_cost * min(abs(cl[r, j] - cl[r - 1, i]), cap)
                elif i == K and j == K:
                    t = 0.0
                else:
                    t = switch_cost
                v = prev - t
                if v > best:
                    best = v
                    arg = i
            acc[r, j] = best + node
            back[r, j] = arg
    s = 0
    for j in range(1, S):
        if acc[H - 1, j] > acc[H - 1, s]:
            s = j
    for r in range(H - 1, -1, -1):
        out[r] = -1 if s == K else s
        s = back[r, s]
    return out
