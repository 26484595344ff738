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


# -- the LLVM target ----------------------------------------------------------------------

def test_llvm_target_syntax():
    assert V.parse_llvm_target(" portable ") == V.PORTABLE_TARGET
    assert V.parse_llvm_target("native") is None and V.parse_llvm_target("") is None  # unset: Dr.Jit's choice
    assert V.parse_llvm_target("znver3/8") == ("znver3", None, 8)
    assert V.parse_llvm_target("skylake-avx512/16/+avx512f,+avx2") == ("skylake-avx512", "+avx512f,+avx2", 16)
    for bad in ("haswell", "haswell/x", "/8", "haswell/0", "haswell/128", "haswell/-8"):
        with pytest.raises(ValueError, match=r"`STRIPEBENCH_LLVM_TARGET` must be .*got '" + bad):
            V.parse_llvm_target(bad)


def test_portable_target_needs_every_x86_64_v3_flag(tmp_path, monkeypatch):
    import platform

    monkeypatch.setattr(platform, "machine", lambda: "x86_64")
    flags = "fpu sse sse2 avx avx2 fma bmi1 bmi2 f16c movbe abm xsave avx512f"
    ok, old = tmp_path / "ok", tmp_path / "old"
    ok.write_text(f"processor\t: 0\nflags\t\t: {flags}\n")
    old.write_text(f"processor\t: 0\nflags\t\t: {flags.replace(' avx2', '')}\n")
    assert V.host_supports_portable(str(ok)) and not V.host_supports_portable(str(old))
    assert not V.host_supports_portable(str(tmp_path / "missing"))
    monkeypatch.setattr(platform, "machine", lambda: "aarch64")
    V.host_supports_portable.cache_clear()
    assert not V.host_supports_portable(str(ok))
    V.host_supports_portable.cache_clear()


def test_the_default_target_is_native_and_portable_is_set_only_on_a_capable_cpu(monkeypatch):
    monkeypatch.setenv(V.ENV_LLVM_TARGET, "")  # recorded, so that the test's own changes are undone
    monkeypatch.delenv(V.ENV_LLVM_TARGET)
    monkeypatch.setattr(V, "host_supports_portable", lambda cpuinfo="/proc/cpuinfo": True)
    assert V._requested() is None  # the default: this CPU's own code (fastest here)
    monkeypatch.setenv(V.ENV_LLVM_TARGET, "portable")  # what the regression gate renders with
    assert V._requested() == V.PORTABLE_TARGET
    monkeypatch.setattr(V, "host_supports_portable", lambda cpuinfo="/proc/cpuinfo": False)
    assert V._requested() is None  # a CPU that cannot run it renders natively; the renderer says so


def _render_in_child(tmp_path, target):
    code = ("import hashlib, numpy as np, scenes; from scenes import variant; "
            "f = scenes.make('cone', material='glazed', support='table', background='none', width=48, height=45, "
            "spp=2, ambient_spp=1, cache=False).render(-2.0); "
            "print(variant.renderer()); print(hashlib.sha256(f.laser_radiance.tobytes() + "
            "f.radiance.tobytes()).hexdigest())")
    env = {**os.environ, "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
           V.ENV_LLVM_TARGET: target, V.ENV_VARIANT: "llvm_ad_mono"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.split()[-3:]


@pytest.mark.slow
def test_renders_do_not_depend_on_the_cpu_the_target_names(tmp_path):
    """The portable target renders the same bits as an AVX2 CPU's own 8-lane code (another CPU
    name, its x86 intrinsics on): the vector width, not the CPU, sets the result."""
    if not V.host_supports_portable() or "llvm_ad_mono" not in __import__("mitsuba").variants():
        pytest.skip("needs an x86-64-v3 CPU and the LLVM variant")
    if not V.probe("llvm_ad_mono"):
        pytest.skip("no working LLVM here")
    portable = _render_in_child(tmp_path, "portable")
    avx2 = _render_in_child(tmp_path, "haswell/8/+avx,+avx2,+fma,+f16c,+bmi,+bmi2,+lzcnt,+movbe,+popcnt")
    assert portable[:2] == ["llvm_ad_mono", "x86-64-v3/8"] and avx2[1].startswith("haswell/8/")
    assert portable[2] == avx2[2]


def test_a_configuration_asks_for_its_target_and_the_environment_overrides_it(monkeypatch):
    monkeypatch.setenv(V.ENV_LLVM_TARGET, "")  # recorded, so that the test's own changes are undone
    monkeypatch.delenv(V.ENV_LLVM_TARGET)
    monkeypatch.setattr(V, "_asked", None)
    monkeypatch.setattr(V, "_target", None)
    V.request_llvm_target("")  # asks for nothing
    assert V.ENV_LLVM_TARGET not in os.environ
    V.request_llvm_target("portable")  # set before anything renders, so that helper processes inherit it
    assert os.environ[V.ENV_LLVM_TARGET] == "portable"
    V.request_llvm_target("native")  # a later configuration, still before any render, may change it
    assert os.environ[V.ENV_LLVM_TARGET] == "native"
    monkeypatch.setenv(V.ENV_LLVM_TARGET, "haswell/8")  # the user's own override wins
    V.request_llvm_target("portable")
    assert os.environ[V.ENV_LLVM_TARGET] == "haswell/8"
    with pytest.raises(ValueError, match="must be 'portable', 'native' or CPU/WIDTH"):
        V.request_llvm_target("haswell/6")


def test_a_process_that_already_rendered_refuses_another_target(monkeypatch):
    monkeypatch.setenv(V.ENV_LLVM_TARGET, "")  # recorded, so that the test's own changes are undone
    monkeypatch.delenv(V.ENV_LLVM_TARGET)
    monkeypatch.setattr(V, "_asked", None)
    monkeypatch.setattr(V, "_target", "native znver3/8")
    with pytest.raises(ValueError, match="already renders for 'native znver3/8'; run it in a fresh process"):
        V.request_llvm_target("haswell/8")
    V.request_llvm_target("native")  # the same target: nothing to do


def test_the_ci_profile_renders_for_the_portable_target():
    from bench.config import parse, profile

    cfg = profile("ci")
    assert cfg.llvm_target == "portable" and cfg.to_dict()["llvm_target"] == "portable"
    assert "llvm_target" not in profile("quick").to_dict()  # unset: older configurations keep their hash
    assert parse(cfg.to_dict(), "x").llvm_target == "portable"
