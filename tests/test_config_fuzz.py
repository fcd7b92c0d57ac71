"""Fuzzing map configurations: whatever a TOML file holds, parse_config returns a
config or raises ConfigError (a ValueError) that names the file and the table; nothing else
escapes from inside the package."""

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from agglomtool._fields import DEFAULTS, FIELD_META
from agglomtool.maps.config import ConfigError, parse_config

FIELDS = list(DEFAULTS) + ["nonsense", "T_", ""]
SCALARS = st.one_of(
    st.none(), st.booleans(), st.integers(-10**6, 10**6),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["air", "water", "silica-sand", "ilmenite", "5 um", "850 degC", "1.5 bar",
                     "5 kg", "umm", "", "paper", "auto", "-1 um", "nan m", "1e400 m"]),
)
VALUES = st.recursive(SCALARS, lambda inner: st.one_of(
    st.lists(inner, max_size=4),
    st.dictionaries(st.sampled_from(["start", "stop", "num", "log", "step"]), inner,
                    max_size=4)), max_leaves=8)
TABLES = st.dictionaries(st.sampled_from(FIELDS), VALUES, max_size=4)
DOCS = st.fixed_dictionaries({}, optional={
    "scene": TABLES, "grid": TABLES,
    "options": st.dictionaries(st.sampled_from(["nodes", "chunks", "other"]), SCALARS,
                               max_size=2),
    "extra": TABLES})


def _strip_none(x):
    if isinstance(x, dict):
        return {k: _strip_none(v) for k, v in x.items() if v is not None}
    if isinstance(x, list):
        return [_strip_none(v) for v in x if v is not None]
    return x


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(DOCS)
def test_any_config_parses_or_names_the_problem(doc):
    doc = _strip_none(doc)  # TOML has no null
    try:
        cfg = parse_config(doc, "fuzz.toml")
    except ConfigError as exc:
        assert str(exc).startswith("fuzz.toml: "), str(exc)
        return
    for key, axis in cfg.grid.items():
        assert len(axis) >= 1
        if key in FIELD_META:
            assert all(v == v for v in axis)  # no NaN accepted into a grid


def test_a_corpus_of_real_mistakes(tmp_path):
    from agglomtool.maps.config import load_config

    corpus = {
        "units": '[scene]\nh0 = "5 kg"\n[grid]\nT = [1000.0]',
        "num1": '[grid]\nT = { start = 900.0, stop = 1200.0, num = 1 }',
        "chunks": '[grid]\nT = [1000.0]\n[options]\nchunks = true',
        "nested": "[grid]\nT = " + "[" * 60 + "1.0" + "]" * 60,
        "bad_utf8": None,
        "typo": '[scen]\nT = 1000.0',
    }
    for name, text in corpus.items():
        path = tmp_path / f"{name}.toml"
        if text is None:
            path.write_bytes(b"[grid]\nT = [1000.0]\n# \xff\xfe\n")
        else:
            path.write_text(text)
        try:
            load_config(path)
        except ConfigError as exc:
            assert str(path) in str(exc), (name, str(exc))
        else:
            raise AssertionError(f"{name}: accepted")


VALID = (Path(__file__).resolve().parent.parent / "examples" / "configs"
         / "granulator_window.toml").read_bytes()
#: Bytes that make TOML go wrong: brackets, quotes, equals signs, newlines, escapes,
#: bytes that are not UTF-8.
NOISE = st.binary(max_size=6) | st.sampled_from(
    [b"[", b"]", b"=", b'"', b"'", b"\n", b"{", b"}", b",", b"\\", b"\xff", b"[[", b"#"])


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(st.integers(0, len(VALID)), st.integers(0, 4), NOISE), max_size=4))
def test_any_damaged_file_loads_or_names_the_file(tmp_path, edits):
    """A real configuration file with bytes cut out and spliced in, read from disk by
    load_config: whatever the TOML reader makes of it (a syntax error, bad UTF-8, a key
    defined twice, or a different valid document) reaches the user as a ConfigError that
    names the file, or as a configuration. (The fuzz test above starts from parsed
    documents, so it never reaches the file reader.)"""
    from agglomtool.maps.config import load_config

    text = VALID
    for at, cut, noise in edits:
        text = text[:at] + noise + text[at + cut:]
    path = tmp_path / "damaged.toml"
    path.write_bytes(text)
    try:
        load_config(path)
    except ConfigError as exc:
        assert str(exc).startswith(f"{path}: "), str(exc)
