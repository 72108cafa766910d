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
    # two maxima in the chord.
    d, e = d_scale * d_unit, 0.0 if no_shear else e
    s = single_chord_peak(*(np.array([v]) for v in (a, b, d, e)))[1][0]
    dense = g(FIBRES, a, b, d, e).max()
    assert -1.0 <= s <= 1.0
    assert g(s, a, b, d, e) >= dense * (1 - 1e-12) - 1e-300


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
    kept, s, _ = single_chord_peak(a, b, d, e, ends)
    assert kept.tolist() == [1]
    assert g(s[0], 0.0, 1.0, 0.1, 4.0) > ends[1]
    assert g(s[0], 0.0, 1.0, 0.1, 4.0) >= g(FIBRES, 0.0, 1.0, 0.1, 4.0).max() * (1 - 1e-9)


def test_single_chord_peak_finds_a_maximum_hidden_between_samples_that_rise_toward_the_end():
    # From the seed coupler over a turn: the samples at s = 0.5, 0.75, 1 rise, yet g peaks at
    # s = 0.611 (0.06 % above the top fibre, where the search starts) and dips before the end.
    # No sample is higher than both its neighbours there; the bracket's Hermite bound finds it.
    # A thousand entries, as in a sweep, so that the search samples nine fibres per chord.
    a, b, d, e = -2052.1315869412115, -487.8821410196797, 138.13033485149026, 1008948.574192273
    top = g(1.0, a, b, d, e)
    assert g(0.5, a, b, d, e) < g(0.75, a, b, d, e) < top
    kept, s, _ = single_chord_peak(*(np.full(1000, v) for v in (a, b, d, e, top)))
    dense = g(FIBRES, a, b, d, e)
    assert kept.tolist() == list(range(1000)) and np.all(abs(s - FIBRES[np.argmax(dense)]) < 1e-4)
    assert np.all(g(s, a, b, d, e) >= dense.max() * (1 - 1e-12))


def test_single_chord_peak_over_many_entries_at_once_matches_twenty_thousand_fibres():
    # 2,000 entries of one call, as the section search makes them: rows with two maxima, rows won
    # at the outer fibres, and the floor those fibres set; each kept row is the chord's maximum and
    # no row left out beats its floor.
    rng = np.random.default_rng(5)
    a, b, e = rng.uniform(-1, 1, 2000), rng.uniform(-1, 1, 2000), rng.uniform(0, 1, 2000) ** 2
    d = rng.uniform(-3, 3, 2000)
    floor = np.maximum(g(-1.0, a, b, d, e), g(1.0, a, b, d, e))
    kept, s, peak = single_chord_peak(a, b, d, e, floor)
    fibres = np.linspace(-1.0, 1.0, 20001)
    dense = np.array([g(fibres, *row).max() for row in zip(a, b, d, e)])
    assert (g(s, a[kept], b[kept], d[kept], e[kept]) >= dense[kept] * (1 - 1e-12)).all()
    np.testing.assert_allclose(peak, g(s, a[kept], b[kept], d[kept], e[kept]), rtol=1e-12)
    left_out = np.setdiff1d(np.arange(2000), kept)
    assert (dense[left_out] <= floor[left_out] * (1 + 1e-12)).all()
    assert 0.2 < len(kept) / 2000 < 0.95


def test_single_chord_peak_resamples_a_bracket_holding_a_maximum_and_a_minimum():
    # g peaks at s = 0.883 and dips to a minimum at s = 0.999, both between the last two of nine
    # samples (0.75 and 1), where g' is positive at both: no sign change shows the peak (0.08 % above
    # the top fibre), the bracket's bound leaves it open, and only sampling it again finds it.
    # A thousand entries, as in a sweep, so that the search samples nine fibres per chord.
    a, b, d, e = 0.31477981971170244, 0.4859813726676905, -0.161968490919564, 0.17418713373461728
    top = g(1.0, a, b, d, e)
    kept, s, _ = single_chord_peak(*(np.full(1000, v) for v in (a, b, d, e, top)))
    dense = g(FIBRES, a, b, d, e)
    assert dense.max() > top * (1 + 5e-4)
    assert kept.tolist() == list(range(1000)) and np.all(abs(s - FIBRES[np.argmax(dense)]) < 1e-4)
    assert np.all(g(s, a, b, d, e) >= dense.max() * (1 - 1e-12))


def test_single_chord_peak_takes_safeguarded_steps_where_plain_newton_leaves_its_bracket():
    # From the seed coupler's 3,600-position sweep (sigma in Pa, floor the outer fibres' g): in a
    # batch of 300 (so nine samples are taken), the plain Newton steps from the Hermite peak do not
    # land in the bracket, and the safeguarded steps must take over.
    a, b, d, e, floor = -145.56586665773898, -1126.4074646735687, 1741.2493322132354, 484612.1632691437, 578219.9222272326
    kept, s, _ = single_chord_peak(*(np.full(300, v) for v in (a, b, d, e, floor)))
    dense = g(FIBRES, a, b, d, e).max()
    assert dense > floor and len(kept) == 300
    assert (g(s, a, b, d, e) >= dense * (1 - 1e-12)).all()
