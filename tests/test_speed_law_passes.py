"""The impact-speed laws on a map's arrays run in compiled parallel passes
(agglomtool.bed.hydrodynamics: ``_bubble_pass``, ``_collisional_pass``) that read each
input by its broadcast steps. They give the plain path's numbers bit for bit, its
``speed_flag`` codes and its warnings; anything they do not answer for (a refused input)
goes back to the plain path, whose errors are the only ones.

The plain path is the same code with the passes switched off (``MAP_PASS_MIN`` above the
map's size): the expected values are what the correlations' own functions give, not
numbers copied from the passes.
"""

import warnings

import numpy as np
import pytest

from agglomtool.bed import hydrodynamics as hd
from agglomtool.bed import speed_models as sm

RNG = np.random.default_rng(2727)
SHAPE = (20, 30, 40)  # 24000 points: a map's block, above MAP_PASS_MIN
PASS_MODELS = ("bubble-darton", "bubble-mori-wen", "collisional-balance")


def _inputs(lo=1.2, hi=4.0, **over):
    """A map's inputs as a Resolved gives them: U over the whole grid, U_mf constant along
    the last axis (U/U_mf), the gas density along the first (T), the rest scalars."""
    Umf = RNG.uniform(0.05, 0.4, SHAPE[:-1] + (1,))
    x = {"U": Umf * RNG.uniform(lo, hi, SHAPE), "Umf": Umf, "d_p": np.array(1e-3),
         "rho_p": np.array(2650.0), "rho_g": RNG.uniform(0.2, 1.2, (SHAPE[0], 1, 1)),
         "eps": np.array(0.55), "e": 0.9, "fluctuation_ratio": np.array(1.0),
         "column_diameter": np.array(0.3), "orifice_area": np.array(0.0),
         "height": np.float64(0.15), "wake_fraction": np.array(0.25)}
    x.update(over)
    return x


VARIANTS = {
    "scalars": {},
    "perforated plate": {"orifice_area": np.array(1e-4)},
    "plate per column": {"orifice_area": np.where(RNG.random((1, 30, 1)) < 0.5, 0.0, 2e-4)},
    "heights": {"height": RNG.uniform(0.0, 0.6, (1, 1, 40))},
    "columns (some slug)": {"column_diameter": RNG.uniform(0.08, 1.5, (20, 1, 1))},
    "restitution and voidage": {"e": RNG.uniform(0.5, 0.99, (1, 30, 1)),
                                "eps": RNG.uniform(0.4, 0.6, (1, 1, 40))},
    "Geldart A powder": {"d_p": np.array(60e-6)},
}


def _run(fn):
    """``fn()``'s result (or its ValueError's text) and its warnings."""
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        try:
            out, err = fn(), None
        except ValueError as exc:
            out, err = None, str(exc)
    return out, err, [(w.category, str(w.message)) for w in seen]


def _plain(monkeypatch, fn):
    with monkeypatch.context() as m:
        m.setattr(hd, "MAP_PASS_MIN", 10**12)
        return _run(fn)


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape and a.dtype == b.dtype
    assert a.tobytes() == b.tobytes()


@pytest.mark.parametrize("variant", list(VARIANTS))
@pytest.mark.parametrize("model", PASS_MODELS)
def test_map_law_is_the_plain_path_bitwise(monkeypatch, model, variant):
    x = _inputs(**VARIANTS[variant])
    inp = {k: x[k] for k in sm.IMPACT_SPEED_MODELS[model].needs}
    launched = []
    real = hd.parallel_launch

    def spy(kernel, *args):
        launched.append(kernel)
        return real(kernel, *args)

    monkeypatch.setattr(hd, "parallel_launch", spy)
    got, err, warned = _run(lambda: sm.speed_law(model, inp).theta)
    assert err is None
    assert launched  # the compiled pass answered, not the plain path
    want, err0, warned0 = _plain(monkeypatch, lambda: sm.speed_law(model, inp).theta)
    _same(got, want)
    assert warned == warned0
    # and through speed_law_partial, the map's entry: no flag, the same law
    (law, flag), _, warned = _run(lambda: sm.speed_law_partial(model, inp))
    assert flag is None
    _same(law.theta, want)
    assert warned == warned0


def test_a_map_with_bubbles_that_fill_the_column_warns_as_the_plain_path(monkeypatch):
    """A narrow column: the slugging warning names the same largest d_b / D_t."""
    x = _inputs(column_diameter=np.array(0.08))
    inp = {k: x[k] for k in sm.IMPACT_SPEED_MODELS["bubble-darton"].needs}
    _, _, warned = _run(lambda: sm.speed_law("bubble-darton", inp))
    _, _, warned0 = _plain(monkeypatch, lambda: sm.speed_law("bubble-darton", inp))
    assert any("slugs" in text for _, text in warned)
    assert warned == warned0


@pytest.mark.parametrize("lo, hi", [(0.5, 4.0), (1.5, 12.0), (0.5, 12.0)],
                         ids=["not fluidized", "no emulsion", "both"])
@pytest.mark.parametrize("model", PASS_MODELS)
def test_flags_come_from_the_pass_as_speed_domain_gives_them(monkeypatch, model, lo, hi):
    """Points with no answer: the pass gives speed_domain's codes and NaN there, the
    plain path's numbers elsewhere and its warnings (none where a point is not
    fluidized: the plain path's excess check raises before any)."""
    x = _inputs(lo, hi)
    inp = {k: x[k] for k in sm.IMPACT_SPEED_MODELS[model].needs}
    (law, flag), err, warned = _run(lambda: sm.speed_law_partial(model, inp))
    (law0, flag0), err0, warned0 = _plain(monkeypatch,
                                          lambda: sm.speed_law_partial(model, inp))
    assert err is None and err0 is None
    if flag0 is None:  # the collisional balance answers wherever the bed is fluidized
        assert flag is None
    else:
        _same(flag, flag0)
        _same(flag, sm.speed_domain(model, inp))
    _same(law.theta, law0.theta)
    assert warned == warned0
    # the pass answered (its own flags), not the plain path
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        on_map = sm._partial_on_map(model, inp)
    assert on_map is not None
    if flag0 is not None:
        assert on_map[1] is not None and on_map[1].any()


REFUSED = [("U", np.nan, "U = nan"), ("height", np.float64(-0.1), "h = -0.1"),
           ("eps", np.array(1.2), "eps_mf = 1.2")]


@pytest.mark.parametrize("model, bad, value, match", [
    *[("bubble-darton", *r) for r in REFUSED],
    *[("bubble-mori-wen", *r) for r in REFUSED],
    # Darton's correlation checks the powder (it warns outside group B), Mori and Wen's
    # the distributor against the column
    ("bubble-darton", "rho_g", np.array(5000.0), "rho_p must exceed rho_g"),
    ("bubble-mori-wen", "orifice_area", np.array(1.0), "A0 = 1 m2 is larger than the column"),
])
def test_refused_inputs_are_named_by_the_plain_path(monkeypatch, model, bad, value, match):
    """The pass does not answer for a refused input: the plain path raises, naming it
    (the same text as with the passes off)."""
    x = _inputs()
    if bad == "U":
        x["U"][3, 4, 5] = value
    else:
        x[bad] = value
    inp = {k: x[k] for k in sm.IMPACT_SPEED_MODELS[model].needs}
    _, err, warned = _run(lambda: sm.speed_law(model, inp))
    _, err0, warned0 = _plain(monkeypatch, lambda: sm.speed_law(model, inp))
    assert err is not None and match in err
    assert (err, warned) == (err0, warned0)


@pytest.mark.parametrize("d_p", [1e-3, 60e-6], ids=["group D", "group A (warns)"])
@pytest.mark.parametrize("model", PASS_MODELS)
def test_a_broadcast_input_costs_its_own_values(model, d_p):
    """Inputs given as full-size broadcast views (step 0 where they do not vary): the law,
    its warnings and its memory are those of the same inputs in their own shapes; the
    checks and copies of the views cost their distinct values, not one element of the
    map each (before: a full-size copy or temporary of each such input)."""
    import tracemalloc

    big = (100, 100, 100)
    Umf = RNG.uniform(0.05, 0.4, big[:-1] + (1,))
    own = {"U": Umf * RNG.uniform(1.2, 4.0, big), "Umf": Umf, "d_p": np.array(d_p),
           "rho_p": np.array(2650.0), "rho_g": RNG.uniform(0.2, 1.2, (big[0], 1, 1)),
           "eps": np.array(0.55), "e": np.array(0.9), "column_diameter": np.array(0.3),
           "orifice_area": np.array(0.0), "height": np.array(0.15),
           "wake_fraction": np.array(0.25)}
    views = {k: (v if k in ("U", "Umf") else np.broadcast_to(v, big)) for k, v in own.items()}
    needs = sm.IMPACT_SPEED_MODELS[model].needs
    peaks, results = [], []
    for x in (own, views):
        inp = {k: x[k] for k in needs}
        tracemalloc.start()
        results.append(_run(lambda inp=inp: sm.speed_law(model, inp).theta))
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    (got, err, warned), (want, err0, warned0) = results[1], results[0]
    assert err is None and err0 is None
    _same(got, want)
    assert warned == warned0
    if model != "bubble-mori-wen":  # (Mori and Wen's data: 60-450 um, no group)
        assert (d_p < 100e-6) == any("Geldart group A" in w for _, w in warned)
    # not one full-size array more (8 MB of float64, 1 MB of bool, for 1e6 points)
    assert peaks[1] - peaks[0] < 0.5e6, peaks


def test_inputs_are_read_by_their_steps_not_copied():
    """Each input reaches the pass as its own elements (no full-size broadcast copy), with
    step 0 along the axes it does not vary on; axes every input steps through alike are
    merged into one."""
    U = RNG.random(SHAPE)
    Umf = RNG.random(SHAPE[:-1] + (1,))
    rho_g = RNG.random((SHAPE[0], 1, 1))
    arrays, st, shp = hd._map_inputs((U, Umf, rho_g, 0.3), SHAPE)
    assert [a.size for a in arrays] == [U.size, Umf.size, rho_g.size, 1]
    assert np.shares_memory(arrays[0], U) and np.shares_memory(arrays[1], Umf)
    # the gas density varies along the first axis alone: no axes merge
    assert shp.tolist() == list(SHAPE)
    assert st.tolist() == [[SHAPE[1] * SHAPE[2], SHAPE[2], 1], [SHAPE[1], 1, 0], [1, 0, 0],
                           [0, 0, 0]]
    # without it the first two axes merge (every input steps through them alike)
    arrays, st, shp = hd._map_inputs((U, Umf, 0.3), SHAPE)
    assert shp.tolist() == [SHAPE[0] * SHAPE[1], SHAPE[2]]
    assert st.tolist() == [[SHAPE[2], 1], [1, 0], [0, 0]]


def test_an_input_in_another_memory_order_gives_the_same_numbers(monkeypatch):
    """A U laid out in Fortran order (a view of a transposed array) is read in its own
    order: the law is the plain path's."""
    x = _inputs()
    x["U"] = np.asfortranarray(x["U"])
    inp = {k: x[k] for k in sm.IMPACT_SPEED_MODELS["bubble-mori-wen"].needs}
    got = sm.speed_law("bubble-mori-wen", inp).theta
    want, _, _ = _plain(monkeypatch, lambda: sm.speed_law("bubble-mori-wen", inp).theta)
    _same(got, want)


def test_the_passes_are_parallel_and_cached():
    """The laws' passes run on every thread the collision kernels use, and are compiled
    once (cached on disk)."""
    for kernel in (hd._bubble_pass, hd._collisional_pass):
        assert kernel.targetoptions.get("parallel") is True
        assert kernel._cache.__class__.__name__ != "NullCache" or not hd.CACHE
