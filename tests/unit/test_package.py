"""The viscbridge package without YADE: the modules that need no YADE import without it, and the
modules split into packages (criteria → planning, scan) keep every name they had, so that code,
scripts and notebooks written against them run unchanged.  (viscbridge.scenes and engine_list, which
need YADE: tests/yade/test_scenes.py.)"""
import importlib
import os
import subprocess
import sys

import pytest

import viscbridge

#: The names of the modules before the split (their own definitions; imported standard modules and
#: helpers left out).
NAMES_BEFORE = {
    'viscbridge.criteria': """
    Bound CAPILLARY_MODELS HERTZ_TC INTEGRATIONS LATTICE_BONDS NORMAL_MODELS RAYLEIGH_A RAYLEIGH_B
    ROT TANGENTIAL_MODELS TimeStepCriteria _bond_block _capillary _g _gap_and_volume _geometry
    _goldman _poisson _regime _registry _tangential_weight capillary_force capillary_max_stiffness
    capillary_stiffness critical_dt effective_shear effective_young hertz_collision_time
    hertz_max_overlap hertz_normal_stiffness lattice_limit mindlin_tangential_stiffness
    network_limit normal_coefficient pair_limit pitois_volume_factor rayleigh_dt rayleigh_time
    reduced_mass reduced_radius restitution_damping_ratio rupture_distance sphere_mass sphere_volume
    tangential_coefficients viscous_decay_time viscous_step_coefficient""",
    'viscbridge.scan': """
    CASE_DEFAULTS CASE_FIELDS CasesFailed Field Interval JOB_SCRIPT ResultsFile SLURM_TEMPLATE
    ScanError _BED_KEYS _COMMANDS _KEY_OMITS_AT_DEFAULT _LIQUID_KEYS _Trial _add_case_options
    _allowed _bed_path _cases_from_args _check_known _check_with_ip2 _checked _collect _describe
    _failures _interrupt _ip2_models _ip2_range _log_error _number _parse_assignments _parse_value
    _progress _registry _run _run_batch _saved_format _scan_dir _signals _slurm _stop_group _table
    _table_value bisect_threshold build_parser case_key collect criteria dry_bed fields_help
    find_critical_dt grid main normalize_case one_at_a_time period_two_ringing run_cases settled_bed
    slurm_script unique_cases write_table""",
    'viscbridge.vtk': """
    BridgeSeries CELL_FIELDS _SERIES _array _bridges bridge_recorder write_bridges""",
}


@pytest.mark.parametrize('module', sorted(NAMES_BEFORE))
def test_every_name_of_a_split_module_is_still_there(module):
    m = importlib.import_module(module)
    assert [n for n in NAMES_BEFORE[module].split() if not hasattr(m, n)] == []


def yade_free_modules():
    """Every module of the package except those that need YADE to import (found on disk: importing a
    package to list it would run it)."""
    needs_yade = ('viscbridge.engine_list', 'viscbridge.scan_job', 'viscbridge.scenes', 'viscbridge.scan.__main__')
    top = os.path.dirname(viscbridge.__file__)
    out = []
    for root, _dirs, files in os.walk(top):
        package = 'viscbridge' + root[len(top):].replace(os.sep, '.')
        for f in sorted(files):
            if f.endswith('.py'):
                name = package if f == '__init__.py' else package + '.' + f[:-3]
                if not name.startswith(needs_yade):
                    out.append(name)
    return out


def test_the_yade_free_modules_import_without_yade():
    """In a fresh interpreter with only the package on the path: none of them loads YADE."""
    modules = yade_free_modules()
    assert {'viscbridge.criteria', 'viscbridge.planning.critical', 'viscbridge.scan.cli', 'viscbridge.measures',
            'viscbridge.analysis', 'viscbridge.vtk', 'viscbridge.scan.job'} <= set(modules)
    code = 'import importlib, sys\nfor m in sys.argv[1:]: importlib.import_module(m)\nprint("yade" in sys.modules)'
    py = os.path.dirname(os.path.dirname(viscbridge.__file__))
    out = subprocess.run([sys.executable, '-c', code, *modules], capture_output=True, text=True, timeout=60,
                         env={'PYTHONPATH': py, 'PATH': '/usr/bin:/bin'})
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == 'False'


def test_criteria_is_the_planning_package():
    from viscbridge import criteria, planning
    for name in planning.__all__:
        assert getattr(criteria, name) is getattr(planning, name), name
    assert criteria.__all__ == planning.__all__
