"""Time-step planning for ViscBridge simulations, in plain Python (no YADE needed): the first and
documented name of :mod:`viscbridge.planning`.

The code lives in ``viscbridge.planning``, one concept per module (materials, viscous, capillary,
bounds, lattice, report, critical, inputs); this module re-exports every name it had when it held
all of it, so that ``from viscbridge import criteria; criteria.critical_dt(...)`` and
``from viscbridge.criteria import critical_dt`` keep working.  See ``help(viscbridge.planning)``.
"""
from . import _registry  # noqa: F401  (was a name of this module)
from .planning import *  # noqa: F401,F403
from .planning import __all__  # noqa: F401
from .planning import HERTZ_TC, LATTICE_BONDS, RAYLEIGH_A, RAYLEIGH_B, ROT  # noqa: F401
from .planning.capillary import _capillary  # noqa: F401
from .planning.inputs import _gap_and_volume, _geometry, _poisson  # noqa: F401
from .planning.lattice import _bond_block  # noqa: F401
from .planning.report import _g, _regime  # noqa: F401
from .planning.viscous import _goldman, _tangential_weight  # noqa: F401
