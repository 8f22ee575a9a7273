"""The dry beds of a scan's cases: a settling scene (:func:`viscbridge.scenes.settling`) settled dry
and saved, cached by the bed's fields and the saved format of the ViscBridge classes (runs inside
YADE).
"""
import hashlib
import json
import os

from .cases import _BED_KEYS, normalize_case

__all__ = ['dry_bed', 'settled_bed']


def _saved_format():
    """The attribute names of the ViscBridge classes a saved bed holds: YADE's archives list every
    attribute in order, so a bed saved by a build with other attributes would not load again."""
    import yade.wrapper as yw
    classes = ('ViscBridgeTimeStepper', 'ViscBridgeGuard', 'Ip2_FrictMat_FrictMat_ViscBridgePhys',
               'Law2_ScGeom_ViscBridgePhys_HertzViscous', 'ViscBridgePhys', 'ViscBridgeImplicitSolver')
    return {c: sorted(getattr(yw, c)().dict()) for c in classes}


def _bed_path(case, cache_dir):
    # the format in the key: a bed cached by an older build is rebuilt, not loaded and refused
    identity = dict({k: case[k] for k in _BED_KEYS}, savedFormat=_saved_format())
    key = hashlib.sha1(json.dumps(identity, sort_keys=True).encode()).hexdigest()[:16]
    return os.path.join(cache_dir, 'bed-%s.yade.gz' % key)


def dry_bed(case, cache_dir):
    """Path of the case's bed settled dry (built and cached on first use)."""
    case = normalize_case(case)
    return settled_bed(_bed_path(case, cache_dir), **{k: case[k] for k in _BED_KEYS})


def settled_bed(path, **settling_args):
    """Save at `path` (unless it exists) a bed of :func:`viscbridge.scenes.settling` (with
    settling_args) settled dry, and return the path."""
    from yade import O
    from .. import scenes
    if os.path.exists(path):
        return path
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    # dry, with strong contact damping (en = 0.2) so that the column comes to rest quickly
    scene = scenes.settling(viscosity=0.0, en=0.2, dt=None, trackEnergy=False, guard=False, **settling_args)
    # settle: the column falls in ~0.05 s; continue until the motion has died down
    scene.run(duration=0.08, stop_when_unstable=False)
    for _ in range(10):
        if scene.kinetic_energy() < 1e-4 * max(scene.released_energy(), 1e-30):
            break
        scene.run(duration=0.02, stop_when_unstable=False)
    # a name of this process's own: parallel cases of one scan may build the same bed at once, and a
    # shared temporary would be renamed under another writer (a truncated bed for whoever loads it)
    tmp = '%s.%d.part.yade.gz' % (path, os.getpid())
    O.save(tmp)
    os.replace(tmp, path)
    return path
