"""bench.run.plan: what a configuration renders, and the renderer it asks for."""

import os

import numpy as np
import pytest

from bench.config import parse
from bench.run.plan import angles_for, renderer_for, scene_for

BASE = {"name": "p", "seed": 3, "trackers": ["dp4"], "baselines": [], "dp": [],
        "render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
        "experiments": [{"scene": "cone", "material": "patchy", "n_angles": 3},
                        {"scene": "plane", "angles": [-1.0, 0.5]}]}


def test_scene_and_angles_follow_the_configuration():
    cfg = parse(BASE)
    a, b = cfg.experiments
    sa, sb = scene_for(a, cfg), scene_for(b, cfg)
    assert sa.params["width"] == 64 and sa.params["seed"] == 3 and sa.params["material"] == "patchy"
    assert len(angles_for(a, sa)) == 3 and np.all(np.diff(angles_for(a, sa)) > 0)
    np.testing.assert_array_equal(angles_for(b, sb), [-1.0, 0.5])


def test_renderer_for_asks_for_the_configurations_target(monkeypatch):
    from scenes import variant

    monkeypatch.setenv(variant.ENV_LLVM_TARGET, "")  # recorded, so that the test's own changes are undone
    monkeypatch.delenv(variant.ENV_LLVM_TARGET)
    monkeypatch.setattr(variant, "_asked", None)
    monkeypatch.setattr(variant, "_target", None)
    renderer_for(parse(BASE))  # none set: nothing asked
    assert variant.ENV_LLVM_TARGET not in os.environ
    renderer_for(parse({**BASE, "llvm_target": "portable"}))
    assert os.environ[variant.ENV_LLVM_TARGET] == "portable"
    monkeypatch.setattr(variant, "_target", "native znver3/8")  # this process has rendered already
    from bench.errors import ConfigError

    with pytest.raises(ConfigError, match="already renders for"):
        renderer_for(parse({**BASE, "llvm_target": "haswell/8"}))
