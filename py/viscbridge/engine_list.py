"""A complete YADE engine list for a wet (viscous liquid bridge) scene::

    from yade import O
    import viscbridge
    O.engines = viscbridge.engines(viscosity=10.0, tangentialModel='slip')

Spheres, walls, facets and boxes all get a bounding-volume functor, a geometry functor, ViscBridge's
Ip2/Law2, NewtonIntegrator with gravity and *no* numerical damping (the liquid is the damping), and
— when the plugin provides them — ViscBridge's time stepper, implicit solver and guard.
"""
import yade.wrapper as yw

from . import _checks, criteria  # noqa: F401  (criteria: a name of this module before)
from ._registry import INTEGRATIONS

#: What engines(integration=...) accepts: a scheme of the law, or 'auto' (ViscBridgeTimeStepper
#: switches between them per phase: autoIntegration, physics.md A5).
ENGINE_INTEGRATIONS = INTEGRATIONS + ('auto',)

__all__ = ['engines', 'bridge_parameters', 'ip2_defaults', 'check_accuracy', 'ENGINE_INTEGRATIONS']


def ip2_defaults():
    """The attributes of :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys` a scene sets (its own, not those
    of every IPhysFunctor), with their defaults: read off the C++ class, the one place they live."""
    own = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys().dict()
    inherited = yw.IPhysFunctor().dict()
    return {k: v for k, v in own.items() if k not in inherited}


def bridge_parameters(**effects):
    """Split ``effects`` into the Ip2 attributes and the rest.  Each Ip2 value must have the type of
    its default (a real number, or a model name): ValueError naming the parameter otherwise, before
    Boost.Python could report an unnamed converter error."""
    defaults = ip2_defaults()
    ip2 = {k: effects.pop(k) for k in list(effects) if k in defaults}
    for k, v in ip2.items():
        if isinstance(defaults[k], str):
            if not isinstance(v, str):
                raise ValueError('%s=%r is not a name; allowed: a string (see help(Ip2_FrictMat_FrictMat_ViscBridgePhys))' % (k, v))
        else:
            ip2[k] = _checks.number('Ip2_FrictMat_FrictMat_ViscBridgePhys', k, v, 'a finite real number (see its docstring for the range)')
    return ip2, effects


def _detection_range(formationDistance, minRadius):
    """Bridges that form at a distance need interactions before contact.

    Returns (aabbEnlargeFactor, sphere-sphere interactionDetectionFactor, wall/facet/box
    detection distance [m], box interactionDetectionFactor), with 5 % margin.
    """
    if formationDistance <= 0:
        return 1.0, 1.0, 0.0, 1.0
    if minRadius is None:
        from yade import O
        radii = [b.shape.radius for b in O.bodies if b and isinstance(b.shape, yw.Sphere)]
        if not radii:
            raise ValueError('engines(formationDistance=%g) needs the smallest sphere radius to set the '
                             'detection range: create the spheres first or pass minRadius=...' % formationDistance)
        minRadius = min(radii)
    if not minRadius > 0:
        raise ValueError('engines(minRadius=%r): allowed > 0 [m]' % (minRadius,))
    reach = 1.05 * formationDistance
    # a sphere's box must reach a wall `reach` away; two spheres share the gap between them
    return 1.0 + reach / minRadius, 1.0 + reach / (2.0 * minRadius), reach, 1.0 + reach / minRadius


def engines(gravity=(0, 0, -9.81), integration=None, timeStepper=True, safety=None, guard=True,
            minRadius=None, label_prefix='', ruptureSplit='half', minBridgeVolume=0.0, kinematic=(), accuracy=None, **effects):
    """Return ``O.engines`` for a wet scene.

    Keyword arguments of :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys` select the effects and the
    liquid: ``viscosity`` [Pa·s] (0 = dry), ``bridgeVolume`` [m³] or ``bridgeVolumeRel``,
    ``contactAngle`` [rad], ``sMin`` [m] or ``sMinRel``, ``normalModel`` ('none', 'adamsPerchard',
    'pitois'), ``tangentialModel`` ('none', 'washino', 'slip', 'goldman'), ``capillaryModel``
    ('none', 'willett', 'rabinovich') with ``surfaceTension`` [N/m], ``formationDistance`` [m] and
    ``en`` (contact restitution), ``liquidModel`` ('fixed' or 'film': bridges take their liquid from
    the particles' films and give it back, with the ViscBridgeLiquid engine inserted after the
    interaction loop; set the films with :mod:`viscbridge.liquid`).  Invalid values raise ValueError
    naming the parameter.

    integration: 'explicit', 'implicit' (viscous forces by backward Euler over the contact
        network, with the ViscBridgeImplicitSolver engine inserted before the integrator) or 'auto'
        (both engines; the time stepper switches the law between the schemes, whichever is
        cheaper for the step stability and `accuracy` allow: ViscBridgeTimeStepper.autoIntegration).
        Default: 'auto' with `accuracy`, else 'explicit'.
    accuracy: tolerance on the run's relative error, in (0, 1) (ViscBridgeTimeStepper.accuracy:
        the stepper also keeps dt at the step its error estimate allows; docs/timestep.md), or None
        (dt from stability alone).  Needs timeStepper=True.
    timeStepper: add ViscBridgeTimeStepper (sets O.dt from the live contacts); ``safety`` is its
        safety factor (None: the stepper's default).  With timeStepper=False set O.dt yourself.
    guard: add ViscBridgeGuard, which stops the run before a blow-up spreads.
    minRadius: smallest sphere radius, used with formationDistance > 0 to set the detection range
        (default: taken from O.bodies).
    label_prefix: prefix of the engines' labels ('collider', 'viscBridgeIp2', 'viscBridgeLaw',
        'newton', 'timeStepper', 'implicitSolver', 'guard', 'liquid', 'forceSum').
    kinematic: engines that move boundaries (YADE's RotationEngine, TranslationEngine, ...), placed
        where they belong: right before NewtonIntegrator, which then moves the bodies they drive.
    ruptureSplit: with liquidModel='film', how a ruptured bridge's liquid returns to the films:
        'half' or 'radius' (ViscBridgeLiquid.ruptureSplit).
    minBridgeVolume: with liquidModel='film', the least liquid [m³] a bridge forms from
        (ViscBridgeLiquid.minBridgeVolume; 0: any liquid).
    """
    check_accuracy(accuracy, timeStepper)
    if integration is None:
        integration = 'explicit' if accuracy is None else 'auto'
    gravity, ip2_args = _checked_engine_args(gravity, integration, timeStepper, safety, guard, label_prefix, effects)
    ip2 = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys(label=label_prefix + 'viscBridgeIp2', **ip2_args)
    law = yw.Law2_ScGeom_ViscBridgePhys_HertzViscous(label=label_prefix + 'viscBridgeLaw',
                                                     integration='explicit' if integration == 'auto' else integration)
    out = []
    if guard and hasattr(yw, 'ViscBridgeGuard'):
        # first: it checks the scene before the interaction loop could crash on it, and sees the
        # last step's forces (before ForceResetter) to account for the work of moving walls
        out.append(yw.ViscBridgeGuard(label=label_prefix + 'guard'))
    out += [yw.ForceResetter()] + _contact_engines(ip2, law, minRadius, label_prefix)
    # the law's forces summed per body in an order the threads cannot change: bit-identical runs on any -j
    out.append(yw.ViscBridgeForceSum(label=label_prefix + 'forceSum'))
    if ip2.liquidModel == 'film':  # before the stepper: it sees the new bridges' actual volumes
        out.append(yw.ViscBridgeLiquid(label=label_prefix + 'liquid', ruptureSplit=ruptureSplit, minBridgeVolume=minBridgeVolume))
    elif ruptureSplit != 'half':
        raise ValueError("engines(ruptureSplit=%r): the split of a ruptured bridge's liquid needs liquidModel='film'" % (ruptureSplit,))
    elif minBridgeVolume != 0:
        raise ValueError("engines(minBridgeVolume=%r): a threshold on the liquid a bridge forms from needs liquidModel='film'" % (minBridgeVolume,))
    if timeStepper and hasattr(yw, 'ViscBridgeTimeStepper'):
        kw = {} if safety is None else {'safety': safety}
        if accuracy is not None:
            kw['accuracy'] = accuracy
        out.append(yw.ViscBridgeTimeStepper(label=label_prefix + 'timeStepper', autoIntegration=integration == 'auto', **kw))
    if integration in ('implicit', 'auto') and hasattr(yw, 'ViscBridgeImplicitSolver'):
        out.append(yw.ViscBridgeImplicitSolver(label=label_prefix + 'implicitSolver'))
    kinematic = list(kinematic)
    if not all(isinstance(e, yw.Engine) for e in kinematic):
        raise ValueError('engines(kinematic=%r): allowed: a list of YADE engines (e.g. RotationEngine)' % (kinematic,))
    out += kinematic
    out.append(yw.NewtonIntegrator(gravity=gravity, damping=0.0, label=label_prefix + 'newton'))
    return out


def _checked_engine_args(gravity, integration, timeStepper, safety, guard, label_prefix, effects):
    """engines()'s arguments checked (ValueError naming the parameter); returns gravity as three
    floats and the Ip2 attributes among `effects`."""
    f = 'engines'
    try:
        checked = tuple(_checks.number(f, 'gravity', g, 'three finite numbers [m/s²]') for g in gravity)
    except TypeError:  # not iterable, e.g. gravity=9.81: reported with the value given
        checked = None
    if checked is None or len(checked) != 3:
        _checks.reject(f, 'gravity', gravity, 'three finite numbers [m/s²], e.g. (0, 0, -9.81)')
    _checks.choice(f, 'integration', integration, ENGINE_INTEGRATIONS)
    if integration == 'auto' and not timeStepper:
        raise ValueError("engines(integration='auto', timeStepper=False): the time stepper chooses the scheme; "
                         "allowed with timeStepper=False: integration='explicit' or 'implicit'")
    _checks.boolean(f, 'timeStepper', timeStepper)
    _checks.boolean(f, 'guard', guard)
    if safety is not None:
        _checks.in_range(f, 'safety', safety, 0, 1, lo_open=True)
    if not isinstance(label_prefix, str):
        _checks.reject(f, 'label_prefix', label_prefix, 'a string')
    ip2_args, rest = bridge_parameters(**effects)
    if rest:
        raise ValueError('engines(): unknown parameter(s) %s; allowed: %s, gravity, integration, '
                         'timeStepper, safety, guard, minRadius, label_prefix, ruptureSplit, kinematic, accuracy'
                         % (', '.join(sorted(rest)), ', '.join(sorted(ip2_defaults()))))
    if integration in ('implicit', 'auto') and ip2_args.get('tangentialModel') == 'washino':
        raise ValueError("engines(integration=%r, tangentialModel='washino'): 'washino' is not dissipative "
                         "(physics.md P7) and cannot be integrated implicitly; allowed with integration=%r: "
                         "tangentialModel='none', 'slip', 'goldman'" % (integration, integration))
    return checked, ip2_args


def check_accuracy(accuracy, timeStepper, func='engines'):
    """accuracy: None, or a tolerance in (0, 1) that the time stepper applies."""
    if accuracy is None:
        return
    _checks.in_range(func, 'accuracy', accuracy, 0, 1, lo_open=True, hi_open=True,
                     unit=' (a relative error, e.g. 1e-2; None: no tolerance)')
    if not timeStepper:
        raise ValueError('%s(accuracy=%r) with a fixed time step: the time stepper applies the tolerance; '
                         'allowed with a fixed time step: accuracy=None' % (func, accuracy))


def _contact_engines(ip2, law, minRadius, label_prefix):
    """The collider and the interaction loop, with detection ranges for bridges that form at a distance."""
    aabb, sphereFactor, reach, boxFactor = _detection_range(ip2.formationDistance, minRadius)
    return [
        yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(aabbEnlargeFactor=aabb), yw.Bo1_Wall_Aabb(),
                                  yw.Bo1_Facet_Aabb(), yw.Bo1_Box_Aabb()], label=label_prefix + 'collider'),
        yw.InteractionLoop(
            [yw.Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=sphereFactor),
             yw.Ig2_Wall_Sphere_ViscBridgeScGeom(detectionDistance=reach),
             yw.Ig2_Facet_Sphere_ViscBridgeScGeom(detectionDistance=reach),
             yw.Ig2_Box_Sphere_ScGeom(interactionDetectionFactor=boxFactor)],
            [ip2], [law]),
    ]
