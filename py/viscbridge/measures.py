"""What is measured on a scene, in one place: kinetic energy, the potential energy released, the
energy the capillary forces put in, the instability criterion of the settling runs and the scans,
the period-2 ringing of the scans' ``verdict='period2'``, the number of bridges and the bridges' end
points (for output).

:func:`instability` is plain Python; the others read YADE's ``O`` (imported when called), so this
module imports without YADE.  A new measure of a scene goes here; an analysis built on measures
(agglomerates, size distributions, ...) goes into :mod:`viscbridge.analysis`.
"""
import math

from ._yade_run import run_steps

__all__ = ['instability', 'kinetic_energy', 'scene_gravity', 'released_energy', 'capillary_input', 'energy_released',
           'bridge_count', 'bridge_segments', 'period_two_ringing']


def instability(kinetic, released, initial_kinetic=0.0):
    """Why a settling run is unstable, or None if it is not.

    The stated criterion: the kinetic energy of a run under gravity can only come from the released
    potential energy (plus what it had at the start); an explicit scheme above its stable step
    injects energy, so KE > KE₀ + released means the integration has blown up.  A NaN or inf in
    either number counts as unstable too.  With capillary forces, ``released`` must include what
    they have put in (:func:`capillary_input`): they pull the particles together by themselves.
    """
    if not (math.isfinite(kinetic) and math.isfinite(released)):
        return 'non-finite energy (kinetic=%r, released=%r)' % (kinetic, released)
    if kinetic > initial_kinetic + max(released, 0.0):
        return 'kinetic energy %.4g J exceeds the released potential energy %.4g J (+ initial %.4g J)' % (
            kinetic, released, initial_kinetic)
    return None


def kinetic_energy():
    """Translational + rotational kinetic energy of all bodies [J]."""
    from yade import utils
    return utils.kineticEnergy()


def scene_gravity():
    """The scene's gravity along −z [m/s²]: −g_z of its NewtonIntegrator (0 without one).  The
    settling scenes (:func:`viscbridge.scenes.settling`) have their gravity along −z."""
    from yade import O
    import yade.wrapper as yw
    newton = next((e for e in O.engines if isinstance(e, yw.NewtonIntegrator)), None)
    return -newton.gravity[2] if newton is not None else 0.0


def released_energy(heights, gravity):
    """Potential energy released since the bodies were at `heights` ({id: z₀}), under `gravity`
    [m/s²] along −z: Σ m g (z₀ − z) [J]."""
    from yade import O
    return sum(O.bodies[i].state.mass * gravity * (z0 - O.bodies[i].state.pos[2]) for i, z0 in heights.items())


def capillary_input():
    """Energy the capillary forces have put into the particles [J] since the scene's ViscBridge law
    was created (its ``capillaryInput``, physics.md P21); 0 without capillary forces."""
    from yade import O
    import yade.wrapper as yw
    for loop in (e for e in O.engines if isinstance(e, yw.InteractionLoop)):
        for law in loop.lawDispatcher.functors:
            if isinstance(law, yw.Law2_ScGeom_ViscBridgePhys_HertzViscous):
                return law.capillaryInput
    return 0.0


def energy_released(heights, gravity, capillary0):
    """All the energy that may have become kinetic since the start [J]: the potential energy
    released (:func:`released_energy`) plus what the capillary forces have put in since their input
    was `capillary0` — the ``released`` of :func:`instability`."""
    return released_energy(heights, gravity) + capillary_input() - capillary0


def bridge_count():
    """Number of interactions with a liquid bridge."""
    from yade import O
    return sum(1 for i in O.interactions if i.isReal and getattr(i.phys, 'bridge', False))


def bridge_segments(only_bridges=False):
    """(end1, end2, phys, interaction) of every ViscBridge interaction (with a bridge, if asked): a
    sphere's end is its centre, a wall's, facet's or box's the point of its surface facing the
    sphere; across a periodic boundary end2 is the image nearest to end1."""
    from yade import O, Vector3
    import yade.wrapper as yw
    out = []
    for i in O.interactions:
        if not i.isReal or not isinstance(i.phys, yw.ViscBridgePhys) or (only_bridges and not i.phys.bridge):
            continue
        ph, n, gap = i.phys, i.geom.normal, -i.geom.penetrationDepth
        p1 = O.bodies[i.id1].state.pos
        p2 = O.bodies[i.id2].state.pos + (O.cell.hSize * Vector3(*i.cellDist) if O.periodic else Vector3.Zero)
        if ph.radius1 <= 0:
            p1 = p2 - n * (ph.radius2 + gap)
        elif ph.radius2 <= 0:
            p2 = p1 + n * (ph.radius1 + gap)
        out.append((p1, p2, ph, i))
    return out


def period_two_ringing(share=0.2):
    """Why the motion is a ringing at the time step's own frequency (physics.md §7), or None: more than
    `share` of the kinetic energy in bodies whose velocity reversed at each of the next two steps
    (+ − +).  Physics reverses a velocity only at a turning point; a mode at the stability limit
    (amplification −1) reverses it every step and stops decaying, so it outlasts a trial even where it
    stays bounded and the energy criterion does not fire.  Runs two steps more."""
    from yade import O, Vector3
    dynamic = [b for b in O.bodies if b.dynamic]
    history = [[Vector3(b.state.vel) for b in dynamic]]  # copies: the attribute is a live view
    for _ in range(2):
        run_steps(1)
        history.append([Vector3(b.state.vel) for b in dynamic])
    ringing = total = 0.0
    for k, b in enumerate(dynamic):
        v0, v1, v2 = history[0][k], history[1][k], history[2][k]
        energy = 0.5 * b.state.mass * v2.squaredNorm()
        total += energy
        if v0.dot(v1) < 0 and v1.dot(v2) < 0:
            ringing += energy
    if total > 0 and ringing > share * total:
        return 'period-2 ringing (%.0f %% of the kinetic energy reverses every step)' % (100 * ringing / total)
    return None
