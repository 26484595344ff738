"""trackers._peak.PeakTracker: the threshold family's detection, then a sub-pixel estimator per row."""

import numpy as np
import pytest

import trackers
from trackers._peak import PeakTracker
from trackers.testing import make_stripe_image

PEAK_TRACKERS = ["centroid", "gauss3", "parabolic", "blais_rioux"]


@pytest.mark.parametrize("name", PEAK_TRACKERS)
def test_reports_exactly_the_rows_the_detection_reports_with_its_score(name):
    img, truth = make_stripe_image(seed=7)
    t = trackers.make(name)
    assert isinstance(t, PeakTracker)
    d = t.detect(img)
    out = t.track(img)
    assert np.array_equal(~np.isnan(out.columns), d.hit)  # the estimator never adds or drops a row
    np.testing.assert_array_equal(out.score[d.hit], d.score[d.hit])
    assert np.isnan(out.score[~d.hit]).all()
    near = np.abs(out.columns[d.hit] - d.col[d.hit])
    assert near.max() <= 3.0  # the refined column stays beside the row's brightest pixel


@pytest.mark.parametrize("name", PEAK_TRACKERS)
def test_the_detection_parameters_are_the_threshold_trackers(name):
    params = set(trackers.make(name).get_params())
    assert set(trackers.make("threshold").get_params()) <= params
