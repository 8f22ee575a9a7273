"""Analyses of a scene: where what is computed *from* a scene's measures goes — e.g. the agglomerates
(connected components of the bridge graph) and their size distribution over a run.

One module per analysis (``analysis/agglomerates.py``, ...), built on :mod:`viscbridge.measures`
(what is read off a scene: energies, bridges, their end points) and, like it, importing YADE only
inside the functions that read ``O``, so that the pure parts can be tested without YADE.  A settling
run logs an analysis by adding it to ``Settling.record`` (:mod:`viscbridge.scenes.runner`).
Analyses: :mod:`.agglomerates` (``viscbridge.agglomerates()``: the connected components of the
bridge graph, their sizes, coordination, mass and liquid).
"""
