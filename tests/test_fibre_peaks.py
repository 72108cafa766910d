"""The largest von Mises within one chord: closed form without the body-load term, climbs with it."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from linkstress.dynamics.fibre_peaks import cubic_peak, has_cubic_peak, single_chord_peak

FIBRES = np.linspace(-1.0, 1.0, 100001)


def g(s, a, b, d, e):
    """sigma_vM^2 at s = u / c of a solid chord: (a + b s + d s^3)^2 + e (1 - s^2)^2."""
    return (a + b * s + d * s**3) ** 2 + e * (1 - s * s) ** 2


@settings(max_examples=200, deadline=None)
@given(
    st.floats(-1, 1), st.floats(-1, 1), st.sampled_from([0.0, 0.01, 0.1, 0.3, 1.0, 3.0]),
    st.floats(-1, 1), st.floats(0, 2), st.booleans(),
)
def test_single_chord_peak_is_the_highest_of_a_hundred_thousand_fibres(a, b, d_scale, d_unit, e, no_shear):
    # d_scale sweeps the body-load term from absent to three times the rest, where g has up to
    # three maxima in the chord.
    d, e = d_scale * d_unit, 0.0 if no_shear else e
    s = single_chord_peak(*(np.array([v]) for v in (a, b, d, e)))[1][0]
    dense = g(FIBRES, a, b, d, e).max()
    assert -1.0 <= s <= 1.0
    assert g(s, a, b, d, e) >= dense * (1 - 1e-9) - 1e-300


def test_single_chord_peak_finds_a_peak_between_samples_that_rise_toward_an_end():
    # From the seed coupler near its free end (sigma in Pa): the nine samples peak at s = 0, the
    # chord at s = 0.14; Newton's first step from s = 0 overshoots the samples' bracket.
    a, b, d, e = -38.7696327, -2566.45608, 3670.48139, 3325345.90
    s = single_chord_peak(*(np.array([v]) for v in (a, b, d, e)))[1][0]
    assert s == np.clip(s, 0.13, 0.15)
    assert g(s, a, b, d, e) >= g(FIBRES, a, b, d, e).max() * (1 - 1e-9)


def test_cubic_peak_is_the_interior_maximum_of_the_linear_stress():
    # (n + m u)^2 + 3 w^2 (C - u^2)^2 on u in [-1, 1] with C = 1: pure shear peaks at the middle,
    # and with some bending the peak moves toward the side where n + m u grows.
    n, m, w, c = np.array([0.0, 0.5]), np.array([0.0, 0.8]), np.array([1.0, 1.0]), np.array([1.0, 1.0])
    assert has_cubic_peak(n, m, w, c).all()
    u = cubic_peak(n, m, w, c)
    dense = [FIBRES[np.argmax((n[k] + m[k] * FIBRES) ** 2 + 3 * w[k] ** 2 * (c[k] - FIBRES**2) ** 2)] for k in range(2)]
    np.testing.assert_allclose(u, dense, atol=2e-5)
    assert abs(u[0]) < 1e-12 and u[1] > 0.0


def test_single_chord_peak_climbs_only_where_g_may_beat_the_floor():
    # g = (s + 0.1 s^3)^2 + 0.5 (1 - s^2)^2: 1.21 at the ends, 0.5 at the middle. Against a floor of
    # 1.21 (the ends, reached already) nothing inside can win on the first entry; the second, with
    # more shear, peaks inside above its ends.
    a, b, d = np.zeros(2), np.ones(2), np.full(2, 0.1)
    e = np.array([0.5, 4.0])
    ends = (a + b + d) ** 2
    kept, s = single_chord_peak(a, b, d, e, ends)
    assert kept.tolist() == [1]
    assert g(s[0], 0.0, 1.0, 0.1, 4.0) > ends[1]
    assert g(s[0], 0.0, 1.0, 0.1, 4.0) >= g(FIBRES, 0.0, 1.0, 0.1, 4.0).max() * (1 - 1e-9)
