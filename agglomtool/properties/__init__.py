"""Property layer: gas, liquid and fluidization correlations, one function per correlation."""

from .drag import drag_force_gidaspow
from .fluidization import umf_wen_yu

__all__ = ["drag_force_gidaspow", "umf_wen_yu"]
