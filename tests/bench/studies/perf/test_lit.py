import pytest

from bench.studies.perf import lit
from bench.cli import main


@pytest.mark.parametrize("argv, message", [
    (["--sizes", "128"], "argument --sizes: must be WIDTHxHEIGHT (e.g. 128x120), got '128'"),
    (["--every", "0"], "argument --every: must be an integer 1 .. 100, got '0'"),
    (["--spp", "x"], "argument --spp: must be an integer 1 .. 4096, got 'x'")])
def test_bad_options_are_one_line_and_exit_2(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["perf", "lit", *argv])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


@pytest.mark.slow
def test_one_tiny_frame_has_no_direct_light_outside():
    import scenes

    s = scenes.make("sphere", background="none", support="table", width=32, height=30, cache=False)
    outside, share, lit_share = lit.check_frame(s, float(s.default_angles()[5]), 4)
    assert (outside, share) == (0, 0.0) and 0.0 < lit_share < 1.0
