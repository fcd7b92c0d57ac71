"""Sweep options checked before any work: block sizes and store paths name the field."""

import numpy as np
import pytest

from agglomtool.maps import sweep
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)


@pytest.mark.parametrize(("chunks", "match"), [
    ({"T": 0}, r"chunks\['T'\] = 0 must be a whole number of points >= 1"),
    ({"T": -2}, r"chunks\['T'\] = -2"),
    ({"T": 1.5}, r"chunks\['T'\] = 1.5"),
    ({"T": True}, r"chunks\['T'\] = True"),
    (True, r"chunks = True must be a whole number"),
    (2.5, r"chunks = 2.5 must be a whole number"),
    ("big", r"chunks = 'big'"),
])
def test_bad_block_sizes_name_the_field(chunks, match):
    with pytest.raises(ValueError, match=match):
        sweep(SCENE, chunks=chunks, T=np.linspace(900.0, 1000.0, 3), h0=[0.2e-6, 0.3e-6])


def test_good_block_sizes_are_accepted():
    ds = sweep(SCENE, chunks={"T": 2}, compute=False, T=[900.0, 950.0, 1000.0])
    assert ds.chunks["T"] == (2, 1)
    assert sweep(SCENE, chunks=np.int64(2), compute=False, T=[900.0, 950.0]).chunks["T"] == (2,)
