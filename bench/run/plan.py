"""What a configuration renders: each experiment's scene and mirror angles, and the progress notes of a run.

Shared by ``run`` (:mod:`bench.run.experiment`), ``export``, ``score`` and
sweeps, so that a frame set, a scored submission and a sweep render exactly
the frames a run renders.
"""

from __future__ import annotations

import sys

import numpy as np

__all__ = ["renderer_for", "scene_for", "angles_for", "say"]


def renderer_for(config) -> None:
    """Ask for ``config``'s LLVM target (``llvm_target``) before anything renders
    (:func:`scenes.variant.request_llvm_target`; ``$STRIPEBENCH_LLVM_TARGET`` overrides it).

    Raises
    ------
    bench.errors.ConfigError
        This process already renders for another target.
    """
    from bench.errors import ConfigError
    from scenes import variant

    try:
        variant.request_llvm_target(config.llvm_target)
    except ValueError as exc:
        raise ConfigError(str(exc)) from None


def scene_for(experiment, config):
    """The :class:`scenes.Scene` of one experiment of ``config`` (its render settings, seed and overrides)."""
    import scenes

    return scenes.make(experiment.scene, material=experiment.material, seed=config.seed, **config.render,
                       **experiment.overrides)


def angles_for(experiment, scene) -> np.ndarray:
    """The experiment's mirror angles (deg): its own ``angles``, else ``n_angles`` spread over the
    object, else the scene's defaults."""
    if experiment.angles is not None:
        return np.asarray(experiment.angles, float)
    if experiment.n_angles is not None:
        return scene.object.default_angles(scene.rig.zeta_deg, experiment.n_angles)
    return scene.default_angles()


def say(msg: str, quiet: bool) -> None:
    """A progress note on stderr unless ``quiet`` (stdout is for results)."""
    if not quiet:
        print(msg, file=sys.stderr, flush=True)
