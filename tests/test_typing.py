"""What a user's type checker sees: the package says it is typed (PEP 561), and the core's
inputs take floats and arrays (``at.Particle(d=1e-3, rho=2650.0)`` type-checks) while their
fields, checked, are arrays."""

import typing
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

import agglomtool as at


def test_the_package_is_marked_typed():
    # PEP 561: without this file a type checker ignores the package's annotations. The
    # wheel ships every file of the package folder (pyproject's hatch wheel target).
    assert (Path(at.__file__).parent / "py.typed").is_file()


def test_inputs_take_array_likes_and_hold_arrays():
    for cls in (at.Particle, at.Liquid, at.Gas, at.Bed):
        params = typing.get_type_hints(cls.__init__)
        fields = typing.get_type_hints(cls)
        for name, hint in fields.items():
            if hint in (np.ndarray, np.ndarray | None):
                assert params[name] in (ArrayLike, ArrayLike | None), (cls.__name__, name)
    p = at.Particle(d=1e-3, rho=2650.0)
    assert isinstance(p.d, np.ndarray) and isinstance(p.h0, np.ndarray)


def test_scene_defaults_are_typed_as_the_scene_fields():
    """DEFAULTS (read by the Scene, the CLI's help and the config files) is a TypedDict
    whose keys and types are the Scene's fields and annotations."""
    import dataclasses

    from agglomtool._fields import DEFAULTS, SceneDefaults

    scene_types = typing.get_type_hints(at.Scene)
    fields = [f.name for f in dataclasses.fields(at.Scene)]
    assert list(DEFAULTS) == list(typing.get_type_hints(SceneDefaults)) == fields
    assert typing.get_type_hints(SceneDefaults) == {k: scene_types[k] for k in fields}
