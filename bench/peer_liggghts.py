# The same wet settling run in LIGGGHTS and in ViscBridge (issue 26, item 4): time to solution, the
# state side by side, and µs per particle-step.
#
#   ./yadew run bench/peer_liggghts.py [--sizes N ...] [--mu MU ...] [--rounds R ...] [--duration T]
#        (default: 300 and 3000 spheres, μ = 1, 10, 100 Pa·s, 0.1 s, 2 rounds for 300 and 1 for 3000; 31 min)
#
# The peer is Debian's `liggghts` (3.8.0): `pair_style gran model hertz tangential history cohesion
# washino/capillary/viscous`, the same viscous bridge (Washino et al., Powder Technology 2016).  If it
# is missing, this script installs it into the environment it runs in (the Debian root of ./yadew)
# with apt-get, as ./yadew installs its own packages.  LIGGGHTS runs as a subprocess, one process at
# a time, on one core; YADE on one thread.
#
# One cloud per size, made once by viscbridge.scenes.settling() (makeCloud, seed 1) and written to a
# LIGGGHTS data file: both codes start from the same positions and radii, at rest.  The column is
# 20 r wide for 300 spheres and √(n/300) times wider for more, so that every cloud is 7.9 mm high and
# lands within the 0.1 s.
#
#   matched   r = 0.5 mm, ρ = 2500 kg/m³, E = 10 MPa, ν = 0.3, friction tan 0.5, gravity 9.81 m/s²;
#             Hertz normal and Mindlin tangential stiffness (the same E*, G*), no contact damping
#             (ViscBridge en = 1, LIGGGHTS coefficientRestitution 1);
#             Adams–Perchard C = 6πμ r̄²/max(S, S_min), S_min = 10⁻³ r̄ (minSeparationDistanceRatio);
#             tangential force C_T (u + ω_r × n), C_T = 6πμ r̄ (8/15 ln(r̄/S) + 0.9588): ViscBridge's
#             'slip' (arms r + S/2) is LIGGGHTS' form (arms r); surface tension 0;
#             bridge volume 1 % of a particle (LIGGGHTS: 5 % of each film, films 10 % of the particle
#             volume), hence the same Lian rupture distance S_rup = V^(1/3) = 0.347 r;
#             walls dry: LIGGGHTS refuses its cohesion model on walls, so ViscBridge's are made dry
#             (viscbridge.liquid.make_dry) here.
#   not       where a bridge forms: at contact in ViscBridge (the scene's setting), at S_rup on
#             approach in LIGGGHTS (formation and rupture at one distance), which damps every approach
#             from 0.347 r on.  A third run, ViscBridge implicit with formationDistance = S_rup, matches
#             LIGGGHTS there (300 spheres, one round, for the state).  The Hertz radius at a wall (YADE's
#             wall functor reports 2r for the wall, R_H = 2r/3; LIGGGHTS: r).  LIGGGHTS moves film
#             liquid at a rupture (for equal particles with equal films the net transfer is zero).
#
# Runs, for every size and viscosity:
#   liggghts              fixed step FRACTION × 2m*/C(S_min), the viscous limit of an equal pair
#                         (the collision step 0.2 T_R is 160–16 000× larger).  A run of more than
#                         LIGGGHTS_BUDGET particle-steps is cut to the largest 0.1 s/10^k within it and
#                         its wall time projected linearly; a full run reports what that projection
#                         from its first tenth would have given (projection_check: projected/actual).
#                         Stable: every thermo row's kinetic energy within the released potential energy.
#   viscbridge implicit   integration='implicit' with ViscBridgeTimeStepper (the collision step).  Above
#                         LARGE spheres it stops at IMPLICIT_CUT × 0.1 s, when the bed has formed, and
#                         the rest is projected at the cost of its last tenth (implicit_projection); a
#                         full run reports what that projection would have given.
#   viscbridge explicit   explicit with the time stepper (safety 0.5): hours to days at these
#                         viscosities, so projected from EXPLICIT_STEPS steps on the state the implicit
#                         run ended in, at the stepper's dt there (the smallest of a run), as
#                         bench/settling_cost.py does.
#   viscbridge implicit, formation at S_rup   see above.
# The state (kinetic energy, bed height) is compared at the time LIGGGHTS reached: LIGGGHTS runs to
# the time of ViscBridge's snapshot.  Timed runs are interleaved over the rounds and the fastest of
# each is kept (common.interleaved explains why); the states do not depend on the round.
#
# Output: docs/perf/peer_liggghts.csv and a table on stdout; LIGGGHTS' inputs, logs and final dumps
# in bench/.cache/peer_liggghts/.
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import common  # noqa: E402
from yade import O  # noqa: E402
import yade.wrapper as yw  # noqa: E402

import viscbridge.liquid  # noqa: E402
import viscbridge.scenes as scenes  # noqa: E402
from viscbridge import criteria  # noqa: E402

R = 0.5e-3                      # sphere radius [m] (all equal: sizeRatio 1)
RHO, YOUNG, POISSON, FRICTION = 2500.0, 1e7, 0.3, 0.5
GRAVITY = 9.81
S_MIN_REL = 1e-3                # S_min / r̄, r̄ = r_i r_j/(r_i + r_j) in both codes
BRIDGE_VOLUME_REL = 0.01        # bridge volume / particle volume
SEED = 1
FRACTION = 0.2                  # LIGGGHTS' step as a fraction of 2m*/C(S_min); see liggghts_dt()
LIGGGHTS_BUDGET = 6e8           # particle-steps a LIGGGHTS run may take before it is cut and projected
EXPLICIT_STEPS = 400            # steps the explicit projection measures, after EXPLICIT_WARMUP
EXPLICIT_WARMUP = 200
SEGMENTS = 10                   # a ViscBridge run is timed in pieces of 1/SEGMENTS of the duration
LARGE = 1000                    # above this many spheres the implicit run stops at IMPLICIT_CUT ...
IMPLICIT_CUT = 0.4              # ... of the duration (the bed has formed) and is projected
TOP_SHARE = 0.1                 # the "top layer": the highest 10 % of the spheres
WORK = os.path.join(common.CACHE, 'peer_liggghts')


# -- the scene ------------------------------------------------------------------------------------
def width(n):
    """Column width: 20 r for 300 spheres, scaled so that every cloud has the same height."""
    return 20 * R * math.sqrt(n / 300.0)


def s_rup():
    """Lian's rupture distance of the bridge (contact angle 0): V^(1/3), the same in both codes."""
    return (BRIDGE_VOLUME_REL * 4.0 / 3.0 * math.pi * R ** 3) ** (1.0 / 3.0)


def viscbridge_scene(n, mu, integration, formationDistance=0.0):
    """The settling scene in O, walls dry (as LIGGGHTS' must be); returns the Settling handle."""
    extra = dict(formationDistance=formationDistance) if formationDistance > 0 else {}
    scene = scenes.settling(n=n, radius=R, density=RHO, young=YOUNG, poisson=POISSON, friction=FRICTION,
                            viscosity=mu, width=width(n), seed=SEED, gravity=GRAVITY, integration=integration,
                            trackEnergy=False, sMinRel=S_MIN_REL, bridgeVolumeRel=BRIDGE_VOLUME_REL,
                            normalModel='adamsPerchard', tangentialModel='slip', **extra)
    viscbridge.liquid.make_dry(ids=scene.walls)
    return scene


def spheres():
    return [b for b in O.bodies if isinstance(b.shape, yw.Sphere)]


def cloud(n):
    """The initial cloud of the scene (positions and radii) and its column (width, height)."""
    scene = viscbridge_scene(n, 1.0, 'explicit')
    return [(tuple(b.state.pos), b.shape.radius) for b in spheres()], scene.params['width'], scene.params['height']


# -- measures, the same for both codes --------------------------------------------------------------
def state_measures(rows):
    """Kinetic energy (translation + rotation, I = 2/5 m r²) and bed heights of spheres given as
    (z, r, m, |v|², |ω|²): the top layer's mean surface height (the highest TOP_SHARE of z + r), the
    highest surface and the mean centre height."""
    ke = sum(0.5 * m * v2 + 0.5 * 0.4 * m * r * r * w2 for z, r, m, v2, w2 in rows)
    tops = sorted((z + r for z, r, m, v2, w2 in rows), reverse=True)
    k = max(1, int(round(TOP_SHARE * len(tops))))
    return dict(kinetic=ke, top_height=sum(tops[:k]) / k, max_height=tops[0],
                mean_z=sum(z for z, r, m, v2, w2 in rows) / len(rows))


def viscbridge_state():
    return state_measures([(b.state.pos[2], b.shape.radius, b.state.mass, b.state.vel.squaredNorm(),
                            b.state.angVel.squaredNorm()) for b in spheres()])


# -- LIGGGHTS ---------------------------------------------------------------------------------------
def ensure_liggghts():
    """The liggghts executable; Debian's package is installed into this environment if missing, the
    way ./yadew installs its own packages (apt-get, no recommends, waiting for a held dpkg lock)."""
    exe = shutil.which('liggghts')
    if exe:
        return exe
    if os.geteuid() != 0:
        sys.exit('liggghts is not installed; install it: sudo apt-get install --no-install-recommends liggghts')
    os.makedirs(WORK, exist_ok=True)
    apt = ['apt-get', '-q', '-y', '-o', 'DPkg::Lock::Timeout=1800']
    install = apt + ['install', '--no-install-recommends', 'liggghts']
    print('installing Debian\'s liggghts into this environment (log: %s/apt.log)' % WORK, flush=True)
    with open(os.path.join(WORK, 'apt.log'), 'a') as log:
        if subprocess.call(install, stdout=log, stderr=log) != 0:  # stale package lists: update once
            subprocess.check_call(apt + ['update'], stdout=log, stderr=log)
            subprocess.check_call(install, stdout=log, stderr=log)
    return shutil.which('liggghts')


def liggghts_dt(mu):
    """FRACTION of the explicit viscous limit of an equal pair at S_min, 2m*/C(S_min) (physics.md
    P12), or of the collision step 0.2 T_R if that were smaller.  A bed's limit is below the pair's:
    ViscBridge's stepper puts this scene's at 0.36–0.38 of it (the study's bed: 0.37, docs/study.md)
    and takes half, so FRACTION = 0.2 keeps the same margin.  LIGGGHTS has no estimate of the
    network's limit: a user takes such a fraction of the pair's.  (Its loose bed here stays bounded far
    above: docs/performance.md §4.)"""
    m_star = RHO * 4.0 / 3.0 * math.pi * R ** 3 / 2
    r_bar = R / 2
    viscous = 2 * m_star * S_MIN_REL * r_bar / (6 * math.pi * mu * r_bar ** 2)
    return min(FRACTION * viscous, 0.2 * criteria.rayleigh_time(R, RHO, YOUNG, POISSON))


def write_data(path, particles, w, h):
    """A LIGGGHTS data file (atom_style granular: id type diameter density x y z) of the cloud."""
    with open(path, 'w') as fh:
        fh.write('ViscBridge settling cloud\n\n%d atoms\n1 atom types\n\n' % len(particles))
        # the box reaches above the cloud: a particle thrown out of a fixed box would be lost
        fh.write('0 %.17g xlo xhi\n0 %.17g ylo yhi\n%.17g %.17g zlo zhi\n\nAtoms\n\n' % (w, w, -R, 2 * h + 4 * R))
        for k, (pos, r) in enumerate(particles):
            fh.write('%d 1 %.17g %.17g %.17g %.17g %.17g\n' % (k + 1, 2 * r, RHO, pos[0], pos[1], pos[2]))


LIGGGHTS_INPUT = """\
# written by bench/peer_liggghts.py: {n} spheres settling through viscous bridges, mu = {mu} Pa s
atom_style      granular
atom_modify     map array
boundary        f f f
newton          off
communicate     single vel yes
units           si
read_data       {data}
# neighbour lists reach the bridge's rupture distance (maxSeparationDistanceRatio), plus a skin
neighbor        {skin} bin
neigh_modify    delay 0

fix m1 all property/global youngsModulus peratomtype {young}
fix m2 all property/global poissonsRatio peratomtype {poisson}
# restitution 1: no contact dashpot (ViscBridge en = 1)
fix m3 all property/global coefficientRestitution peratomtypepair 1 1.0
fix m4 all property/global coefficientFriction peratomtypepair 1 {mu_friction}
fix l1 all property/global minSeparationDistanceRatio scalar {s_min_rel}
fix l2 all property/global maxSeparationDistanceRatio scalar {max_sep}
# a fraction of the particle volume (the source multiplies it by the volume; its docs say "%")
fix l3 all property/global surfaceLiquidContentInitial scalar {film}
fix l4 all property/global surfaceTension scalar 0.0
fix l5 all property/global fluidViscosity scalar {mu}
fix l6 all property/global contactAngle peratomtype 0.0

pair_style gran model hertz tangential history cohesion washino/capillary/viscous
pair_coeff * *
timestep {dt}
fix gravity all gravity {g} vector 0.0 0.0 -1.0
# walls: Hertz only (LIGGGHTS has no cohesion model for walls)
fix floor all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix x0 all wall/gran model hertz tangential history primitive type 1 xplane 0.0
fix x1 all wall/gran model hertz tangential history primitive type 1 xplane {w}
fix y0 all wall/gran model hertz tangential history primitive type 1 yplane 0.0
fix y1 all wall/gran model hertz tangential history primitive type 1 yplane {w}
fix integrate all nve/sphere

compute rke all erotate/sphere
variable zc equal xcm(all,z)
thermo_style    custom step cpu ke c_rke v_zc atoms
thermo_modify   norm no lost error format float %.15g
thermo          {thermo}
dump final all custom {steps} {dump} id radius mass x y z vx vy vz omegax omegay omegaz
dump_modify final sort id
run             {steps}
"""


def liggghts_input(n, mu, dt, steps, data, dump, w):
    film = BRIDGE_VOLUME_REL / (0.05 * 2)  # LIGGGHTS' bridge: 5 % of each particle's film
    return LIGGGHTS_INPUT.format(
        n=n, mu=mu, data=data, dump=dump, dt=repr(dt), steps=steps, thermo=max(1, steps // 200), w=repr(w),
        skin=repr(0.2 * R), young=YOUNG, poisson=POISSON, mu_friction=repr(math.tan(FRICTION)),
        s_min_rel=S_MIN_REL, max_sep=repr(1.05 * (1 + s_rup() / (2 * R))), film=repr(film), g=GRAVITY)


def liggghts_run(exe, n, mu, duration, data, w):
    """One LIGGGHTS run of `duration` [s]: wall and loop time, steps, the thermo history, the final state."""
    dt = liggghts_dt(mu)
    steps = int(round(duration / dt))
    stem = os.path.join(WORK, 'n%d_mu%g' % (n, mu))
    with open(stem + '.in', 'w') as fh:
        fh.write(liggghts_input(n, mu, dt, steps, data, stem + '.dump', w))
    start = time.perf_counter()
    proc = subprocess.run([exe, '-in', stem + '.in', '-log', stem + '.log', '-screen', 'none', '-echo', 'none'],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - start
    log = ''
    if os.path.exists(stem + '.log'):
        with open(stem + '.log') as fh:
            log = fh.read()
    if proc.returncode != 0 or 'ERROR' in log:
        raise RuntimeError('liggghts failed (status %d); see %s.log:\n%s' % (proc.returncode, stem, proc.stdout[-2000:]))
    loop = re.search(r'Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps', log)
    return dict(dt=dt, steps=int(loop.group(2)), wall=wall, loop=float(loop.group(1)), time=int(loop.group(2)) * dt,
                thermo=thermo_rows(log), state=dump_state(stem + '.dump'))


def thermo_rows(log):
    """The thermo table of a LIGGGHTS log: dicts of step, cpu, kineng (translation), rke (rotation), zc."""
    lines = log.splitlines()
    head = next(k for k, line in enumerate(lines) if line.split()[:2] == ['Step', 'CPU'])
    names = [s.lower() for s in lines[head].split()]
    rows = []
    for line in lines[head + 1:]:
        if line.startswith('Loop time'):
            break
        rows.append(dict(zip(names, (float(x) for x in line.split()))))
    return rows


def dump_state(path):
    """state_measures() of the last snapshot of a LIGGGHTS custom dump."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    start = max(k for k, line in enumerate(lines) if line.startswith('ITEM: ATOMS'))
    cols = lines[start].split()[2:]
    rows = []
    for line in lines[start + 1:]:
        a = dict(zip(cols, (float(x) for x in line.split())))
        rows.append((a['z'], a['radius'], a['mass'], a['vx'] ** 2 + a['vy'] ** 2 + a['vz'] ** 2,
                     a['omegax'] ** 2 + a['omegay'] ** 2 + a['omegaz'] ** 2))
    return state_measures(rows)


def liggghts_stability(thermo, total_mass):
    """The first thermo row that fails the instability criterion, or ''.  In free fall the kinetic
    energy equals the released potential energy exactly (velocity Verlet), so round-off alone could
    tip the test: 1 % is allowed on top, which a blow-up (exponential) passes within a few steps."""
    zc0 = thermo[0]['zc']
    for row in thermo:
        why = scenes.instability(row['kineng'] + row['rke'], 1.01 * total_mass * GRAVITY * (zc0 - row['zc']))
        if why:
            return 'step %d: %s' % (row['step'], why)
    return ''


def liggghts_duration(n, mu, duration):
    """The largest duration/10^k whose run fits LIGGGHTS_BUDGET particle-steps."""
    steps = duration / liggghts_dt(mu)
    k = max(0, math.ceil(math.log10(steps * n / LIGGGHTS_BUDGET)))
    return duration / 10 ** k


# -- ViscBridge -------------------------------------------------------------------------------------
_RUN = {}  # what the PyRunners of the ViscBridge run in progress record (viscbridge_run)


def _tick():
    """PyRunner: a point of the wall-time profile.  It runs after NewtonIntegrator, before YADE adds
    dt to O.time: the positions are those of O.time + O.dt."""
    _RUN['profile'].append((O.time + O.dt, time.perf_counter() - _RUN['start'], O.iter + 1 - _RUN['iter0']))


def _snapshot():
    """PyRunner: the state at the comparison time (the first step that reaches it)."""
    if _RUN['at'] is None:
        _RUN['at'] = dict(viscbridge_state(), time=O.time + O.dt)


def viscbridge_run(n, mu, duration, compare_at, until=None, formationDistance=0.0):
    """ViscBridge implicit at the stepper's step, to `until` (default `duration`): the wall-time
    profile (time, wall, steps every duration/SEGMENTS), the state at `compare_at` (if reached) and at
    the end.  One O.run(): the profile and the snapshot are taken by PyRunners, because every
    O.run(..., True) waits for the run in 40 ms polls, which pieces would add up."""
    until = until or duration
    scene = viscbridge_scene(n, mu, 'implicit', formationDistance)
    me = 'import sys; sys.modules[%r].' % __name__
    runners = [yw.PyRunner(virtPeriod=duration / SEGMENTS, command=me + '_tick()'),
               yw.PyRunner(virtPeriod=compare_at, command=me + '_snapshot()')]
    O.engines = O.engines + runners
    _RUN.update(profile=[(0.0, 0.0, 0)], at=None, iter0=O.iter, start=time.perf_counter())
    O.stopAtTime = until
    O.run(-1, True)
    O.stopAtTime = 0
    wall, steps = time.perf_counter() - _RUN['start'], O.iter - _RUN['iter0']
    O.engines = [e for e in O.engines if not (isinstance(e, yw.PyRunner) and e.command.startswith(me))]
    profile = [p for p in _RUN['profile'] if p[2] < steps] + [(O.time, wall, steps)]
    state = viscbridge_state()
    at = _RUN['at']
    if at is None and O.time >= compare_at * (1 - 1e-9):  # the PyRunner sees O.time before the last step's dt
        at = dict(state, time=O.time)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    return dict(dt=O.dt, steps=steps, wall=wall, time=O.time, state=state, at=at, profile=profile,
                unstable=scene.unstable() or scene.stopped_because or '', bridges=scene.bridges(),
                cg=solver.totalIterations / max(solver.solves, 1))


def implicit_projection(profile, cut, duration):
    """(wall, steps) to `duration` of an implicit run measured to `cut`: the measured part, then the
    rest at the cost per simulated second of its last segment — by then the bed has formed, and
    the early, cheap part of the run (a falling cloud, few bridges) is not extrapolated."""
    k = min(range(1, len(profile)), key=lambda i: abs(profile[i][0] - cut))  # the point at `cut`, give or take a step
    (t0, w0, s0), (t1, w1, s1) = profile[k - 1], profile[k]
    rest = (duration - t1) / (t1 - t0)
    return w1 + rest * (w1 - w0), int(round(s1 + rest * (s1 - s0)))


def explicit_projection(duration):
    """ViscBridge explicit with its time stepper, on the settled state in O (an implicit run's end):
    EXPLICIT_STEPS steps after EXPLICIT_WARMUP, projected to `duration` at the stepper's mean dt."""
    # switch the law itself: existing interactions keep the functor they were first handled by
    law = next(f for e in O.engines if isinstance(e, yw.InteractionLoop) for f in e.lawDispatcher.functors)
    law.integration = 'explicit'
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
    O.run(EXPLICIT_WARMUP, True)  # the stepper brings dt down to the explicit limit
    t0 = O.time
    per_step = common.engine_seconds_per_step(EXPLICIT_STEPS)
    dt = (O.time - t0) / EXPLICIT_STEPS
    steps = int(math.ceil(duration / dt))
    return dict(dt=dt, steps=steps, wall=per_step * steps)


# -- the benchmark ----------------------------------------------------------------------------------
def row(n, mu, run, dt, steps, wall, projected, at=None, **extra):
    """A row of the table: time to solution and, where the run has one, the state compared."""
    out = dict(spheres=n, viscosity=mu, run=run, dt=dt, steps=steps, wall_seconds=wall, projected=projected,
               us_per_particle_step=1e6 * wall / (steps * n), compare_time=None, kinetic=None, top_height=None,
               max_height=None, mean_z=None)
    if at:
        out.update({k: at[k] for k in ('time', 'kinetic', 'top_height', 'max_height', 'mean_z')})
        out['compare_time'] = out.pop('time')
    out.update(extra)
    return out


def liggghts_row(n, mu, lig, duration):
    """LIGGGHTS' row: a cut run's wall time projected linearly; a full run's projection_check is what
    that linear projection from its first tenth would have given, over its actual loop time."""
    scale = duration / lig['time']
    check = None
    if scale < 1.0001:
        last = lig['thermo'][-1]['step']
        tenth = min(lig['thermo'], key=lambda r: abs(r['step'] - last / 10.0))
        check = tenth['cpu'] * last / tenth['step'] / lig['loop']
    return row(n, mu, 'liggghts', lig['dt'], int(round(duration / lig['dt'])), lig['wall'] * scale, scale > 1.0001,
               dict(lig['state'], time=lig['time']), unstable=lig['unstable'], run_time=lig['time'],
               loop_seconds=lig['loop'] * scale, projection_check=check)


def viscbridge_row(n, mu, run, r, duration):
    """ViscBridge implicit's row: a run cut before `duration` projected by implicit_projection(); a
    full run's projection_check is what that projection from IMPLICIT_CUT would have given, over its
    actual wall time."""
    projected = r['time'] < duration * (1 - 1e-9)
    if projected:
        wall, steps = implicit_projection(r['profile'], r['time'], duration)
        check = None
    else:
        wall, steps = r['wall'], r['steps']
        check = implicit_projection(r['profile'], IMPLICIT_CUT * duration, duration)[0] / r['wall']
    return row(n, mu, run, r['dt'], steps, wall, projected, r['at'], unstable=r['unstable'], run_time=r['time'],
               projection_check=check, cg_per_step=r['cg'], bridges=r['bridges'], final_time=r['time'],
               final_kinetic=r['state']['kinetic'], final_top_height=r['state']['top_height'])


def write_clouds(sizes):
    """The cloud of every size as a LIGGGHTS data file: {n: (path, column width, total mass)}."""
    clouds = {}
    for n in sizes:
        particles, w, h = cloud(n)
        data = os.path.join(WORK, 'cloud_%d.data' % n)
        write_data(data, particles, w, h)
        clouds[n] = (data, w, sum(RHO * 4.0 / 3.0 * math.pi * r ** 3 for _, r in particles))
    return clouds


def timed_rounds(exe, cases, rounds, clouds, duration):
    """ViscBridge implicit and LIGGGHTS, case by case, in interleaved rounds: the fastest run of each
    code per case, and the explicit projection (made once, on the first implicit run's end state)."""
    runs, explicit = {}, {}   # (n, mu, code) -> the fastest run; (n, mu) -> the explicit projection
    for rnd in range(max(rounds.values())):
        for n, mu in cases:
            if rnd >= rounds[n]:
                continue
            data, w, mass = clouds[n]
            lig_time = liggghts_duration(n, mu, duration)
            ours = viscbridge_run(n, mu, duration, lig_time, IMPLICIT_CUT * duration if n > LARGE else None)
            if (n, mu) not in explicit:
                explicit[(n, mu)] = explicit_projection(duration)
            # LIGGGHTS runs to the very time of ViscBridge's snapshot (the first step at or after
            # lig_time): in free fall a 2 % later time is 4 % more kinetic energy
            lig = liggghts_run(exe, n, mu, ours['at']['time'] if ours['at'] else lig_time, data, w)
            lig['unstable'] = liggghts_stability(lig['thermo'], mass)
            for code, r in (('viscbridge', ours), ('liggghts', lig)):
                if (n, mu, code) not in runs or r['wall'] < runs[(n, mu, code)]['wall']:
                    runs[(n, mu, code)] = r
            print('round %d, %d spheres, mu=%g: ViscBridge implicit %.1f s for %.3g s; LIGGGHTS %.1f s for %.3g s (%d steps)%s'
                  % (rnd + 1, n, mu, ours['wall'], ours['time'], lig['wall'], lig['time'], lig['steps'],
                     ', UNSTABLE ' + lig['unstable'] if lig['unstable'] else ''), flush=True)
    return runs, explicit


def main():
    ap = argparse.ArgumentParser(description='ViscBridge against LIGGGHTS on the wet settling run')
    ap.add_argument('--sizes', type=int, nargs='+', default=[300, 3000])
    ap.add_argument('--mu', type=float, nargs='+', default=[1.0, 10.0, 100.0])
    ap.add_argument('--rounds', type=int, nargs='+', default=[2, 1], help='interleaved rounds, one value per size (or one for all)')
    ap.add_argument('--duration', type=float, default=0.1, help='simulated time [s]')
    ap.add_argument('--csv', default=os.path.join(common.RESULTS, 'peer_liggghts.csv'))
    args = ap.parse_args(sys.argv[1:])
    rounds = dict(zip(args.sizes, args.rounds if len(args.rounds) > 1 else args.rounds * len(args.sizes)))
    exe = ensure_liggghts()
    os.makedirs(WORK, exist_ok=True)
    clouds = write_clouds(args.sizes)
    cases = [(n, mu) for n in args.sizes for mu in args.mu]
    runs, explicit = timed_rounds(exe, cases, rounds, clouds, args.duration)
    rows = []
    for n, mu in cases:
        rows.append(liggghts_row(n, mu, runs[(n, mu, 'liggghts')], args.duration))
        rows.append(viscbridge_row(n, mu, 'viscbridge implicit', runs[(n, mu, 'viscbridge')], args.duration))
        e = explicit[(n, mu)]
        rows.append(row(n, mu, 'viscbridge explicit', e['dt'], e['steps'], e['wall'], True))
        if n <= LARGE:  # one round, for the state: bridges formed where LIGGGHTS forms them
            matched = viscbridge_run(n, mu, args.duration, liggghts_duration(n, mu, args.duration), formationDistance=s_rup())
            rows.append(viscbridge_row(n, mu, 'viscbridge implicit, formation at S_rup', matched, args.duration))
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    out = common.write_rows(args.csv, [{k: r.get(k) for k in keys} for r in rows])
    print_table(rows, rounds)
    print('written', out)


def print_table(rows, rounds):
    print('\nwet settling, 1 thread, fastest of %s interleaved rounds (* projected to the full duration)'
          % ', '.join('%d for %d spheres' % (r, n) for n, r in rounds.items()))
    print('%6s %6s %-42s %10s %11s %10s %8s %11s %9s %9s' % ('n', 'μ', 'run', 'dt [s]', 'steps', 'wall [s]', 'µs/p-step',
                                                            'at t [s]', 'KE [J]', 'top [mm]'))
    for r in rows:
        state = ('%11.3g %9.3g %9.4f' % (r['compare_time'], r['kinetic'], 1e3 * r['top_height'])
                 if r['kinetic'] is not None else '')
        print('%6d %6g %-42s %10.3g %11d %10.4g%s %8.3f %s' % (
            r['spheres'], r['viscosity'], r['run'], r['dt'], r['steps'], r['wall_seconds'], '*' if r['projected'] else ' ',
            r['us_per_particle_step'], state))


if __name__ == '__main__':  # yade -x runs the script as __main__; importing it (to try a function) does not run it
    main()
