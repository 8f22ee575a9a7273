"""Ready-made scenes: particles settling under gravity through viscous liquid bridges
(:func:`settling`), and a wet granulation drum (:func:`drum`, which returns a :class:`Drum` handle)::

    import viscbridge.scenes as scenes
    s = scenes.settling(n=300, viscosity=1.0)      # builds the scene in O
    s.run(duration=0.01)
    print(s.kinetic_energy(), s.released_energy(), s.unstable())
    csv, png = s.save('settling')                     # the logged history

The history (time, kinetic energy, released potential energy, O.energy terms, bridges, time step)
is logged with yade.plot, so ``yade.plot.plots`` and the F8 plot window work as usual.

Modules: :mod:`.construction` (:func:`settling` builds the scene), :mod:`.runner` (the
:class:`Settling` handle runs it and logs its history), :mod:`.history` (the history as CSV and
plot); the measures (:func:`instability`, :func:`capillary_input`, ...) live in
:mod:`viscbridge.measures` and are re-exported here.
"""
from .. import _checks, criteria  # noqa: F401  (names of this module before the split)
from ..engine_list import bridge_parameters, engines  # noqa: F401
from ..measures import capillary_input, instability
from .construction import _check_settling_args, _floor_of_spheres, settling  # noqa: F401
from .history import log_limits, plot_history, write_history_csv  # noqa: F401
# _log is the hook of the PyRunner Settling.run adds, 'import viscbridge.scenes; viscbridge.scenes._log()':
# scenes saved while a run was logging hold that command, so the name stays here.
from .runner import _ACTIVE, _LOG_COMMAND, Settling, _log  # noqa: F401
from .drum import Drum, drum

__all__ = ['settling', 'Settling', 'drum', 'Drum', 'instability', 'capillary_input']
