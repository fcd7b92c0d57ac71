"""The compiled checks and kernels of agglomtool.bed.hydrodynamics give the same numbers,
bit for bit, and the same errors and warnings as the plain numpy expressions of the
correlations they replace (the excess gas ``U - Umf`` with its domain checks, the Geldart
group bounds, the bubble wakes' granular temperature).

The expected values are recomputed here from the correlations' formulas with numpy, in
the order of operations the functions state; equality is exact (``assert_array_equal``):
the kernels use only IEEE additions, multiplications and divisions, each correctly
rounded, so any reordering or a fused multiply-add would show.
"""

import warnings

import numpy as np
import pytest

import agglomtool as at
from agglomtool.bed import hydrodynamics as hd

RNG = np.random.default_rng(27)
N = 20_000


def _arrays():
    Umf = RNG.uniform(0.005, 0.5, N)
    U = Umf * RNG.uniform(1.01, 6.0, N)
    return U, Umf


def test_excess_is_u_minus_umf_bitwise():
    U, Umf = _arrays()
    np.testing.assert_array_equal(hd._excess(U, Umf), U - Umf)
    # broadcasting: one Umf for every U, and a 2-D grid
    np.testing.assert_array_equal(hd._excess(U, 0.004), U - 0.004)
    low = RNG.uniform(0.001, 0.004, 200)  # below every U
    np.testing.assert_array_equal(hd._excess(U.reshape(100, 200), low),
                                  U.reshape(100, 200) - low)


@pytest.mark.parametrize("U, Umf, match", [
    ([0.3, 0.2], [0.1, 0.2], "U = 0.2 m/s does not exceed Umf = 0.2"),
    ([0.3, np.nan], [0.1, 0.1], "U = nan"),
    ([0.3, -0.1], [0.1, 0.1], "U = -0.1"),
    ([0.3, 0.4], [0.1, 0.0], "Umf = 0.0"),
    ([0.3, np.inf], [0.1, 0.1], "U = inf"),
    ([0.3, 0.4], [0.1, np.inf], "Umf = inf"),
])
def test_excess_errors_name_the_value(U, Umf, match):
    """An array with one bad element is refused as before: the error names the field and
    the value (the compiled check only finds that something is wrong; the message is
    the plain path's)."""
    with pytest.raises(ValueError, match=match):
        hd._excess(np.array(U), np.array(Umf))


def test_geldart_check_bounds_are_the_groups():
    """The compiled group check warns exactly where geldart_group says a powder is outside
    B (A below, D above), naming the first such element."""
    d = RNG.uniform(50e-6, 1.5e-3, N)
    rho = RNG.uniform(1000.0, 4000.0, N)
    groups = hd.geldart_group(d, rho, 1.2)
    inside = groups == "B"
    with warnings.catch_warnings():
        warnings.simplefilter("error", at.PlausibilityWarning)
        hd._check_group("x", d[inside], rho[inside], 1.2)  # no warning
    first = int(np.argmax(~inside))
    with pytest.warns(at.PlausibilityWarning,
                      match=f"d_p = {d[first]:g} m is a Geldart group {groups[first]}"):
        hd._check_group("x", d, rho, 1.2)
    # B and D allowed: only the A powders warn, the first of them named
    first_a = int(np.argmax(groups == "A"))
    with pytest.warns(at.PlausibilityWarning, match=f"d_p = {d[first_a]:g} m is a Geldart "
                      "group A"):
        hd._check_group("x", d, rho, 1.2, allowed=("B", "D"))


def test_geldart_check_on_the_boundaries():
    """On the group bounds themselves (A/B at (rho_p - rho_g) d_p = 225 g/cm3 um, B/D at
    (rho_p - rho_g) d_p**2 = 1e6): B includes its lower bound and excludes its upper one,
    as geldart_group does."""
    rho = 2225.0  # rho_p - rho_g = 2.225 g/cm3 with rho_g = 0
    for d in (225.0 / 2.225 * 1e-6, (1e6 / 2.225) ** 0.5 * 1e-6):
        group = str(hd.geldart_group(d, rho, 0.0))
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            hd._check_group("x", np.array([d]), rho, 0.0)
        assert bool(w) == (group != "B"), (d, group)


def test_wake_temperature_bitwise():
    delta = RNG.uniform(0.0, 0.6, N)
    u_b = RNG.uniform(0.0, 3.0, N)
    for f_w in (0.25, RNG.uniform(0.05, 0.5, N)):
        phi = f_w * delta / (1.0 - delta)
        expected = phi * u_b * u_b / (3.0 * (1.0 - phi))
        np.testing.assert_array_equal(hd.granular_temperature_bubble_wake(delta, u_b, f_w),
                                      expected)


@pytest.mark.parametrize("delta, u_b, f_w, match", [
    ([0.1, 1.0], [1.0, 1.0], 0.25, "delta = 1.0"),
    ([0.1, -0.1], [1.0, 1.0], 0.25, "delta = -0.1"),
    ([0.1, np.nan], [1.0, 1.0], 0.25, "delta = nan"),
    ([0.1, 0.2], [1.0, -1.0], 0.25, "u_b = -1.0"),
    ([0.1, 0.2], [1.0, np.inf], 0.25, "u_b = inf"),
    ([0.1, 0.2], [1.0, 1.0], 0.0, "wake_fraction = 0"),
    ([0.1, 0.6], [1.0, 1.0], 1.0, "wakes fill the bed"),
])
def test_wake_temperature_errors(delta, u_b, f_w, match):
    with pytest.raises(ValueError, match=match):
        hd.granular_temperature_bubble_wake(np.array(delta), np.array(u_b), f_w)


def test_mori_wen_range_warnings_name_the_extreme():
    """Mori and Wen's data range, checked by two reductions: the warning names the
    smallest value where one is below the range, else the largest; a NaN particle size
    among sizes outside the range still warns (as the element-wise comparisons did)."""
    U = np.array([0.3, 0.3, 0.3])
    with pytest.warns(at.PlausibilityWarning, match="Umf = 0.001 m/s"):
        hd.bubble_diameter_mori_wen(U, np.array([0.1, 0.001, 0.05]), 0.2, 0.5)
    with pytest.warns(at.PlausibilityWarning, match="d_p = 0.0009 m"):
        hd.bubble_diameter_mori_wen(U, 0.1, 0.2, 0.5, d_p=np.array([2e-4, 9e-4, 5e-4]))
    with pytest.warns(at.PlausibilityWarning, match="d_p = nan m"):
        hd.bubble_diameter_mori_wen(U, 0.1, 0.2, 0.5, d_p=np.array([2e-4, np.nan, 9e-4]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", at.PlausibilityWarning)
        hd.bubble_diameter_mori_wen(U, 0.1, 0.2, 0.5, d_p=np.array([2e-4, np.nan, 3e-4]))


def test_slugging_warning_names_the_largest_bubble():
    d_b = RNG.uniform(0.01, 0.2, N)
    D_t = 0.25
    worst = float(np.max(d_b / D_t))
    with pytest.warns(at.PlausibilityWarning, match=f"d_b = {worst:.3g} D_t"):
        hd.bubble_rise_velocity_davidson_harrison(d_b, D_t)


def test_bubble_fraction_of_one_or_more_names_the_largest():
    """Bubbles too slow to carry the excess gas (delta >= 1) anywhere in an array: the
    error names the largest fraction (Kunii and Levenspiel's slow-bubble form here,
    0.18 / (0.01 + 2 x 0.02) = 3.6)."""
    with pytest.raises(ValueError, match="delta = 3.6 >= 1"):
        hd.bubble_fraction_kunii_levenspiel(np.array([0.2, 0.2]), 0.02,
                                            np.array([1.0, 0.01]), 0.5)


def _chain(U, Umf, d_b, D_t, eps, f_w):
    u_b = hd.bubble_velocity_davidson_harrison(U, Umf, d_b, D_t)
    delta = hd.bubble_fraction_kunii_levenspiel(U, Umf, u_b, eps)
    return hd.granular_temperature_bubble_wake(delta, u_b, f_w)


def test_bubble_chain_is_the_functions_in_turn_bitwise():
    """granular_temperature_bubbles on arrays (one compiled pass) gives the numbers of the
    three functions called in turn, exactly, over every regime of the bubble fraction
    (u_b / u_f from below 1 to above 10) and of the rise velocity (free, wall, slug)."""
    Umf = RNG.uniform(0.005, 0.3, N)
    U = Umf * RNG.uniform(1.05, 3.0, N)
    d_b = RNG.uniform(0.001, 0.12, N)
    for D_t in (0.5, 0.15):  # 0.15 m: bubbles of 0.6 D_t and more, a slug's velocity
        with warnings.catch_warnings(record=True) as fused_w:
            warnings.simplefilter("always")
            fused = hd.granular_temperature_bubbles(U, Umf, d_b, D_t, 0.45, 0.25)
        with warnings.catch_warnings(record=True) as chain_w:
            warnings.simplefilter("always")
            chain = _chain(U, Umf, d_b, D_t, 0.45, 0.25)
        np.testing.assert_array_equal(fused, chain)
        assert [str(w.message) for w in fused_w] == [str(w.message) for w in chain_w]
        assert bool(fused_w) == (D_t == 0.15)  # the slugging warning, once
    # the regimes were all reached
    u_b = hd.bubble_velocity_davidson_harrison(U, Umf, d_b, 0.5)
    ratio = u_b / (Umf / 0.45)
    assert ratio.min() < 1.0 and ratio.max() > 10.0


@pytest.mark.parametrize("U, Umf, d_b, eps, f_w, match", [
    ([0.2, 0.2], 0.02, [0.05, 1e-9], 0.5, 0.25, "delta = "),    # bubbles too slow
    ([0.3, 0.3], 0.1, [0.05, 0.0], 0.45, 0.25, "d_b = 0"),
    ([0.3, 0.3], 0.1, [0.05, 0.05], 1.0, 0.25, "eps_mf = 1"),
    ([0.9, 0.9], 0.1, [0.02, 0.02], 0.45, 2.0, "wakes fill the bed"),
    ([0.3, 0.05], 0.1, [0.05, 0.05], 0.45, 0.25, "does not exceed Umf"),
])
def test_bubble_chain_errors_are_the_functions(U, Umf, d_b, eps, f_w, match):
    """Where one of the three functions refuses an element, the fused form refuses it with
    the same message."""
    args = (np.array(U), Umf, np.array(d_b), 0.5, eps, f_w)
    with pytest.raises(ValueError, match=match) as fused:
        hd.granular_temperature_bubbles(*args)
    with pytest.raises(ValueError) as chain:
        _chain(*args)
    assert str(fused.value) == str(chain.value)


@pytest.mark.parametrize("A0", [0.0, 1e-4, "mixed"])
def test_mori_wen_on_arrays_is_the_formula_element_by_element(A0):
    """Mori and Wen's bubble size on a map's arrays (numpy's vectorized powers) against
    the formula evaluated element by element with Python's math module (the C library's
    pow and exp), the operations in the docstring's order: within 1e-12 relative. Not
    bitwise: numpy's SIMD pow may differ from the C library's by 1 ulp, and where
    d_b0 and d_bm nearly cancel (a low height in a wide column) that ulp grows to about
    3e-14 relative (measured on 2e5 random points)."""
    import math

    U, Umf = _arrays()
    h, D_t = RNG.uniform(0.0, 1.0, N), RNG.uniform(0.3, 1.3, N)
    a0 = (RNG.uniform(0.0, 1e-3, N) * (RNG.random(N) < 0.5) if A0 == "mixed"
          else np.full(N, A0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        got = hd.bubble_diameter_mori_wen(U, Umf, h, D_t, a0 if A0 == "mixed" else A0)
        scalar = hd.bubble_diameter_mori_wen(U[0], Umf[0], h[0], D_t[0], a0[0])

    def one(u, umf, hh, d, a):
        ex = u - umf
        d_bm = hd._MW_MAX * (0.25 * math.pi * d * d * ex) ** 0.4
        d_b0 = (hd._MW_PERFORATED * (a * ex) ** 0.4 if a > 0.0
                else hd._MW_POROUS * (ex * ex))
        return d_bm - (d_bm - d_b0) * math.exp(-0.3 * hh / d)

    want = np.array([one(*v) for v in zip(U, Umf, h, D_t, a0, strict=True)])
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=0.0)
    assert float(scalar) == want[0]  # one point: the compiled form, the C library's pow
