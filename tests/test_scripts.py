"""The scripts in ``scripts/`` use the installed packages' public names only (issue 36).

A script that needs a private kernel goes through its public entry point
(:mod:`trackers.dp_stages`); none puts the repository on ``sys.path`` (the project is installed,
editable), and each answers ``--help`` from outside the repository.
"""

import ast
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]
SCRIPTS = sorted((REPO / "scripts").glob("*.py"))
PACKAGES = ("trackers", "scenes", "bench")


def _private(dotted: str) -> bool:
    """Whether a dotted name has a private part (``_x``; dunders such as ``__file__`` are not)."""
    return any(p.startswith("_") and not (p.startswith("__") and p.endswith("__")) for p in dotted.split("."))


def private_uses(source: str) -> list[str]:
    """``line: name`` of every private name of the project's packages that ``source`` imports or reaches.

    Imports anywhere in the file (``import trackers._x``, ``from trackers import _x``,
    ``from trackers._x import y``, ``from trackers.dp import _y``) and attributes of an imported
    project module (``trackers.dp._y``, ``alias._y``).
    """
    tree = ast.parse(source)
    found = []
    modules = {}  # local name -> dotted project name it is bound to
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] in PACKAGES:
                    if _private(a.name):
                        found.append(f"{node.lineno}: {a.name}")
                    if a.asname:
                        modules[a.asname] = a.name
                    else:
                        modules[a.name.split(".")[0]] = a.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module.split(".")[0] in PACKAGES:
            for a in node.names:
                name = f"{node.module}.{a.name}"
                if _private(name):
                    found.append(f"{node.lineno}: {name}")
                modules[a.asname or a.name] = name
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            chain = []
            base = node
            while isinstance(base, ast.Attribute):
                chain.append(base.attr)
                base = base.value
            if isinstance(base, ast.Name) and base.id in modules and _private(chain[0]) and not _private(
                    ".".join(chain[1:])):  # report a chain once, at its first private part
                found.append(f"{node.lineno}: {modules[base.id]}.{'.'.join(reversed(chain))}")
    return sorted(set(found))


def test_there_are_scripts():
    assert {"dp_profile.py", "dp_kernel_identity.py", "tracker_digest.py"} <= {p.name for p in SCRIPTS}


@pytest.mark.parametrize("path", SCRIPTS, ids=[p.name for p in SCRIPTS])
def test_scripts_import_no_private_name(path):
    assert private_uses(path.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("path", SCRIPTS, ids=[p.name for p in SCRIPTS])
def test_scripts_do_not_edit_sys_path(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    edits = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr == "path"
             and isinstance(n.value, ast.Name) and n.value.id == "sys"]
    assert edits == [], f"{path.name} touches sys.path on lines {edits}: the project is installed"


@pytest.mark.parametrize("source, want", [
    ("from trackers import _dp_kernels as K\n", ["1: trackers._dp_kernels"]),
    ("import trackers._dp_rows\n", ["1: trackers._dp_rows"]),
    ("def f():\n    from trackers._dp_gap import sweep\n", ["2: trackers._dp_gap.sweep"]),
    ("from trackers.dp import _TIE_TOL, ROW_RULES\n", ["1: trackers.dp._TIE_TOL"]),
    ("import trackers.dp as D\nD._half_cost(1)\n", ["2: trackers.dp._half_cost"]),
    ("import trackers\ntrackers.dp._solve(1)\n", ["2: trackers.dp._solve"]),
    ("import bench.studies.perf.frames\nbench.studies._x.y\n", ["2: bench.studies._x"]),
    ("from bench.store import realset as real\nreal.load_frame(1)\nreal.__file__\n", []),
    ("from trackers import dp_stages as S\nS.half_costs(1)\n", []),
    ("import numpy as np\nnp._core\nfrom os import _exit\n", []),  # not the project's
])
def test_the_check_finds_private_names(source, want):
    assert private_uses(source) == want


@pytest.mark.parametrize("path", SCRIPTS, ids=[p.name for p in SCRIPTS])
def test_scripts_answer_help_from_outside_the_repository(path, tmp_path):
    out = subprocess.run([sys.executable, str(path), "--help"], capture_output=True, text=True, cwd=tmp_path,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    assert "usage:" in out.stdout


def test_make_real_set_writes_the_shipped_references():
    """The reference rule (its noise and contrast from bench.evaluate.outcomes) gives the shipped columns, and every
    shipped ``none`` row is a ``none`` row of its guide that passes the none-row check (bench.evaluate.nonerows)."""
    import csv
    import importlib.util
    import tomllib

    import numpy as np

    from bench.store import realset as real

    spec = importlib.util.spec_from_file_location("make_real_set", REPO / "scripts" / "make_real_set.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    guides = tomllib.loads((mod.DATA / "guides.toml").read_text())
    rows = list(csv.DictReader((mod.DATA / "manifest.csv").read_text().splitlines()))
    assert len(rows) >= 12
    for row in rows:
        name, channel = row["name"], row.get("channel") or "auto"
        rot = int(row.get("rotate") or 0)
        frame, original = real.load_frame(mod.DATA / f"{name}.png", channel="excess" if channel == "auto" else channel,
                                          laser=row["laser_colour"], rotate_deg=rot)
        ref = mod.reference_for(frame, guides[name])
        shipped, states, _ = real.read_reference_states(mod.DATA / f"{name}_ref.csv", frame.shape)
        assert np.array_equal(np.isnan(ref), np.isnan(shipped)), name
        assert np.allclose(ref[~np.isnan(ref)], shipped[~np.isnan(shipped)], atol=0.0051), name
        want = mod.states_for(ref, guides[name])
        off = off_original = None
        if row["has_background"] == "1":
            off, off_original = real.load_frame(mod.DATA / f"{name}_off.png",
                                                channel="excess" if channel == "auto" else channel,
                                                laser=row["laser_colour"], rotate_deg=rot)
        doubt = mod.none_doubts(frame, ref, want, original, row["laser_colour"], rot, off, off_original)
        assert not (doubt & (states == 0)).any(), name
        want[doubt] = -1
        assert np.array_equal(want, states), name


def test_without_states_copies_a_real_set_with_its_references_read_by_the_fallback_rule(tmp_path, capsys):
    """``scripts/without_states.py``: the columns as shipped, the states those of the fallback rule, every other file
    the same bytes; an existing destination or a bad reference is one line and exit 2."""
    import importlib.util

    import numpy as np

    from bench.evaluate.outcomes import fallback_states
    from bench.store import realset as real

    spec = importlib.util.spec_from_file_location("without_states", REPO / "scripts" / "without_states.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    dst = tmp_path / "copy"
    assert mod.main([str(real.SHIPPED), str(dst)]) == 0
    assert sorted(p.name for p in dst.iterdir()) == sorted(p.name for p in real.SHIPPED.iterdir())
    for im in real.load_dataset(dst):
        frame, _, _, _ = im.load()
        cols, states, explicit = real.read_reference_states(im.reference_path, frame.shape)
        shipped, _, was = real.read_reference_states(real.SHIPPED / im.reference_path.name, frame.shape)
        assert was and not explicit and real.reference_gives_states(real.SHIPPED / im.reference_path.name)
        np.testing.assert_array_equal(cols, shipped)
        np.testing.assert_array_equal(states, fallback_states(shipped))
        assert (dst / im.image_path.name).read_bytes() == im.image_path.read_bytes()
    capsys.readouterr()
    assert mod.main([str(real.SHIPPED), str(dst)]) == 2
    assert capsys.readouterr().err.strip().endswith("exists; give a new folder")
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "manifest.csv").write_text("name,has_background,laser_colour\n")
    (bad / "a_ref.csv").write_text("r,c,s\n0,1,stripe\n")
    assert mod.main([str(bad), str(tmp_path / "out")]) == 2 and not (tmp_path / "out").exists()
    assert "a_ref.csv: header must be" in capsys.readouterr().err


def _setup_copy(tmp_path):
    """``scripts/setup.sh`` alone in an empty project folder (no ``.venv``)."""
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "setup.sh").write_text((REPO / "scripts" / "setup.sh").read_text())
    return tmp_path / "scripts" / "setup.sh"


def test_setup_stops_in_one_line_when_the_disk_is_too_full(tmp_path):
    script = _setup_copy(tmp_path)
    env = {"PATH": "/usr/bin:/bin", "STRIPEBENCH_SETUP_NEED_MB": str(10**12), "TMPDIR": str(tmp_path)}
    r = subprocess.run(["bash", str(script)], capture_output=True, text=True, env=env, timeout=60)
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("setup: only ") and "MB free on" in lines[0], r.stderr
    assert not (tmp_path / ".venv").exists()  # stopped before it made anything


def test_ci_run_stops_when_setup_fails():
    """``set -e`` does not stop on a failure left of ``&&``: the set-up must be a command of its own."""
    lines = [ln.strip() for ln in (REPO / ".ci" / "run").read_text().splitlines()]
    commands = [ln for ln in lines if ln and not ln.startswith("#")]
    assert "set -euo pipefail" in commands
    setup = [ln for ln in commands if "scripts/setup.sh" in ln]
    assert setup == ["bash scripts/setup.sh"], setup


def _script(name):
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, REPO / "scripts" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("path", [p for p in SCRIPTS if ">>> " in p.read_text(encoding="utf-8")],
                         ids=lambda p: p.name)
def test_scripts_docstring_examples(path):
    """Every docstring example of a script runs and prints what it shows, as the packages' do."""
    import doctest

    import numpy as np

    mod = _script(path.stem)
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(mod, extraglobs={"np": np}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0, (path.name, result)


def test_drawn_line_finds_a_line_blended_over_the_stripe_and_not_the_stripe_alone():
    """``scripts/drawn_line.py``: a one-pixel line at opacity a leaves a dip of depth 1 - a in every channel where it
    falls on a pixel, two pixels at 1 - a / 2 where it falls between two; a clean stripe, or one whose dip is
    shallower than DIP, has none; a dip farther than HALF_WIDTH from the reference is not looked at."""
    import numpy as np

    mod = _script("drawn_line")
    rows, cols = np.mgrid[0:30, 0:60]
    stripe = 20.0 + 200.0 * np.minimum(1.0, 1.5 * np.exp(-0.5 * ((cols - 30.0) / 2.5) ** 2))  # a clipped core
    img = np.repeat(stripe[..., None], 3, axis=2) * np.array([1.0, 0.6, 0.5])
    ref = np.full(30, 30.0)
    assert mod.narrow_dips(img, ref) == []
    drawn = img.copy()
    drawn[:10, 30] *= 1 - 0.4  # on a pixel, opacity 0.4
    drawn[10:20, 30:32] *= 1 - 0.3 / 2  # between two pixels, opacity 0.3: each covered half
    drawn[20:, 30] *= 0.9  # too shallow to count
    dips = mod.narrow_dips(drawn, ref)
    assert [r for r, *_ in dips] == list(range(10))  # the two-pixel dips (0.85) are not under DIP...
    assert all(c == 30 and w == 1 and np.allclose(d, 0.6, atol=0.02) for _, c, w, d in dips)
    deeper = img.copy()
    deeper[:, 30:32] *= 1 - 0.6 / 2
    assert [(c, w) for _, c, w, _ in mod.narrow_dips(deeper, ref)] == [(30, 2)] * 30  # ... at opacity 0.6 they are
    far = img.copy()
    far[:, 30] *= 0.5
    assert mod.narrow_dips(far, np.full(30, 30.0 + mod.HALF_WIDTH + 3)) == []
    half = ref.copy()
    half[5:] = np.nan
    assert len(mod.narrow_dips(drawn, half)) == 5
    with pytest.raises(ValueError, match="ref_cols"):
        mod.narrow_dips(img, ref[:5])


def test_the_shipped_ag_tape_has_no_line_drawn_over_its_stripe():
    """The shipped ``ag_tape`` is its source with the drawn line undone (``make_real_set.py images``): along its
    references it has no more even narrow dips than the other photographs have (0-3), where its source has one in
    244 of its 253 reference rows (docs/real.md)."""
    import numpy as np

    from bench.store import realset as real

    mod = _script("drawn_line")
    im = next(im for im in real.load_dataset(real.SHIPPED) if im.name == "ag_tape")
    frame, _, original, ref = im.load()
    dips = mod.narrow_dips(original, ref)
    assert sum(1 for *_, d in dips if d.max() - d.min() <= mod.EVEN) <= 3


def test_drawn_line_reads_a_real_set_and_names_an_unknown_photograph(capsys, tmp_path):
    from bench.store import realset as real

    mod = _script("drawn_line")
    assert mod.main([str(real.SHIPPED), "ag_tape", "dg_weld"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["photograph", "rows", "1", "px", "even", "depth", "2", "px", "even", "depth"]
    assert [ln.split()[0] for ln in lines[1:]] == ["ag_tape", "dg_weld"]
    assert mod.main([str(real.SHIPPED), "nosuch"]) == 2
    assert "no photograph nosuch" in capsys.readouterr().err
    assert mod.main([str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith("drawn_line.py: ")


def test_make_real_set_reads_the_fh_guides_off_the_laser_off_difference():
    """``make_real_set.py guides``: the shipped ``fh_*`` guides are what :func:`difference_guide` reads off each
    frame's laser-on minus laser-off difference (the ``triangulation_4`` frames' window columns left out; the
    ``fh_box*`` halves of ``triangulation_3`` whole), segment for segment."""
    import tomllib

    from bench.store import realset as real

    mod = _script("make_real_set")
    guides = tomllib.loads((mod.DATA / "guides.toml").read_text())
    names = [n for n in guides if n.startswith("fh_")]
    skip = {n: 0 if n.startswith("fh_box") else 70 for n in names}
    assert sorted(skip.values()) == [0] * 13 + [70] * 4
    for name in names:
        on, off = (real.read_image(mod.DATA / f"{name}{s}.png") for s in ("", "_off"))
        assert mod.difference_guide(on, off, "red", skip_cols=skip[name]) == guides[name]["segments"], name
    on = real.read_image(mod.DATA / "fh_left0.png")
    assert mod.difference_guide(on, on, "red") == []  # no difference, no guide


def _fake_apt(tmp_path, script: str) -> dict:
    """A PATH where ``ldconfig`` finds no LLVM, ``id -u`` says root and ``apt-get`` runs ``script`` (bash; ``$n``:
    how many times it has run), and a ``PYTHON`` that stops the set-up right after the LLVM step."""
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    (bin_ / "ldconfig").write_text("#!/bin/sh\nexit 0\n")
    (bin_ / "id").write_text("#!/bin/sh\necho 0\n")
    (bin_ / "apt-get").write_text(f"#!/bin/bash\nc={tmp_path}/calls; n=$(( $(cat $c 2>/dev/null || echo 0) + 1 ));"
                                  f" echo $n > $c\n{script}\n")
    for f in bin_.iterdir():
        f.chmod(0o755)
    return {"PATH": f"{bin_}:/usr/bin:/bin", "STRIPEBENCH_SETUP_NEED_MB": "1", "STRIPEBENCH_SETUP_APT_WAIT_S": "4",
            "PYTHON": "false", "TMPDIR": str(tmp_path)}


LOCKED = ('echo "E: Could not get lock /var/lib/dpkg/lock-frontend. It is held by process 4242 (apt-get)" >&2; '
          'echo "E: Unable to acquire the dpkg frontend lock, is another process using it?" >&2; exit 100')


@pytest.mark.parametrize("apt, says, calls", [
    # the lock is released after two tries: a short wait, then installed
    (f'if [ $n -le 2 ]; then {LOCKED}; fi; exit 0', ["setup: apt is busy", "setup: installing libllvm19"], 3),
    # held all along: after the wait, apt's own words
    (LOCKED, ["could not install libllvm19 (apt-get: E: Could not get lock /var/lib/dpkg/lock-frontend. It is held "
              "by process 4242 (apt-get) E: Unable to acquire the dpkg frontend lock, is another process using it?)"],
     None),
    # not a lock: apt's message at once, after one update and one more try
    ('echo "E: Unable to locate package libllvm19" >&2; exit 100',
     ["could not install libllvm19 (apt-get: E: Unable to locate package libllvm19)"], 2),
])
def test_setup_says_what_apt_said_and_waits_for_its_lock(tmp_path, apt, says, calls):
    script = _setup_copy(tmp_path)
    r = subprocess.run(["bash", str(script)], capture_output=True, text=True, env=_fake_apt(tmp_path, apt),
                       timeout=120)
    out = r.stdout + r.stderr
    for s in says:
        assert s in out, out
    if calls == 3:
        assert "could not install" not in out, out
    if calls is not None:
        assert int((tmp_path / "calls").read_text()) == calls, out


def test_compile_kernels_runs_every_listed_tracker_on_every_kind_of_frame(monkeypatch, capsys):
    """``scripts/compile_kernels.py --trackers-only`` (a step of ``setup.sh``) tracks each kind of frame a run hands
    a tracker with every listed tracker, and says so in one line."""
    import trackers
    from bench.run import track

    mod = _script("compile_kernels")
    kinds = {(im.dtype.kind, bg is not None, c is not None) for im, bg, c in mod.frames()}
    assert kinds >= {("u", True, False), ("u", False, False), ("f", True, True), ("f", False, True)}
    seen = []
    real = track.track_frame
    monkeypatch.setattr(track, "track_frame", lambda t, *a, **k: seen.append(type(t).__name__) or real(t, *a, **k))
    assert mod.main(["--trackers-only"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1 and out[0].startswith(f"compile_kernels: {len(trackers.available())} trackers compiled")
    assert len(seen) == len(trackers.available()) * len(mod.frames())


def test_setup_compiles_the_kernels_once_per_home():
    text = (REPO / "scripts" / "setup.sh").read_text()
    assert ".venv/bin/python scripts/compile_kernels.py" in text and '!= "$HOME"' in text
