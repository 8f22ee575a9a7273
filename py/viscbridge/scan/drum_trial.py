"""One drum case (kind='drum', :data:`~.cases.DRUM_DEFAULTS`), inside YADE: the drum of
:func:`viscbridge.scenes.drum` built from the case and turned for its revolutions, while an
:class:`~viscbridge.analysis.agglomerate_history.AgglomerateHistory` records the agglomerates every
:data:`RECORD_EVERY` revolution into ``<scanDir>/case-KEY/agglomerates.csv`` with its sidecar (so
that ``python3 -m viscbridge.analysis compare DIR/case-*/`` overlays the cases); the case's result
is the last row's measures (:func:`run_drum_case`).  :func:`drum_arguments` is plain Python.
"""
import math
import os
import time

from .cases import DRUM_DEFAULTS, DRUM_SPRAY_KEYS, case_key, kind_of, normalize_case

__all__ = ['RECORD_EVERY', 'MEASURES', 'drum_arguments', 'history_dir', 'run_drum_case']

RECORD_EVERY = 1 / 16
"""Revolutions between two rows of a case's agglomerate history."""

MEASURES = ('spheres', 'agglomerates', 'granules', 'granulated_mass_fraction', 'granule_d50', 'granule_mean_size',
            'd50', 'largest', 'largest_mass_fraction', 'coordination', 'liquid_cov', 'bridges', 'liquid_sprayed')
"""The columns of the history's last row that a drum case's result holds (their meanings:
viscbridge.analysis.agglomerate_history.COLUMN_INFO); nan is written as null."""


def _drum_case(func, case):
    case = normalize_case(case)
    if kind_of(case) != 'drum':
        raise ValueError("%s: the case's kind=%r is out of range; allowed: 'drum'" % (func, kind_of(case)))
    return case


def drum_arguments(case):
    """The arguments of :func:`viscbridge.scenes.drum` for a drum case: every field but
    ``revolutions`` and the spray's, and the speed as ``rpm`` when it is set (> 0), else as ``froude``."""
    case = _drum_case('drum_arguments', case)
    args = {k: case[k] for k in DRUM_DEFAULTS if k not in ('revolutions', 'froude', 'rpm') + tuple(DRUM_SPRAY_KEYS)}
    speed = 'rpm' if case['rpm'] > 0 else 'froude'
    args[speed] = case[speed]
    return args


def history_dir(scan_dir, case):
    """Where the case's agglomerate history goes: ``<scan_dir>/case-KEY`` (beside its log case-KEY.log)."""
    return os.path.join(scan_dir, 'case-%s' % case_key(case))


def _plain(value):
    """A measure for JSON: nan as None (results.jsonl stays strict JSON; an empty cell in results.csv)."""
    return None if isinstance(value, float) and math.isnan(value) else value


def run_drum_case(case, scan_dir):
    """Run one drum case (inside YADE; O is reset) and return its result: the case, its ``key``, the
    last row's :data:`MEASURES`, the agglomerates ``broken`` and ``merged`` summed over the run, the
    simulated time ``t_end`` [s] and ``steps``, the drum's ``period`` [s] and speed as it turned
    (``drum_froude``, ``drum_rpm`` [1/min]), the ``history`` CSV (relative to `scan_dir`) and
    ``wall_seconds``."""
    from yade import O
    from .. import scenes
    from ..analysis.agglomerate_history import AgglomerateHistory
    case = _drum_case('run_drum_case', case)
    started = time.time()
    d = scenes.drum(**drum_arguments(case))
    if case['sprayRel'] > 0:
        d.spray(**{argument: case[field] for field, argument in DRUM_SPRAY_KEYS.items()})
    history = AgglomerateHistory(os.path.join(history_dir(scan_dir, case), 'agglomerates.csv'), drum=d,
                                 params={k: case[k] for k in ('revolutions',) + tuple(DRUM_SPRAY_KEYS)})
    O.engines = O.engines + [history.recorder(virtPeriod=d.period * RECORD_EVERY)]
    d.run(revolutions=case['revolutions'])
    last = history.record()
    return dict(case, key=case_key(case), **{m: _plain(last[m]) for m in MEASURES},
                broken=sum(r['broken'] for r in history.rows), merged=sum(r['merged'] for r in history.rows),
                t_end=last['t'], steps=last['iter'], period=d.period, drum_froude=d.params['froude'],
                drum_rpm=d.params['rpm'], history=os.path.relpath(history.csv_path, scan_dir),
                wall_seconds=time.time() - started)
