"""Mesh convergence: Richardson extrapolation and the refinement study of nominal stresses."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from linkstress.validation.bench.fea import nominal_points, seed_crank, seed_position
from linkstress.validation.fea.convergence import convergence_study, richardson
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import MeshSettings


@settings(max_examples=60, deadline=None)
@given(
    exact=st.floats(-1e6, 1e6),
    c=st.floats(0.1, 10.0),
    p=st.floats(1.0, 4.0),
    h1=st.floats(0.01, 0.1),
    r21=st.floats(1.3, 2.0),
    r32=st.floats(1.3, 2.0),
)
def test_richardson_recovers_order_and_limit_of_a_power_law(exact, c, p, h1, r21, r32):
    # phi(h) = phi_0 + C h^p (Celik et al. 2008): the order from unequal ratios is exact. Only
    # well-conditioned cases: the finest error at least 1e-6 of the value, far above rounding.
    assume(c * h1**p > 1e-6 * max(1.0, abs(exact)))
    h = np.array([h1 * r21 * r32, h1 * r21, h1])
    est = richardson(exact + c * h**p, h)
    assert est.determined
    assert est.order == pytest.approx(p, rel=1e-6)
    assert est.extrapolated == pytest.approx(exact, abs=1e-6 * c * h1**p + 1e-9 * abs(exact))
    assert est.error == pytest.approx(c * h1**p, rel=1e-5)


def test_richardson_of_oscillating_or_settled_values_falls_back_to_the_last_change():
    est = richardson(np.array([[1.0, 5.0], [1.2, 5.0], [1.1, 5.0]]), np.array([0.4, 0.2, 0.1]))
    np.testing.assert_array_equal(est.determined, [False, False])
    np.testing.assert_array_equal(est.order, [0.0, 0.0])
    np.testing.assert_allclose(est.extrapolated, [1.1, 5.0])
    np.testing.assert_allclose(est.error, [0.1, 0.0])
    assert np.isfinite(est.gci).all()


def test_richardson_needs_three_distinct_meshes():
    with pytest.raises(ValueError, match="three mesh spacings must differ"):
        richardson(np.ones(3), np.array([0.1, 0.1, 0.2]))


def test_the_seed_crank_converges_to_half_a_percent_in_three_levels():
    # The seed's crank at 60 degrees under its published joint forces; nominal fibres at x = 0.25,
    # 0.5, 0.75 m. Three meshes, each 1.5 times finer; "converged" is a change below 0.5 %.
    study = convergence_study(
        seed_crank(),
        seed_position(),
        MeshSettings(0.12, 0.004, (0.25, 0.5, 0.75)),
        nominal_points(),
        ratio=1.5,
    )
    assert study.values.shape == (3, 1, 6)
    assert (np.diff(study.dofs) > 0).all() and (np.diff(study.spacing) < 0).all()
    assert study.converged and study.change[0] < 0.005
    assert study.relative_error[0] < 0.01
    assert study.finest.dofs == study.dofs[-1]
    # The peak (at the torqued pin O2) and the resultants at the three meshed cuts are followed too.
    assert study.peaks.shape == (3, 1) and study.resultants.shape == (3, 3, 1, 3)
    np.testing.assert_array_equal(study.peaks[-1], study.finest.von_mises_peak)
    assert study.peak_change[0] == pytest.approx(abs(study.peaks[2, 0] - study.peaks[1, 0]) / study.peaks[2, 0])
    assert study.peak_change[0] < 0.05


def test_a_study_without_nominal_points_follows_peak_and_resultants_alone():
    # A link too short for a nominal station: the study still runs and says it had no nominal point.
    study = convergence_study(
        seed_crank(), seed_position(), MeshSettings(0.12, 0.004, (0.5,)), np.zeros((0, 2)), ratio=1.5
    )
    assert not study.has_nominal and study.values.shape == (3, 1, 0)
    assert study.change[0] == 0.0 and study.resultants.shape == (3, 3, 1, 1)
    assert study.peak_change[0] < 0.05


def test_a_study_needs_three_levels():
    with pytest.raises(FEAError, match="at least three mesh levels"):
        convergence_study(
            seed_crank(), seed_position(), MeshSettings(0.12, 0.004), nominal_points(), levels=2
        )
