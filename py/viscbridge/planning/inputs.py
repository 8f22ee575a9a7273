"""What the planning functions accept: the model names of the C++ registry and the argument checks
they share (plain Python).

Every failure is a ValueError naming the parameter, its value and the range (see ``_checks``).
"""
from .._checks import in_range, number, positive, reject
from .. import _registry

__all__ = ['NORMAL_MODELS', 'TANGENTIAL_MODELS', 'CAPILLARY_MODELS', 'INTEGRATIONS']

# The model names are those the C++ registry lists (core/models/Registry.hpp, via _registry.py).
#: The names ``normal_model`` (the Ip2's ``normalModel``) accepts.
NORMAL_MODELS = _registry.SLOTS['normalModel']['models']
#: The names ``tangential_model`` (the Ip2's ``tangentialModel``) accepts.
TANGENTIAL_MODELS = _registry.SLOTS['tangentialModel']['models']
#: The names ``capillary_model`` (the Ip2's ``capillaryModel``) accepts.
CAPILLARY_MODELS = _registry.SLOTS['capillaryModel']['models']
#: The schemes ``integration`` accepts (the law's ``integration``).
INTEGRATIONS = _registry.INTEGRATIONS


def _poisson(func, value, name='poisson'):
    allowed = '(-1, 0.5)'
    x = number(func, name, value, allowed)
    if not -1 < x < 0.5:
        reject(func, name, value, allowed)
    return x


def _gap_and_volume(func, r_bar, particle_volume, s_min, s_min_rel, bridge_volume, bridge_volume_rel):
    """S_min and V as the Ip2 fills them in (sMin or sMinRel · r̄, bridgeVolume or bridgeVolumeRel × the
    mean particle volume), checked."""
    if s_min is None:
        smin = in_range(func, 's_min_rel', s_min_rel, 0, 1, lo_open=True, unit=' (S_min / r̄)') * r_bar
    else:
        smin = positive(func, 's_min', s_min, ' [m]')
    if bridge_volume is None:
        vrel = in_range(func, 'bridge_volume_rel', bridge_volume_rel, 0, 1, lo_open=True,
                        unit=' (fraction of the particle volume)')
        volume = vrel * particle_volume
    else:
        volume = positive(func, 'bridge_volume', bridge_volume, ' [m³]')
    return smin, volume


def _geometry(func, radius1, radius2, wall):
    """(r1, r2) checked; r2 is None against a wall, r1 when radius2 is None (identical spheres)."""
    r1 = positive(func, 'radius1' if func != 'critical_dt' else 'radius', radius1, ' [m]')
    if not isinstance(wall, bool):
        reject(func, 'wall', wall, 'True or False')
    if wall:
        if radius2 is not None:
            reject(func, 'radius2', radius2, 'None when wall=True (a wall has no radius)')
        return r1, None
    r2 = r1 if radius2 is None else positive(func, 'radius2', radius2, ' [m]')
    return r1, r2
