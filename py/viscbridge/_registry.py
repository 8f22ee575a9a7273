"""What the C++ side of ViscBridge registers, for the Python tools (generated: do not edit).

Made by `viscbridge_registry --python` from pkg/viscbridge/core/models/Registry.hpp,
Parameters.hpp and core/pair/PairRecord.hpp; tests/unit/test_registry.py fails when it is out of date.
"""
import math

#: The slots of a wet contact: the Ip2 attribute that selects the model, its models in order
#: (the first is 'none'), their capabilities and the O.energy keys each books.
SLOTS = {
    'normalModel': dict(
        default='adamsPerchard',
        description='normal viscous force F = -C^n v_n (physics.md P3-P6)',
        models=('none', 'adamsPerchard', 'pitois'),
        capabilities={
            'none': dict(enabled=False, dissipative=True, conservative=False, beyondContact=False, implicitCapable=True),
            'adamsPerchard': dict(enabled=True, dissipative=True, conservative=False, beyondContact=True, implicitCapable=True),
            'pitois': dict(enabled=True, dissipative=True, conservative=False, beyondContact=True, implicitCapable=True),
        },
        energyKeys={
            'none': (),
            'adamsPerchard': ('viscDissipNormal',),
            'pitois': ('viscDissipNormal',),
        }),
    'tangentialModel': dict(
        default='slip',
        description='tangential viscous force (physics.md P7-P9)',
        models=('none', 'washino', 'slip', 'goldman'),
        capabilities={
            'none': dict(enabled=False, dissipative=True, conservative=False, beyondContact=False, implicitCapable=True),
            'washino': dict(enabled=True, dissipative=False, conservative=False, beyondContact=True, implicitCapable=False),
            'slip': dict(enabled=True, dissipative=True, conservative=False, beyondContact=True, implicitCapable=True),
            'goldman': dict(enabled=True, dissipative=True, conservative=False, beyondContact=True, implicitCapable=True),
        },
        energyKeys={
            'none': (),
            'washino': ('viscDissipTangential', 'viscDissipRotational'),
            'slip': ('viscDissipTangential', 'viscDissipRotational'),
            'goldman': ('viscDissipTangential', 'viscDissipRotational'),
        }),
    'en': dict(
        default='none',
        description='contact damping of the dry contact, selected by en < 1 (physics.md P2b)',
        models=('none', 'restitution'),
        capabilities={
            'none': dict(enabled=False, dissipative=True, conservative=False, beyondContact=False, implicitCapable=True),
            'restitution': dict(enabled=True, dissipative=True, conservative=False, beyondContact=False, implicitCapable=True),
        },
        energyKeys={
            'none': (),
            'restitution': ('contactDampDissip',),
        }),
    'capillaryModel': dict(
        default='none',
        description='capillary force of the bridge (physics.md P19-P22)',
        models=('none', 'willett', 'rabinovich'),
        capabilities={
            'none': dict(enabled=False, dissipative=False, conservative=True, beyondContact=False, implicitCapable=True),
            'willett': dict(enabled=True, dissipative=False, conservative=True, beyondContact=True, implicitCapable=True),
            'rabinovich': dict(enabled=True, dissipative=False, conservative=True, beyondContact=True, implicitCapable=True),
        },
        energyKeys={
            'none': (),
            'willett': ('capillaryWork',),
            'rabinovich': ('capillaryWork',),
        }),
}

#: The time integrations of the viscous forces (Law2_ScGeom_ViscBridgePhys_HertzViscous.integration).
INTEGRATIONS = ('explicit', 'implicit')

#: Beyond these a value is legal but almost surely a unit mistake (core/models/Plausible.hpp).
PLAUSIBLE = dict(maxRadius=0.10000000000000001, minViscosity=0.0001, maxViscosity=1000.0)

#: The numeric parameters of Ip2_FrictMat_FrictMat_ViscBridgePhys: unit, default, allowed range.
PARAMETERS = {
    'viscosity': dict(unit='Pa·s', default=0.0, lo=0.0, hi=math.inf, lo_open=False, hi_open=True, zero_means='dry'),
    'bridgeVolume': dict(unit='m³', default=0.0, lo=0.0, hi=math.inf, lo_open=False, hi_open=True, zero_means='bridgeVolumeRel times the particle volume'),
    'bridgeVolumeRel': dict(unit='', default=0.01, lo=0.0, hi=1.0, lo_open=True, hi_open=False, zero_means=''),
    'contactAngle': dict(unit='rad', default=0.0, lo=0.0, hi=1.5707963267948966, lo_open=False, hi_open=False, zero_means=''),
    'sMin': dict(unit='m', default=0.0, lo=0.0, hi=math.inf, lo_open=False, hi_open=True, zero_means='sMinRel times the reduced radius'),
    'sMinRel': dict(unit='', default=0.001, lo=0.0, hi=1.0, lo_open=True, hi_open=False, zero_means=''),
    'formationDistance': dict(unit='m', default=0.0, lo=0.0, hi=math.inf, lo_open=False, hi_open=True, zero_means='at contact'),
    'en': dict(unit='', default=1.0, lo=0.0, hi=1.0, lo_open=True, hi_open=False, zero_means=''),
    'surfaceTension': dict(unit='N/m', default=0.0, lo=0.0, hi=math.inf, lo_open=False, hi_open=True, zero_means='no capillary force'),
}

#: The per-contact record of ViscBridgePhys (core/pair/PairRecord.hpp), in its order: the type of each
#: attribute, whether it is an output a user reads (else internal state), and its documentation.
RECORD = {
    'shearElastic': dict(type='Vector3r', output=True, doc='Elastic tangential contact force, incrementally updated (YADE sense: sustained by body 2) [N].'),
    'shearPotential': dict(type='Real', output=True, doc='Elastic energy stored in the tangential contact spring, accumulated as $\\sum(|F_s|^2-|F_{s,prev}|^2)/(2k_s)$ while energy is tracked [J].'),
    'bridge': dict(type='bool', output=True, doc='Whether the liquid bridge exists.'),
    'separation': dict(type='Real', output=True, doc='Surface gap $S$ of the last step, negative in overlap [m].'),
    'cn': dict(type='Real', output=True, doc='Normal viscous coefficient $C^n$ of the last step (0 without bridge) [N·s/m].'),
    'ct': dict(type='Real', output=True, doc='Tangential viscous coefficient $C_T$ of the last step (0 without bridge) [N·s/m].'),
    'cr': dict(type='Real', output=True, doc='Rotational coupling coefficient $C_R$ of the last step (washino, goldman) [N·s/m].'),
    'normalContactForce': dict(type='Vector3r', output=True, doc='Hertz normal contact force on body 1 (including contact damping) [N].'),
    'shearContactForce': dict(type='Vector3r', output=True, doc='Mindlin tangential contact force on body 1 [N].'),
    'normalViscousForce': dict(type='Vector3r', output=True, doc='Normal viscous bridge force on body 1 (P3) [N].'),
    'shearViscousForce': dict(type='Vector3r', output=True, doc='Tangential viscous bridge force on body 1 [N].'),
    'capillaryForce': dict(type='Vector3r', output=True, doc='Capillary force on body 1, towards body 2 (P19, P20) [N].'),
    'workPending': dict(type='bool', output=False, doc='A previous step\'s work is still to be accounted.'),
    'workCn': dict(type='Real', output=False, doc='C^n of that step.'),
    'workVn': dict(type='Real', output=False, doc='Relative normal velocity of that step.'),
    'workU': dict(type='Vector3r', output=False, doc='Tangential relative velocity u of that step.'),
    'workS': dict(type='Vector3r', output=False, doc='Rotational term s of that step.'),
    'workM1': dict(type='Vector2r', output=False, doc='Resistance row (m11, m12) of that step.'),
    'workM2': dict(type='Vector2r', output=False, doc='Resistance row (m21, m22) of that step.'),
    'workCapillary': dict(type='Real', output=False, doc='Capillary pull of that step.'),
}
