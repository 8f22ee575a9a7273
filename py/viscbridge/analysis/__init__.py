"""Analyses of a scene: where what is computed *from* a scene's measures goes — e.g. the agglomerates
(connected components of the bridge graph), their statistics over a run, and several runs compared.

One module per analysis (``analysis/agglomerates.py``, ...), built on :mod:`viscbridge.measures`
(what is read off a scene: energies, bridges, their end points) and, like it, importing YADE only
inside the functions that read ``O``, so that the pure parts can be tested without YADE.  A settling
run logs an analysis by adding it to ``Settling.record`` (:mod:`viscbridge.scenes.runner`).
Analyses: :mod:`.agglomerates` (``viscbridge.agglomerates()``: the connected components of the
bridge graph, their sizes, coordination, mass and liquid), :mod:`.agglomerate_history` (their
statistics over a run: a CSV row per record, the run's parameters in a sidecar, a plot) and
:mod:`.comparison` (:func:`compare`: the histories of several runs in one figure; also
``python3 -m viscbridge.analysis compare``, :mod:`.cli`).
"""
from .comparison import compare

__all__ = ['compare']
