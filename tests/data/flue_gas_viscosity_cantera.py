"""The flue gas's viscosity by Cantera, the reference number pinned in
tests/test_properties_gas.py::test_flue_gas_viscosity_matches_cantera_and_coolprop.

Cantera is not a dependency of agglomtool or of its tests (a large library for one number),
so the test holds the number this script prints; rerun it with::

    python3 -m pip install cantera && python3 tests/data/flue_gas_viscosity_cantera.py

Made with Cantera 3.2.0 and its bundled GRI-Mech 3.0 mechanism (gri30.yaml, whose transport
data hold the four species), mixture-averaged transport (Wilke's mixing rule on kinetic-theory
pure-component viscosities); it printed 4.35977e-05 Pa s.
"""

import cantera as ct

gas = ct.Solution("gri30.yaml")
gas.transport_model = "mixture-averaged"
gas.TPX = 1073.15, 1e5, "N2:0.75, CO2:0.15, H2O:0.06, O2:0.04"
print(f"Cantera {ct.__version__}, 75 N2 / 15 CO2 / 6 H2O / 4 O2 mol %, 1073.15 K, 1 bar: "
      f"mu = {gas.viscosity:.5e} Pa s")
