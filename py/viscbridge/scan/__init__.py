"""Critical time step of settling cases by bisection, and granulation drums turned for some
revolutions: parameter scans that resume and run in parallel (yade-batch locally, or as a Slurm
array job on a cluster).

The settling case (one row of a scan; the default kind): a bed of spheres settled dry in a walled column
(:func:`viscbridge.scenes.settling`), then wetted — every contact becomes a liquid bridge at S_min,
the stiffest viscous state — and released under gravity with small random velocities.  It runs
`steps` steps at a fixed Δt.  **Instability criterion** (:func:`viscbridge.measures.instability`):
the kinetic energy exceeds the initial kinetic energy plus the potential energy released since the
start, or becomes NaN/inf.  Physics cannot do that; an explicit scheme above its stable step does,
because the unstable mode grows by a factor $|1 − Δt/t_v|$ > 1 per step.

The drum case (``--kind drum``, :data:`DRUM_FIELDS`): :func:`viscbridge.scenes.drum` built from the
case and turned for `revolutions` (:mod:`.drum_trial`); its agglomerate history goes to
``DIR/case-KEY/agglomerates.csv`` (with the run's parameters in ``agglomerates.json``: ``python3 -m
viscbridge.analysis compare DIR/case-*/`` overlays the cases) and its result row holds the final
agglomerates, granules, granulated_mass_fraction, granule_d50, largest, coordination, liquid_cov, ...

Command line (inside the environment, e.g. ``./yadew sh python3 -m viscbridge.scan ...``)::

    python3 -m viscbridge.scan run    DIR [--vary viscosity=1e-3,1,100] [--base radius=0.5e-3 ...] [-j 2]
    python3 -m viscbridge.scan run    DIR --kind drum --base n=300 revolutions=2 --vary viscosity=5,50
    python3 -m viscbridge.scan table  DIR ...same case options...     # only write DIR/cases.table
    python3 -m viscbridge.scan collect DIR                             # DIR/results.csv from results.jsonl
    python3 -m viscbridge.scan slurm  DIR                              # DIR/scan.sbatch for the same table

``--help`` lists the case fields of each kind (:data:`CASE_FIELDS`, :data:`DRUM_FIELDS`). Every case
is checked before anything runs; equal cases (``viscosity=1`` and ``viscosity=1.0``) run once. Every
finished case is appended to ``DIR/results.jsonl`` at once; re-running skips finished cases, so a
killed or interrupted scan resumes where it stopped. ``DIR/cases.table`` holds the whole scan,
``DIR/todo.table`` the cases yade-batch was given; per-case logs are ``DIR/case-KEY.log``. Cases
that fail are listed with their error and make the command exit non-zero.

Modules: :mod:`.cases` (fields, checks, keys, sets of cases, of each kind), :mod:`.bisection`,
:mod:`.beds` (the cached dry beds), :mod:`.trial` (one settling case inside YADE),
:mod:`.drum_trial` (one drum case), :mod:`.table` (the yade-batch table and :data:`~viscbridge.scan.table.JOB_SCRIPT`, the
job script :mod:`.job`), :mod:`.results`, :mod:`.batch` (yade-batch runs), :mod:`.slurm`,
:mod:`.errors` and :mod:`.cli` (``__main__``).
"""
from .. import _registry, criteria  # noqa: F401  (names of this module before the split)
from ..measures import period_two_ringing  # noqa: F401  (its name here before measures.py)
from .batch import _failures, _interrupt, _log_error, _progress, _run_batch, _signals, _stop_group, run_cases  # noqa: F401
from .beds import _bed_path, _saved_format, dry_bed, settled_bed  # noqa: F401
from .bisection import bisect_threshold
from .cases import (_BED_KEYS, _KEY_OMITS_AT_DEFAULT, _LIQUID_KEYS, CASE_DEFAULTS, CASE_FIELDS, DRUM_DEFAULTS, DRUM_SPRAY_KEYS,  # noqa: F401
                    DRUM_FIELDS, KINDS, Field, Interval, Kind, _allowed, _check_known, _check_with_ip2, _checked,
                    _describe, _ip2_models, _ip2_range, kind_of,
                    _number, case_key, grid, normalize_case, one_at_a_time, unique_cases)
from .cli import (_COMMANDS, _add_case_options, _cases_from_args, _collect, _parse_assignments,  # noqa: F401
                  _parse_value, _run, _slurm, _table, build_parser, fields_help, main)
from .errors import CasesFailed, ScanError
from .results import ResultsFile, _scan_dir, collect  # noqa: F401
from .slurm import SLURM_TEMPLATE, slurm_script  # noqa: F401
from .table import JOB_SCRIPT, _table_value, write_table  # noqa: F401
from .trial import _Trial, find_critical_dt  # noqa: F401
from .drum_trial import drum_arguments, run_drum_case

__all__ = ['CASE_DEFAULTS', 'CASE_FIELDS', 'DRUM_DEFAULTS', 'DRUM_FIELDS', 'DRUM_SPRAY_KEYS', 'KINDS', 'Kind', 'Field', 'Interval',
           'ScanError', 'CasesFailed', 'kind_of', 'normalize_case', 'case_key', 'unique_cases', 'one_at_a_time', 'grid',
           'bisect_threshold', 'find_critical_dt', 'drum_arguments', 'run_drum_case', 'ResultsFile', 'write_table',
           'run_cases', 'collect', 'slurm_script', 'build_parser', 'main']
