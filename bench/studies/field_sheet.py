"""The field profile's conditions at a glance, and what each costs to render.

``python -m bench.cli.field_sheet docs/field_conditions.png`` (:func:`sheet`) renders the middle mirror angle of every
experiment of ``bench/config/profiles/field.toml`` (its own size and settings) and writes a contact sheet
of the photographs as the colour camera developed them, titled with each ``condition``.
``--cost`` also renders two more frames per experiment with the render cache off and prints the
second one's wall and process CPU seconds (the first pays for loading the scene and the JIT).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

__all__ = ["frames", "render_cost", "contact_sheet", "sheet"]


def _scenes(config):
    import scenes

    for e in config.experiments:
        yield e, scenes.make(e.scene, material=e.material, **config.render, **e.overrides)


def frames(config):
    """``[(experiment, frame)]``: every experiment's frame at its middle default mirror angle."""
    out = []
    for e, s in _scenes(config):
        a = s.default_angles() if e.angles is None else np.asarray(e.angles)
        out.append((e, s.render(float(a[len(a) // 2]), seed=config.seed)))
    return out


def render_cost(config) -> list[tuple[str, float, float]]:
    """``[(experiment key, wall s, CPU s)]`` of one frame per experiment, render cache off, scene loaded.

    Two angles per experiment; the first (loading, JIT) is not counted. CPU is this process's
    time over all its threads.
    """
    import scenes

    rows = []
    for e in config.experiments:
        s = scenes.make(e.scene, material=e.material, **config.render, **{**e.overrides, "cache": False})
        a = s.default_angles()
        s.render(float(a[len(a) // 2]), seed=config.seed)
        t0, c0 = time.perf_counter(), time.process_time()
        s.render(float(a[1]), seed=config.seed)
        rows.append((e.key, time.perf_counter() - t0, time.process_time() - c0))
    return rows


def contact_sheet(items, path, columns: int = 4) -> Path:
    """Write the frames (colour photographs, or the mono image) in a grid with their conditions as titles."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(items)
    rows = (n + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(3.2 * columns, 3.2 * rows * 0.9 + 0.3), squeeze=False)
    for ax in axes.ravel():
        ax.axis("off")
    for ax, (e, f) in zip(axes.ravel(), items):
        img = f.rgb if f.rgb is not None else f.image
        ax.imshow(img, cmap=None if img.ndim == 3 else "gray", vmin=0, vmax=255, interpolation="antialiased")
        ax.set_title(f"{e.condition or e.key}\n{e.scene}/{e.material}, {img.shape[1]}x{img.shape[0]}", fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=64)
    plt.close(fig)
    return path


def sheet(out, *, cost: bool = False, config=None) -> int:
    """Write the contact sheet of the field profile's conditions to ``out`` (a ``.png``), and with ``cost``
    print each experiment's render cost per frame (``python -m bench.cli.field_sheet``).

    Parameters
    ----------
    out : path
        The PNG file to write.
    cost : bool
        Also render two more frames per experiment, render cache off, and print the second one's wall and
        CPU seconds (:func:`render_cost`).
    config : bench.config.Config, optional
        The configuration whose experiments are shown (default: the ``field`` profile).

    Returns
    -------
    int
        0, or 2 (one line on stderr) when ``out`` is not a ``.png`` file.
    """
    out = Path(out)
    if out.suffix.lower() != ".png":
        print(f"stripebench: `out` must be a .png file, got {str(out)!r}", file=sys.stderr)
        return 2
    if config is None:
        from bench.config import profile

        config = profile("field")
    contact_sheet(frames(config), out)
    print(f"wrote {out}")
    if cost:
        w, h = config.render.get("width", 512), config.render.get("height", 480)
        print(f"render cost per frame at {w}x{h} (cache off, scene loaded):")
        for key, wall, cpu in render_cost(config):
            print(f"  {key:28s} wall {wall:6.2f} s   CPU {cpu:6.2f} s")
    return 0
