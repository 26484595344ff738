import os
import subprocess
import sys

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
