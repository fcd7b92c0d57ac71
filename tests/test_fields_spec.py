"""The light field specification (what the command line states) agrees with the modules
that own each list: the Scene's defaults, the tier registry, the speed models, the drag slip
modes and the U_mf correlations."""

import dataclasses

from agglomtool import _fields
from agglomtool.api import MODES
from agglomtool.bed.speeds import SPEED_FAMILIES
from agglomtool.pair import DRAG_SLIP_MODES
from agglomtool.properties import umf_methods
from agglomtool.scene import Scene


def test_every_scene_field_has_a_spec_and_a_default():
    fields = dataclasses.fields(Scene)
    assert [f.name for f in fields] == list(_fields.DEFAULTS)  # same fields, same order
    assert Scene().values() == {**_fields.DEFAULTS, "speed": "excess-gas"}


def test_allowed_names_are_the_registries():
    assert tuple(_fields.CHOICES["mode"]) == tuple(MODES)
    assert tuple(_fields.CHOICES["speed"]) == tuple(SPEED_FAMILIES)
    assert tuple(_fields.CHOICES["drag_slip"]) == tuple(DRAG_SLIP_MODES)
    assert tuple(_fields.CHOICES["umf_method"]) == tuple(umf_methods())


def test_every_field_is_numeric_or_named_once():
    names = set(_fields.DEFAULTS) - {"body_forces"}
    assert names == set(_fields.NUMERIC_FIELDS) | set(_fields.CATEGORICAL_FIELDS)
    assert not set(_fields.NUMERIC_FIELDS) & set(_fields.CATEGORICAL_FIELDS)
    assert set(_fields.FIELD_META) == set(_fields.NUMERIC_FIELDS)
