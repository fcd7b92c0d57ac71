"""Melt viscosity models written a second time, for the tests, without the package.

Written for ``tests/test_properties_liquids.py`` from the published equations (cited at each
function), sharing no code or data with ``agglomtool.properties``: the molar masses come
from IUPAC's standard atomic weights typed below (the package takes its own from the
``chemicals`` library), the compositions are summed in a different order, and every
coefficient was typed from the sources, not copied from the package. The tests compare the
package with these functions where the old suite compared it with numbers from a scratch
script that was never committed; run this file to print those numbers::

    python3 tests/independent_melts.py

The molar masses use the same atomic weights as the package's (IUPAC 2001, the table
``chemicals`` holds), typed here from IUPAC's publication: the two codings then differ only in
the order of their arithmetic, a few units of 1e-15 in log10 eta. (With IUPAC's abridged
five-figure weights instead they differ by up to 6e-5 decades on the melts tested.)
"""

import math

#: Standard atomic weights, IUPAC 2001 (Coplen, Pure Appl. Chem. 2001, 73:667-683).
ATOMIC_WEIGHT = {"H": 1.00794, "O": 15.9994, "Na": 22.989770, "Mg": 24.3050,
                 "Al": 26.981538, "Si": 28.0855, "P": 30.973761, "K": 39.0983, "Ca": 40.078,
                 "Ti": 47.867, "Mn": 54.938049, "Fe": 55.845}
#: Oxide -> (cation, cations per formula unit, oxygens per formula unit).
OXIDES = {"SiO2": ("Si", 1, 2), "TiO2": ("Ti", 1, 2), "Al2O3": ("Al", 2, 3),
          "Fe2O3": ("Fe", 2, 3), "FeO": ("Fe", 1, 1), "MnO": ("Mn", 1, 1),
          "MgO": ("Mg", 1, 1), "CaO": ("Ca", 1, 1), "Na2O": ("Na", 2, 1), "K2O": ("K", 2, 1),
          "P2O5": ("P", 2, 5), "H2O": ("H", 2, 1)}


def oxide_mass(oxide):
    """Molar mass of an oxide [g/mol]."""
    cation, n, n_o = OXIDES[oxide]
    return n * ATOMIC_WEIGHT[cation] + n_o * ATOMIC_WEIGHT["O"]


def moles(wt):
    """Mole fractions of the oxides of a wt % composition (any total)."""
    n = {k: v / oxide_mass(k) for k, v in wt.items()}
    total = math.fsum(n.values())
    return {k: v / total for k, v in n.items()}


def grd_log10(wt, T):
    """log10 viscosity [Pa s] by Giordano, Russell and Dingwell (2008), EPSL 271:123-134,
    their Eq. 1 and Table 1 (no fluorine): log eta = -4.55 + B / (T - C), B and C in mol %."""
    wt = dict(wt)
    if "Fe2O3" in wt:  # total iron as FeO: two FeO per Fe2O3
        wt["FeO"] = wt.get("FeO", 0.0) + wt.pop("Fe2O3") * 2 * oxide_mass("FeO") / oxide_mass(
            "Fe2O3")
    x = moles(wt)

    def m(*names):
        return 100.0 * sum(x.get(k, 0.0) for k in names)

    h2o = m("H2O")
    fm = m("FeO", "MnO", "MgO")
    nk = m("Na2O", "K2O")
    B = (159.56 * m("SiO2", "TiO2") - 173.34 * m("Al2O3") + 72.13 * m("FeO", "MnO", "P2O5")
         + 75.69 * m("MgO") - 38.98 * m("CaO") - 84.08 * (m("Na2O") + h2o)
         + 141.54 * (h2o + math.log(1.0 + h2o))
         - 2.43 * m("SiO2", "TiO2") * fm
         - 0.91 * m("SiO2", "Al2O3", "TiO2", "P2O5") * (nk + h2o)
         + 17.62 * m("Al2O3") * nk)
    C = (2.75 * m("SiO2") + 15.72 * m("TiO2", "Al2O3") + 8.32 * fm + 10.20 * m("CaO")
         - 12.29 * nk - 99.54 * math.log(1.0 + h2o)
         + 0.30 * (m("Al2O3") + fm + m("CaO") - m("P2O5")) * (nk + h2o))
    return -4.55 + B / (T - C)


#: Urbain's coefficients as tabulated by Mills (Slag Atlas, 1995, ch. 9): for each cation
#: group, B_k = a_k + b_k alpha + c_k alpha^2 (k = 0..3).
URBAIN_A = (13.2, 30.5, -40.4, 60.8)
URBAIN_B = {"Ca": (41.5, -117.2, 232.1, -156.4), "Mg": (15.9, -54.1, 138.0, -99.8),
            "Mn": (20.0, 26.0, -110.3, 64.3)}
URBAIN_C = {"Ca": (-45.0, 130.0, -298.6, 213.6), "Mg": (-18.6, 33.0, -112.0, 97.6),
            "Mn": (-25.6, -56.0, 186.2, -104.6)}


def urbain_mills_log10(wt, T):
    """log10 viscosity [Pa s] by Urbain's model with Mills's parameters, for a CaO-MgO-
    Al2O3-SiO2 slag: eta [dPa s] = A T exp(1000 B / T), ln A = -(0.29 B + 11.57);
    X_G = SiO2, X_A = Al2O3, X_M = CaO + MgO, normalised to sum to 1; alpha = X_M/(X_M+X_A);
    B averaged over the Ca and Mg groups with the mole fractions of CaO and MgO."""
    x = moles(wt)
    xg, xa, xm = x.get("SiO2", 0.0), x.get("Al2O3", 0.0), x.get("CaO", 0.0) + x.get("MgO", 0.0)
    s = xg + xa + xm
    xg, xa, xm = xg / s, xa / s, xm / s
    alpha = xm / (xm + xa)
    share = {"Ca": x.get("CaO", 0.0), "Mg": x.get("MgO", 0.0)}
    B = 0.0
    for group, w in share.items():
        Bk = [URBAIN_A[k] + URBAIN_B[group][k] * alpha + URBAIN_C[group][k] * alpha**2
              for k in range(4)]
        B += w / sum(share.values()) * sum(Bk[k] * xg**k for k in range(4))
    ln_eta_dpas = -(0.29 * B + 11.57) + math.log(T) + 1000.0 * B / T
    return (ln_eta_dpas + math.log(0.1)) / math.log(10.0)


def riboud_log10(wt, T):
    """log10 viscosity [Pa s] by Riboud et al. (1981), as reviewed by Mills (Slag Atlas,
    1995): eta = A T exp(B / T), ln A = -19.81 + 1.73 X_C + 5.82 X_CaF2 + 7.02 X_N
    - 35.76 X_Al2O3, B = 31140 - 23896 X_C - 46356 X_CaF2 - 39159 X_N + 68833 X_Al2O3, for a
    slag without CaF2, Fe2O3 or B2O3 (X_C = CaO + MgO + FeO + MnO, X_N = Na2O + K2O)."""
    x = moles(wt)
    xc = sum(x.get(k, 0.0) for k in ("CaO", "MgO", "FeO", "MnO"))
    xn = x.get("Na2O", 0.0) + x.get("K2O", 0.0)
    xal = x.get("Al2O3", 0.0)
    ln_A = -19.81 + 1.73 * xc + 7.02 * xn - 35.76 * xal
    B = 31140.0 - 23896.0 * xc - 39159.0 * xn + 68833.0 * xal
    return (ln_A + math.log(T) + B / T) / math.log(10.0)


if __name__ == "__main__":
    melt_a = {"K2O": 20.0, "CaO": 10.0, "SiO2": 70.0}
    bf_slag = {"CaO": 40.0, "SiO2": 36.0, "Al2O3": 14.0, "MgO": 10.0}
    for T in (1073.15, 1173.15, 1273.15):
        print(f"GRD, K2O-CaO-SiO2 melt, {T} K: log10 eta = {grd_log10(melt_a, T):.4f}")
    print(f"blast-furnace slag, 1773.15 K: Urbain-Mills {urbain_mills_log10(bf_slag, 1773.15):.4f}"
          f", Riboud {riboud_log10(bf_slag, 1773.15):.4f}, GRD {grd_log10(bf_slag, 1773.15):.4f}")
