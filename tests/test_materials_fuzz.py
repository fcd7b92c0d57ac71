"""Fuzzing user materials files: whatever an entry holds, loading it gives the
entry or a MaterialsError (a ValueError) naming the file, the entry and the field; nothing
else escapes from inside the package."""

import tomllib
import uuid

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from agglomtool import materials

FIELDS = {
    "solid": ["density", "asperity_height", "restitution_dry", "size_range", "source",
              "confidence", "assumed", "colour"],
    "liquid": ["model", "mu", "gamma", "rho", "theta_deg", "composition_wt",
               "viscosity_model", "source", "confidence", "assumed"],
    "gas": ["composition", "source", "confidence", "assumed"],
}
SCALARS = st.one_of(
    st.booleans(), st.integers(-10, 10**5), st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["", "fixed", "water", "melt", "grd", "text", "N2", "SiO2",
                     "density", "theta_deg"]))
VALUES = st.one_of(
    SCALARS, st.lists(SCALARS, max_size=3),
    st.dictionaries(st.sampled_from(["N2", "O2", "SiO2", "CaO", "Xx", "Air"]),
                    st.one_of(st.floats(-10, 120), st.just(float("nan"))), max_size=3))


@st.composite
def files(draw):
    kind = draw(st.sampled_from(sorted(FIELDS)))
    name = draw(st.sampled_from(["my-entry", "My_Entry", "two words"]))
    entry = draw(st.dictionaries(st.sampled_from(FIELDS[kind]), VALUES, max_size=6))
    return kind, name, entry


def _toml(kind, name, entry) -> str:
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, float):
            return {float("inf"): "inf", float("-inf"): "-inf"}.get(v, "nan" if v != v
                                                                     else repr(v))
        if isinstance(v, int):
            return str(v)
        if isinstance(v, str):
            return '"' + v + '"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"

    lines = [f'[{kind}."{name}"]'] + [f"{k} = {value(v)}" for k, v in entry.items()]
    return "\n".join(lines) + "\n"


@settings(max_examples=200, deadline=None, suppress_health_check=[
    HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(files())
def test_any_user_entry_loads_or_names_file_entry_and_field(tmp_path, spec):
    kind, name, entry = spec
    text = _toml(kind, name, entry)
    tomllib.loads(text)  # the generator writes valid TOML: the package is what is tested
    folder = tmp_path / uuid.uuid4().hex  # a fresh folder: no cached earlier example
    folder.mkdir()
    path = folder / "mine.toml"
    path.write_text(text)
    try:
        loaded = materials.load(extra_dirs=[folder])
    except materials.MaterialsError as exc:
        msg = str(exc)
        assert str(path) in msg, msg
        assert name in msg or materials._key(name) in msg, msg
        return
    assert materials._key(name) in loaded[kind]
