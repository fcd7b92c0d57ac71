"""Integer codes frozen into the compiled kernels: stage codes, path flags, and the
column of each detail. One definition for every tier (see :mod:`.outcome` for names)."""

from .outcome import DETAIL_NAMES, Path, Stage

REBOUND = int(Stage.REBOUND)
APP_VIS = int(Stage.APPROACH_VISCOUS)
APP_EN = int(Stage.APPROACH_ENERGY)
APP_ALONE = int(Stage.APPROACH_ALONE)
APP_ALONE_VIS = int(Stage.APPROACH_ALONE_VISCOUS)
CONTACT = int(Stage.CONTACT)
SEP_VIS = int(Stage.SEPARATION_VISCOUS)
SEP_EN = int(Stage.SEPARATION_ENERGY)
SEP_ALONE = int(Stage.SEPARATION_ALONE)
SEP_ALONE_VIS = int(Stage.SEPARATION_ALONE_VISCOUS)
P_APP_I = int(Path.APPROACH_I_STOPS)
P_APP_J = int(Path.APPROACH_J_STOPS)
P_SEP_I = int(Path.SEPARATION_I_STOPS)
P_SEP_J = int(Path.SEPARATION_J_STOPS)
P_NO_BRIDGE = int(Path.NO_BRIDGE)
P_BROKEN = int(Path.BRIDGE_BROKEN_AT_CONTACT)

N_DETAILS = len(DETAIL_NAMES)
_DI = {name: k for k, name in enumerate(DETAIL_NAMES)}
K_INI_I = _DI["K_ini_i"]
K_INI_J = _DI["K_ini_j"]
L_CAP_APP = _DI["L_cap_app"]
L_VIS_APP = _DI["L_vis_app"]
L_BDW_APP_I = _DI["L_bdw_app_i"]
L_BDW_APP_J = _DI["L_bdw_app_j"]
K_APP_I = _DI["K_app_i"]
K_APP_J = _DI["K_app_j"]
D_STOP_APP = _DI["D_stop_app"]
W_CONTACT = _DI["w_contact"]
L_C = _DI["L_c"]
K_SEP_I = _DI["K_sep_i"]
K_SEP_J = _DI["K_sep_j"]
CA = _DI["Ca"]
H_RUPT = _DI["h_rupt"]
L_CAP_SEP = _DI["L_cap_sep"]
L_VIS_SEP = _DI["L_vis_sep"]
L_BDW_SEP_I = _DI["L_bdw_sep_i"]
L_BDW_SEP_J = _DI["L_bdw_sep_j"]
D_STOP_SEP = _DI["D_stop_sep"]
K_FIN_I = _DI["K_fin_i"]
K_FIN_J = _DI["K_fin_j"]
ST_APP = _DI["St_app"]
W_BODY = _DI["W_body_frac"]
W_VOLCORR = _DI["W_volcorr_frac"]

__all__ = [
    "REBOUND",
    "APP_VIS",
    "APP_EN",
    "APP_ALONE",
    "APP_ALONE_VIS",
    "CONTACT",
    "SEP_VIS",
    "SEP_EN",
    "SEP_ALONE",
    "SEP_ALONE_VIS",
    "P_APP_I",
    "P_APP_J",
    "P_SEP_I",
    "P_SEP_J",
    "P_NO_BRIDGE",
    "P_BROKEN",
    "N_DETAILS",
    "K_INI_I",
    "K_INI_J",
    "L_CAP_APP",
    "L_VIS_APP",
    "L_BDW_APP_I",
    "L_BDW_APP_J",
    "K_APP_I",
    "K_APP_J",
    "D_STOP_APP",
    "W_CONTACT",
    "L_C",
    "K_SEP_I",
    "K_SEP_J",
    "CA",
    "H_RUPT",
    "L_CAP_SEP",
    "L_VIS_SEP",
    "L_BDW_SEP_I",
    "L_BDW_SEP_J",
    "D_STOP_SEP",
    "K_FIN_I",
    "K_FIN_J",
    "ST_APP",
    "W_BODY",
    "W_VOLCORR",
]
