import os
import subprocess
import sys

import numpy as np
import pytest

from scenes import variant as V


def test_candidates_order_and_mono():
    assert V.CANDIDATES == ("cuda_ad_mono", "llvm_ad_mono", "scalar_rgb")
    assert V.is_mono("llvm_ad_mono") and not V.is_mono("scalar_rgb")


def test_find_libllvm_returns_a_new_enough_library_or_none():
    path = V.find_libllvm()
    if path is not None:
        assert os.path.exists(path) and "LLVM" in os.path.basename(path)


def test_a_failing_probe_is_false_not_a_crash():
    assert V.probe("no_such_variant", timeout_s=120) is False


def test_environment_override_is_used_without_probing(monkeypatch, capsys):
    monkeypatch.setattr(V, "_chosen", None)
    monkeypatch.setenv(V.ENV_VARIANT, "scalar_rgb")
    monkeypatch.setattr(V, "probe", lambda v, timeout_s=0: pytest.fail("probed"))
    assert V.choose() == "scalar_rgb"
    assert "scalar_rgb" in capsys.readouterr().err


def test_importing_scenes_loads_no_renderer():
    code = ("import sys, scenes; scenes.make('cone', width=64, height=60); "
            "print(sorted(m for m in ('mitsuba', 'drjit') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    assert out.stdout.strip() == "[]"


def test_scalar_fallback_renders_the_same_scene(tmp_path):
    """The always-available scalar_rgb variant (forced by the environment) agrees with the default one."""
    code = ("import numpy as np, scenes; f = scenes.make('sphere', width=64, height=60, cache=False).render(0.0); "
            "np.save('out.npy', np.concatenate([f.laser_radiance.ravel(), f.truth.columns])); print(f.variant)")
    env = {**os.environ, V.ENV_VARIANT: "scalar_rgb",
           "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=tmp_path,
                         env=env)
    assert out.stdout.strip() == "scalar_rgb"
    scalar = np.load(tmp_path / "out.npy")
    import scenes

    f = scenes.make("sphere", width=64, height=60, cache=False).render(0.0)
    laser, cols = scalar[:-60].reshape(60, 64), scalar[-60:]
    assert np.abs(laser - f.laser_radiance).sum() < 0.05 * f.laser_radiance.sum()
    assert np.array_equal(np.isnan(cols), np.isnan(f.truth.columns))
    assert np.nanmax(np.abs(cols - f.truth.columns)) < 1e-3
