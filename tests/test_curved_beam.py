"""Curved-beam (Winkler-Bach) section stresses: the textbook ring, the straight limit, split sections,
equilibrium, the centre-of-curvature limit and plane-stress FEA of a curved bar."""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest
from scipy.integrate import quad
from shapely.geometry import Polygon, box

from linkstress.geometry.curved_beam import SERIES_LIMIT, cubic_kernel, curved_sections, theory_of
from linkstress.geometry.curves import arc_points, circle_points
from linkstress.errors import GeometryError
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import section_table
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings

T = 0.01
DEPTH = 0.02
CENTROID = 0.004
"""The rectangular sections sit off the member axis (v_bar = 4 mm), as a cut through a lug would."""


def rectangle(depth: float = DEPTH, centroid: float = CENTROID):
    """One cut (x = 0.5 m) of a plate whose material spans v = centroid -+ depth / 2 [m]."""
    return section_table(box(0.0, centroid - depth / 2, 1.0, centroid + depth / 2), [0.5], T)


def textbook_ring(kappa: float, v: np.ndarray, table, n: float, m: float) -> tuple[np.ndarray, float, float]:
    """Winkler-Bach for the rectangle of ``table`` bent about a centre at v = 1/kappa, in 60 digits.

    Boresi & Schmidt eqs. 9.19-9.23: r_n = h / ln(ro/ri), e = R - r_n, A = t h,
    sigma(r) = N/A + M_tb (r_n - r) / (A e r), with r the distance from the centre and M_tb > 0 putting
    the inner fibre (r = ri) in tension. Our M > 0 puts the +v fibre in tension, and +v points toward
    the centre when kappa > 0 (+v is then inner: M_tb = M) and away from it when kappa < 0 (M_tb = -M).
    e = R - r_n cancels about 2 log10(R/h) digits (19 at kappa h = 1e-9), hence 60 decimals.
    Returns sigma at ``v``, e and J = A e R^2 / r_n (the stiffness of the section about its centroid).
    """
    with localcontext() as ctx:
        ctx.prec = 60
        centre = 1 / Decimal(kappa)
        a, b = Decimal(table.lower[0, 0]), Decimal(table.upper[0, 0])
        ri, ro = sorted((abs(centre - a), abs(centre - b)))
        h, big_r = ro - ri, (ri + ro) / 2
        area = Decimal(T) * h
        r_n = h / (ro / ri).ln()
        e = big_r - r_n
        m_tb = Decimal(m) if kappa > 0 else -Decimal(m)
        r = [abs(centre - Decimal(x)) for x in v]
        sigma = [Decimal(n) / area + m_tb * (r_n - radius) / (area * e * radius) for radius in r]
        return np.array([float(s) for s in sigma]), float(e), float(area * e * big_r**2 / r_n)


@pytest.mark.parametrize("side", [1, -1], ids=["centre toward +v", "centre toward -v"])
@pytest.mark.parametrize("radius_in_depths", [0.75, 1.5, 3, 10, 100])
def test_rectangular_ring_has_the_textbook_winkler_bach_stress(radius_in_depths, side):
    table = rectangle()
    kappa = 1 / (CENTROID + side * radius_in_depths * DEPTH)
    n, m = 800.0, -35.0
    # inner and outer fibre and three between
    v = CENTROID + DEPTH * np.array([-0.5, -0.3, 0.0, 0.2, 0.5])
    curved = curved_sections(table, kappa)
    sigma = n / table.area[0] + m * curved.gain(v[None, :])[0]
    expected, e, stiffness = textbook_ring(kappa, v, table, n, m)
    np.testing.assert_allclose(sigma, expected, rtol=1e-11)
    assert curved.neutral_axis_shift()[0] == pytest.approx(e, rel=1e-11)
    assert curved.stiffness[0] == pytest.approx(stiffness, rel=1e-12)


@pytest.mark.parametrize("side", [1, -1])
@pytest.mark.parametrize("kappa_depth", [1e-3, 1e-6, 1e-9])
def test_gain_tends_to_the_straight_beam_as_the_curvature_vanishes(kappa_depth, side):
    # To first order in k h a rectangle's gain is (w + k h^2 / 6) / I at w = +-h/2: the outer fibres
    # differ from the straight (v - v_bar)/I by +-k h / 3, and the value stays exact to rounding.
    table = rectangle()
    kappa = side * kappa_depth / DEPTH
    v = CENTROID + DEPTH * np.array([-0.5, 0.5])
    curved = curved_sections(table, kappa)
    gain = curved.gain(v[None, :])[0]
    straight = (v - table.neutral_axis[0]) / table.second_moment[0]
    expected, _, _ = textbook_ring(kappa, v, table, 0.0, 1.0)
    np.testing.assert_allclose(gain, expected, rtol=1e-12)
    k = curved.centroid_curvature[0]
    # the ratio's rounding, 1e-16, is the atol
    deviation = [-k * DEPTH / 3, k * DEPTH / 3]
    np.testing.assert_allclose(gain / straight - 1, deviation, rtol=2 * kappa_depth, atol=1e-15)


def test_zero_curvature_is_the_straight_beam_exactly():
    # station 0 straight, station 1 curved (R = 25 mm): the straight one is untouched by its neighbour
    table = section_table(box(0.0, -0.011, 1.0, 0.017), [0.2, 0.7], T)
    v = np.array([[-0.011, 0.001, 0.017], [-0.01, 0.0, 0.016]])
    curved = curved_sections(table, [0.0, 40.0])
    straight = (v - table.neutral_axis[:, None]) / table.second_moment[:, None]
    np.testing.assert_array_equal(curved.gain(v)[0], straight[0])
    assert curved.neutral_axis_shift()[0] == 0.0
    assert np.abs(curved.gain(v)[1] / straight[1] - 1).max() > 0.05


def decimal_kernel(z: float) -> float:
    """Q(z) = (-ln(1 - z) - z - z^2/2 - z^3/3) / z^4 in 60 digits."""
    with localcontext() as ctx:
        ctx.prec = 60
        d = Decimal(z)
        return float((-(1 - d).ln() - d - d * d / 2 - d**3 / 3) / d**4)


def test_kernel_is_within_1e_14_on_both_sides_of_the_series_switch():
    z = np.concatenate([
        SERIES_LIMIT * np.array([1 - 1e-12, 1 + 1e-12]),
        -SERIES_LIMIT * np.array([1 - 1e-12, 1 + 1e-12]),
        np.linspace(-3.0, 0.99, 400),
        np.geomspace(1e-8, 0.49, 40),
        -np.geomspace(1e-8, 0.49, 40),
    ])
    z = z[z != 0]
    expected = np.array([decimal_kernel(x) for x in z])
    np.testing.assert_allclose(cubic_kernel(z), expected, rtol=1e-14)
    assert cubic_kernel(np.array([0.0]))[0] == 0.25


def test_stiffness_is_continuous_where_the_outer_fibres_cross_the_series_switch():
    # A centred rectangle's fibres reach z = k h / 2 = SERIES_LIMIT at R = h: just short of it every
    # chord end takes the series, just past it the closed form.
    table = rectangle(centroid=0.0)
    for kappa in np.array([1 - 1e-9, 1 + 1e-9]) * 2 * SERIES_LIMIT / DEPTH:
        _, _, stiffness = textbook_ring(kappa, np.zeros(1), table, 0.0, 1.0)
        assert curved_sections(table, kappa).stiffness[0] == pytest.approx(stiffness, rel=1e-13)


def holed_plate():
    """A plate 1 m long across v = -30..20 mm with a window v = -10..4 mm over x = 0.4..0.6 m: the cut
    at x = 0.5 is two chords, the one at x = 0.2 one."""
    window = [(0.4, -0.01), (0.4, 0.004), (0.6, 0.004), (0.6, -0.01)]
    plate = Polygon([(0, -0.03), (1, -0.03), (1, 0.02), (0, 0.02)], [window])
    return section_table(plate, [0.5, 0.2], T)


def by_quadrature(table, i: int, kappa: float, v: np.ndarray) -> np.ndarray:
    """(g(v) - g_bar) / J from the definitions, g(v) = v / (1 - kappa v) about the cut's origin:
    g_bar = (1/A) int g dA, J = int g (v - v_bar) dA, each integral by adaptive quadrature."""
    chords = table.chords(i)

    def integral(f):
        return T * sum(quad(f, a, b, epsabs=0, epsrel=1e-12)[0] for a, b in chords)

    def g(x):
        return x / (1 - kappa * x)

    area = integral(lambda x: 1.0)
    v_bar = integral(lambda x: x) / area
    g_bar = integral(g) / area
    stiffness = integral(lambda x: g(x) * (x - v_bar))
    return (g(v) - g_bar) / stiffness


@pytest.mark.parametrize("kappa", [20.0, -1 / 0.045, 1e-4])
def test_a_section_split_by_a_hole_matches_quadrature_of_the_definitions(kappa):
    # kappa = 20: centre at v = 50 mm, above the section; -1/0.045: at -45 mm, below it.
    table = holed_plate()
    np.testing.assert_array_equal(table.n_chords, [2, 1])
    v = np.array([[-0.03, -0.02, -0.01, 0.004, 0.01, 0.02], [-0.03, -0.02, -0.005, 0.0, 0.01, 0.02]])
    curved = curved_sections(table, kappa)
    gain = curved.gain(v)
    for i in range(2):
        np.testing.assert_allclose(gain[i], by_quadrature(table, i, kappa, v[i]), rtol=1e-10)
        # g_bar about the centroid, w = v - v_bar, where the centre is at w = 1 / k; g = w + k w^2 / (1 - k w),
        # the first part integrated exactly, the rest (no cancellation in it) by quadrature
        k, v_bar = curved.centroid_curvature[i], table.neutral_axis[i]
        assert k == pytest.approx(1 / (1 / kappa - v_bar), rel=1e-14)
        chords = table.chords(i) - v_bar
        g_bar = T * sum(
            (b * b - a * a) / 2 + quad(lambda w: k * w * w / (1 - k * w), a, b, epsabs=0, epsrel=1e-12)[0]
            for a, b in chords
        ) / table.area[i]
        assert curved.mean_g[i] == pytest.approx(g_bar, rel=1e-10)


def test_gain_of_one_station_takes_its_own_fibres():
    table = holed_plate()
    curved = curved_sections(table, [20.0, -10.0])
    v = np.array([-0.03, 0.0, 0.02])
    np.testing.assert_array_equal(curved.gain(v, at=1), curved.gain(np.tile(v, (2, 1)))[1])
    np.testing.assert_array_equal(curved.gain(v[:2]), [curved.gain(v[0], at=0), curved.gain(v[1], at=1)])


@pytest.mark.parametrize("kappa", [[20.0, -25.0], [-1 / 0.045, 40.0]])
def test_stress_resolves_to_the_section_forces(kappa):
    # int sigma dA = N and int sigma (v - v_bar) dA = M over the chords, by quadrature.
    table = holed_plate()
    curved = curved_sections(table, kappa)
    n, m = 1500.0, -42.0
    for i in range(2):
        def sigma(x):
            return n / table.area[i] + m * curved.gain(x, at=i)

        v_bar = table.neutral_axis[i]
        force = T * sum(quad(sigma, a, b, epsabs=0, epsrel=1e-12)[0] for a, b in table.chords(i))
        moment = T * sum(
            quad(lambda x: sigma(x) * (x - v_bar), a, b, epsabs=0, epsrel=1e-12)[0] for a, b in table.chords(i)
        )
        assert force == pytest.approx(n, rel=1e-10)
        assert moment == pytest.approx(m, rel=1e-10)


@pytest.mark.parametrize(
    "kappa, where",
    [(1 / 0.005, "centre inside the material"), (64.0, "centre on the top fibre"),
     (-1 / 0.02, "centre inside the hole, material beyond it")],
)
def test_material_at_or_beyond_the_centre_of_curvature_is_refused(kappa, where):
    if where == "centre inside the hole, material beyond it":
        table = holed_plate()
    else:
        # v = -1/64 .. 1/64 m: kappa = 64 puts the centre exactly on the top fibre.
        table = section_table(box(0.0, -1 / 64, 1.0, 1 / 64), [0.5], T)
    message = r"station x = 0\.5 m: the section reaches past its centre of curvature"
    with pytest.raises(GeometryError, match=message):
        curved_sections(table, kappa)


def test_a_curvature_that_is_not_finite_is_refused():
    with pytest.raises(GeometryError, match=r"station x = 0\.5 m: curvature must be finite, got inf 1/m"):
        curved_sections(rectangle(), math.inf)


def test_a_fibre_beyond_the_centre_of_curvature_is_refused():
    curved = curved_sections(rectangle(), 1 / 0.05)
    with pytest.raises(GeometryError, match="fibre v = 0.06 m lies at or beyond its cut's centre of curvature"):
        curved.gain(np.array([[0.0, 0.06]]))


def test_a_radius_under_ten_section_depths_is_curved():
    depth = 0.02
    kappa = np.array([0.1, -0.1, 0.1001, -0.1001, 0.0, 3.0]) / depth
    assert theory_of(kappa, depth).tolist() == ["straight", "straight", "curved", "curved", "straight", "curved"]


# -- against plane-stress FEA -------------------------------------------------------------------

ARC_RADIUS, ARC_DEPTH = 0.05, 0.0125
"""A ring segment of R = 50 mm, h = 12.5 mm (R/h = 4), 120 degrees, t = 10 mm."""
LUG_RADIUS, HOLE_RADIUS = 0.010, 0.004


def ring_segment(sagitta: float = 1e-5) -> LinkProfile:
    """The ring segment ri..ro over 30..150 degrees about the origin, a round lug with a pin hole at
    each end on the mean radius; joints sorted by x. Each arc has a vertex at the crown (90 degrees),
    so that the section table's crown cut has the exact radii.

    (A finer sagitta, 1e-6 m, makes lines of under a micrometre where lug and ring meet, on which
    gmsh fails to cut the plate at the crown.)
    """
    ri, ro = ARC_RADIUS - ARC_DEPTH / 2, ARC_RADIUS + ARC_DEPTH / 2
    start, end = math.radians(30), math.radians(150)

    def arc(r, a0, a1):
        to_crown = arc_points((0, 0), r, a0, math.pi / 2, sagitta)
        return np.vstack([to_crown, arc_points((0, 0), r, math.pi / 2, a1, sagitta)[1:]])

    pins = ARC_RADIUS * np.array([[math.cos(end), math.sin(end)], [math.cos(start), math.sin(start)]])
    shape = Polygon(np.vstack([arc(ro, start, end), arc(ri, end, start)]))
    for p in pins:
        shape = shape.union(Polygon(circle_points(tuple(p), LUG_RADIUS, sagitta)))
    holes = [circle_points(tuple(p), HOLE_RADIUS, sagitta)[::-1] for p in pins]
    return LinkProfile(Polygon(shape.exterior, holes), pins, 0.01, STRUCTURAL_STEEL, "ring segment")


def hoop_stress(stress: np.ndarray, points: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """sigma_tt (Q,) [Pa] of stresses (Q, 3) (sigma_xx, sigma_yy, tau_xy) at ``points`` (Q, 2), hoop
    direction square to the radius from ``centre`` (all member frame)."""
    radial = points - centre
    tx, ty = np.array([-radial[:, 1], radial[:, 0]]) / np.hypot(*radial.T)
    sxx, syy, txy = stress.T
    return sxx * tx * tx + syy * ty * ty + 2 * txy * tx * ty


def test_ring_segment_under_pin_forces_has_winkler_bach_hoop_stress_at_its_crown():
    # Pins at 30 and 150 degrees on R = 50 mm, pulled apart by P = 1000 N along the chord between
    # them (no motion, no gravity). Member frame: origin at the left pin, x along the chord, so the
    # crown's radial cut is the cut x = R cos 30 (half the chord) and spans y = ri - R sin 30 ..
    # ro - R sin 30 = 18.75 .. 31.25 mm, centroid y = 25 mm; the centre of curvature is at
    # y = -R sin 30 = -25 mm, 50 mm below the centroid: kappa = 1 / (-25 mm) = -40 1/m.
    # Statics of the part left of the cut (the left pin's force (-P, 0) at the origin):
    # N = P = 1000 N, and M = -(25 mm) P = -25 N m about the centroid (the outer, +y fibre in
    # compression: pulling the pins apart flattens the arc).
    link = ring_segment()
    p = 1000.0
    crown = ARC_RADIUS * math.cos(math.radians(30))
    centre = np.array([crown, -ARC_RADIUS * math.sin(math.radians(30))])
    table = link.sections([crown], 0, 1)
    np.testing.assert_allclose(table.chords(0), [[0.01875, 0.03125]], rtol=1e-12)
    n, m = p, -0.025 * p
    loads = LinkLoadCase(
        (0, 1), np.array([[[-p, 0.0], [p, 0.0]]]), np.zeros((1, 2)), np.zeros(1), np.zeros(1),
        np.zeros((1, 2)), np.zeros((1, 2)),
    )
    fibres = np.array([table.bottom[0], table.top[0]])
    curved = curved_sections(table, 1 / centre[1])
    winkler_bach = n / table.area[0] + m * curved.gain(fibres[None, :])[0]
    straight = n / table.area[0] + m * (fibres - table.neutral_axis[0]) / table.second_moment[0]

    points = np.column_stack([[crown, crown], fibres])
    results = [
        solve_link(link, loads, MeshSettings(size, size / 2, (crown,), size / 2, order=2))
        for size in (ARC_DEPTH / 6, ARC_DEPTH / 8)
    ]
    coarse, fine = (hoop_stress(r.stress_at(points)[0], points, centre) for r in results)
    # converged: the last refinement moves the crown's fibre stresses by under 0.2 %
    np.testing.assert_allclose(coarse, fine, rtol=2e-3)
    # the FEA's cut at the crown carries the N and M of the statics above
    cut = results[-1].section_resultants([crown])
    assert cut.normal[0, 0] == pytest.approx(n, rel=5e-3)
    assert cut.moment[0, 0] == pytest.approx(m, rel=5e-3)
    # Winkler-Bach within 1 % at the inner and outer fibre (measured: +0.45 % and +0.57 %; the
    # elasticity solution of this bar, Timoshenko & Goodier sections 29 and 31, is 0.53 % above
    # Winkler-Bach at both); the straight beam is 8-9 % off
    np.testing.assert_allclose(fine, winkler_bach, rtol=1e-2)
    assert (np.abs(fine / straight - 1) > 0.05).all()
