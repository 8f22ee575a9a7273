"""Time-step planning for ViscBridge simulations, in plain Python (no YADE needed).

This package is also importable as ``viscbridge.criteria`` (its first name).

Which time step Δt does a DEM simulation with highly viscous liquid bridges need?  Two families of
limits compete (physics.md §3; equation tags P4…P15 as in the code comments of the C++ kernels):

* the **collision** limits of the dry Hertz–Mindlin contact: the Rayleigh-wave step (the usual
  DEM criterion) and the stability of the contact spring at the stiffness reached in a collision;
* the **viscous** limits of the bridges' dashpots.  YADE's leapfrog evaluates every
  velocity-dependent force from the stored velocity v_{n−1/2}, i.e. explicit Euler in velocity, so
  a dashpot C acting on a reduced mass m* multiplies the relative velocity by (1 − Δt C/m*) per
  step: stable iff Δt < 2 m*/C, free of spurious rebound iff Δt ≤ m*/C.  The coefficient is largest
  at the smallest gap the model allows, S_min (P6), so every viscous limit is proportional to
  S_min/μ and can be many orders of magnitude below the collision limit.

:func:`critical_dt` evaluates all of them for one representative contact and returns a
:class:`TimeStepCriteria` (a table of :class:`Bound` rows) with the stable step, the step free of
spurious rebounds, the governing bound and the regime.  The building blocks are public:

===============================  =================================================================
:func:`rayleigh_time`            T_R = π r √(ρ/G) / (0.1631 ν + 0.876605), G = E/(2(1+ν))
:func:`rayleigh_dt`              fraction · T_R (fraction 0.2 by default)
:func:`hertz_collision_time`     t_c = 2.868 (m*²/(r̄ E*² v))^(1/5)
:func:`viscous_decay_time`       t_v = m*/C^n(S_min)                                          (P12)
:func:`normal_coefficient`       C^n(S) of Adams–Perchard (P4) or Pitois (P5)
:func:`tangential_coefficients`  C_T, C_R, C_W of Goldman et al. (P8, P9, C_W)
:func:`pair_limit`               4m*/(C + √(C² + 4m*k))                                       (P13)
:func:`network_limit`            4/(d + √(d² + 4κ))                                           (P14)
===============================  =================================================================

Conventions (physics.md §1): r̄ = r_i r_j/(r_i + r_j), m* = m_i m_j/(m_i + m_j); against a wall
r̄ = r and m* = m.  All quantities in SI units.  The constants are those of the C++ kernels
(``pkg/viscbridge/physics/*.hpp``): same E*, G*, Hertz and Mindlin stiffnesses as YADE's
``Ip2_FrictMat_FrictMat_MindlinPhys``, same viscous coefficients as the ViscBridge laws.

Modules, one concept each: :mod:`.materials` (particles, dry contact, collision scales),
:mod:`.viscous` (viscous coefficients, t_v), :mod:`.capillary` (capillary force and stiffness),
:mod:`.bounds` (P13, P14), :mod:`.lattice` (the Bloch-wave limit of a regular packing),
:mod:`.report` (:class:`Bound`, :class:`TimeStepCriteria`), :mod:`.critical` (:func:`critical_dt`)
and :mod:`.inputs` (model names, argument checks).
"""
from .bounds import network_limit, pair_limit
from .capillary import capillary_force, capillary_max_stiffness, capillary_stiffness, rupture_distance
from .critical import critical_dt
from .inputs import CAPILLARY_MODELS, INTEGRATIONS, NORMAL_MODELS, TANGENTIAL_MODELS
from .lattice import LATTICE_BONDS, lattice_limit
from .materials import (HERTZ_TC, RAYLEIGH_A, RAYLEIGH_B, effective_shear, effective_young, hertz_collision_time,
                        hertz_max_overlap, hertz_normal_stiffness, mindlin_tangential_stiffness, rayleigh_dt,
                        rayleigh_time, reduced_mass, reduced_radius, restitution_damping_ratio, sphere_mass,
                        sphere_volume)
from .report import Bound, TimeStepCriteria
from .viscous import (ROT, normal_coefficient, pitois_volume_factor, tangential_coefficients, viscous_decay_time,
                      viscous_step_coefficient)

__all__ = ['Bound', 'TimeStepCriteria', 'critical_dt', 'rayleigh_time', 'rayleigh_dt',
           'hertz_collision_time', 'hertz_max_overlap', 'hertz_normal_stiffness',
           'mindlin_tangential_stiffness', 'effective_young', 'effective_shear',
           'viscous_decay_time', 'normal_coefficient', 'pitois_volume_factor',
           'tangential_coefficients', 'pair_limit', 'network_limit', 'restitution_damping_ratio',
           'reduced_radius', 'reduced_mass', 'sphere_mass', 'sphere_volume', 'viscous_step_coefficient',
           'rupture_distance', 'capillary_force', 'capillary_stiffness', 'capillary_max_stiffness', 'lattice_limit',
           'NORMAL_MODELS', 'TANGENTIAL_MODELS', 'CAPILLARY_MODELS', 'INTEGRATIONS']
