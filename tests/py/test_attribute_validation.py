"""Bad parameters of the functors raise ValueError naming the parameter, its value and the allowed
range, when they are set; the previous valid value stays in place."""
import math

import pytest
from yade.wrapper import Ip2_FrictMat_FrictMat_ViscBridgePhys, Law2_ScGeom_ViscBridgePhys_HertzViscous

import viscbridge

IP2_BAD = [
    ('viscosity', -1.0, '>= 0'),
    ('viscosity', float('nan'), '>= 0'),
    ('bridgeVolume', -1e-12, '>= 0'),
    ('bridgeVolumeRel', 0.0, '(0, 1]'),
    ('contactAngle', 2.0, '[0, 1.570796327]'),
    ('contactAngle', -0.1, '[0, 1.570796327]'),
    ('sMin', -1e-9, '>= 0'),
    ('sMinRel', 0.0, '(0, 1]'),
    ('sMinRel', 2.0, '(0, 1]'),
    ('formationDistance', -1e-6, '>= 0'),
    ('en', 0.0, '(0, 1]'),
    ('en', 1.5, '(0, 1]'),
    ('normalModel', 'stokes', "'none', 'adamsPerchard', 'pitois'"),
    ('tangentialModel', 'Goldman', "'none', 'washino', 'slip', 'goldman'"),
]


@pytest.mark.parametrize('name,value,allowed', IP2_BAD)
def test_ip2_rejects_on_assignment_and_keeps_previous_value(name, value, allowed):
    ip2 = Ip2_FrictMat_FrictMat_ViscBridgePhys()
    before = getattr(ip2, name)
    with pytest.raises(ValueError) as err:
        setattr(ip2, name, value)
    msg = str(err.value)
    shown = ('%g' % value) if isinstance(value, float) else "'%s'" % value
    assert name in msg and allowed in msg and shown in msg, msg
    assert getattr(ip2, name) == before or (isinstance(before, float) and math.isnan(before))


@pytest.mark.parametrize('name,value,allowed', IP2_BAD)
def test_ip2_constructor_rejects(name, value, allowed):
    with pytest.raises(ValueError, match=name):
        Ip2_FrictMat_FrictMat_ViscBridgePhys(**{name: value})


def test_ip2_accepts_valid_values():
    ip2 = Ip2_FrictMat_FrictMat_ViscBridgePhys(viscosity=100.0, bridgeVolume=1e-12, contactAngle=math.pi / 2,
                                               sMin=1e-8, normalModel='pitois', tangentialModel='goldman', en=0.5)
    assert (ip2.viscosity, ip2.normalModel, ip2.tangentialModel, ip2.en) == (100.0, 'pitois', 'goldman', 0.5)


def test_law_integration_names():
    law = Law2_ScGeom_ViscBridgePhys_HertzViscous()
    assert law.integration == 'explicit'
    with pytest.raises(ValueError, match="integration='semi'.*'explicit'"):
        law.integration = 'semi'
    assert law.integration == 'explicit'


def test_engines_rejects_unknown_effects():
    with pytest.raises(ValueError, match='viscosityy'):
        viscbridge.engines(viscosityy=1.0)
    with pytest.raises(ValueError, match='tangentialModel'):
        viscbridge.engines(viscosity=1.0, tangentialModel='sticky')
