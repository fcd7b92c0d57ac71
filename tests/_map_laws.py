"""The four speed laws a map's tests sweep, each with its scene fields and its swept axis
(6 values): the maps' default excess-gas estimate over U/U_mf, and a fixed, a lognormal and
a Maxwellian law over their own parameter."""

import numpy as np

#: speed law -> (its scene fields, its swept axis)
LAWS = {
    "excess-gas": ({}, dict(U_Umf=np.linspace(1.2, 8.0, 6))),
    "fixed": ({"speed": "fixed", "u0": 0.1}, dict(u0=np.geomspace(0.01, 2.0, 6))),
    "lognormal": ({"speed": "lognormal", "u0": 0.1, "sigma_ln": 0.5},
                  dict(u0=np.geomspace(0.01, 2.0, 6))),
    "maxwellian": ({"speed": "maxwellian", "granular_temperature": 0.01},
                   dict(granular_temperature=np.geomspace(1e-4, 1.0, 6))),
}
