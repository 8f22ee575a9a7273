"""The fixed-seed subset of the property-based campaign (tools/campaign.py, issue 27): random wet
scenes within the documented ranges keep every invariant of campaign.check, and the cases the long
campaign found and shrank stay here as regression tests."""
import os
import sys

import pytest
from hypothesis import HealthCheck, given, seed, settings

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, 'tools'))
import campaign  # noqa: E402


@seed(0)
@settings(max_examples=150, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(campaign.scene_specs(moving=False))
def test_random_scenes_keep_the_invariants(spec):
    campaign.check(spec)


# Found by `./yadew run tools/campaign.py 1000 1` and shrunk by hypothesis: two dry spheres dropped
# on a floor at the time stepper's collision step (0.2 T_R).  During a contact the guard compared
# the kinetic energy of the half-step velocities with the elastic energy of the whole-step
# positions; they differ by about F·v·Δt/2, first order in Δt (up to 15 % of the impact energy
# mid-contact at 0.2 T_R), and the guard's 5 % margin stopped the run.  Fixed: the guard uses the
# smaller of ½m|v_{n−1/2}|² and ½m|v_{n+1/2}|² (physics.md E5).
DRY_BOUNCE = {'n': 2, 'radius': 0.002, 'spread': 0.0, 'boundary': 'floor', 'viscosity': 1.0, 'normalModel': 'none',
              'tangentialModel': 'none', 'capillaryModel': 'none', 'surfaceTension': 0.0, 'liquidModel': 'fixed',
              'integration': 'explicit', 'speed': 0.0, 'seed': 136}


def test_a_dry_bounce_at_the_collision_step_is_not_stopped():
    campaign.check(DRY_BOUNCE)


# Cases the campaign's first balance measure failed and the present one passes: mid-contact or in
# the step a bridge forms, YADE's kinetic energy (½m|v_{n−1/2}|²) and the time-centred one differ by
# up to half the kinetic energy, and either alone called these defects (balance off by 6–20 %).
#  - seed 0, moving floor: ten wet spheres (films, 1 Pa·s) thrown at 0.05 m/s above a rising floor.
RISING_FLOOR_FILMS = {'n': 10, 'radius': 0.001953125, 'spread': 0.3, 'boundary': 'floor', 'viscosity': 1.0,
                      'normalModel': 'adamsPerchard', 'tangentialModel': 'none', 'capillaryModel': 'none', 'surfaceTension': 0.0,
                      'liquidModel': 'film', 'integration': 'explicit', 'speed': 0.05, 'lift': 0.01, 'erase': False, 'seed': 9}
#  - seed 2: 20 spheres of 0.2 mm (±30 %) at 0.5 m/s in a facet box, 10 Pa·s, implicit.
IMPLICIT_FAST_BOX = {'n': 20, 'radius': 0.0002, 'spread': 0.3, 'boundary': 'box', 'viscosity': 10.0, 'normalModel': 'adamsPerchard',
                     'tangentialModel': 'none', 'capillaryModel': 'none', 'surfaceTension': 0.0, 'liquidModel': 'fixed',
                     'integration': 'implicit', 'speed': 0.5, 'seed': 5758}


@pytest.mark.parametrize('spec', [RISING_FLOOR_FILMS, IMPLICIT_FAST_BOX], ids=['rising_floor_films', 'implicit_fast_box'])
def test_balance_cases_close_by_a_consistent_measure(spec):
    campaign.check(spec)


# Found by `./yadew run tools/campaign.py 60 7` once it saved and loaded scenes half-way (2026-12-03),
# shrunk by hypothesis; both fixed.
#  - Two spheres thrown in a facet box: the resumed run's dt differed from the continued one's in the
#    8th digit.  The time stepper's saved state was tied to the interactions' count, which includes
#    the collider's potential interactions that YADE does not save, so the loaded scene never matched
#    it and took a fresh full update (the signature no longer counts them).
SAVED_IN_A_BOX = dict(DRY_BOUNCE, radius=0.001953125, boundary='box', normalModel='adamsPerchard', speed=0.5, seed=128,
                      halfway='saveLoad')
#  - Nine spheres with films and Willett bridges, implicit: positions 1e-4 off.  A bridge's
#    liquidModel is not saved (old scenes keep loading) and ViscBridgeLiquid restores it after the
#    first step's interaction loop, in which a contact without liquid formed a bridge of its own
#    volume; the law now takes films from the scene's liquid engine as well.
SAVED_WITH_FILMS = dict(SAVED_IN_A_BOX, n=9, boundary='floor', capillaryModel='willett', surfaceTension=0.0625, liquidModel='film',
                        integration='implicit', seed=0)


@pytest.mark.parametrize('spec', [SAVED_IN_A_BOX, SAVED_WITH_FILMS], ids=['dt_in_a_box', 'films_capillary_implicit'])
def test_a_run_resumed_from_its_saved_copy_continues_identically(spec):
    campaign.check(spec)


def test_loading_a_film_scene_warns_of_nothing(capfd):
    """Restoring the unsaved liquidModel after loading is not the user changing the Ip2: when the
    first step after loading created an interaction, it printed the warning that existing
    interactions keep their old values (seed 10)."""
    from yade import O
    campaign.build(SAVED_WITH_FILMS)
    O.run(100, True)
    O.saveTmp('films')
    O.loadTmp('films')
    spheres = [b for b in O.bodies if b.shape.__class__.__name__ == 'Sphere']
    spheres[-1].state.pos = spheres[0].state.pos + (1.9 * spheres[0].shape.radius, 0, 0)  # a new contact at the next step
    capfd.readouterr()
    O.run(1, True)
    assert 'existing ones keep' not in capfd.readouterr().err


# Found once the campaign drew spheres resting on each other and dry films (a user's false alarm:
# two dry spheres stacked on a floor, liquidModel='film', stopped by the guard at step 200), shrunk
# by hypothesis; all fixed.
#  - Dry spheres released from rest bounce back up: their energy returns to gravity, and the energy
#    put in since the reference falls towards 0 while the integrator's error of the bounce (0.5 % of
#    the energy it held) stays: the guard's margin, 5 % of what is in now, stopped the run, and the
#    campaign's own balance (5 % of the net flow at the end) failed the same way.  Both are now held
#    to a fraction of the most energy the scene held (physics.md E5).
STACKED_DRY = dict(DRY_BOUNCE, n=5, radius=0.5e-3, viscosity=5.0, normalModel='adamsPerchard', tangentialModel='slip',
                   liquidModel='film', wet=0.0, packing='touching', seed=1)
BOUNCED_BACK = dict(STACKED_DRY, n=2, radius=2e-3)
#  - 24 spheres of 0.2 mm placed touching: a contact at exactly zero overlap has ks = 0 and a Coulomb
#    limit of 0; the shear force it carried slid to 0 and the friction dissipation was (x/0)·0 = NaN.
TOUCHING_ZERO_OVERLAP = dict(STACKED_DRY, n=24, radius=0.2e-3)
#  - seed 12: three wet spheres resting on each other (two of them a clump) with Willett capillary
#    bridges, pulled together from rest: the capillary work of a step is booked at the next one, and
#    the guard left the last step's out — from rest, a fifth of all the work after ten steps.
TOUCHING_CAPILLARY_CLUMP = dict(DRY_BOUNCE, n=3, radius=0.001953125, packing='touching', capillaryModel='willett',
                                surfaceTension=0.0625, clump=True, seed=0)


@pytest.mark.parametrize('spec', [STACKED_DRY, BOUNCED_BACK, TOUCHING_ZERO_OVERLAP, TOUCHING_CAPILLARY_CLUMP],
                         ids=['stacked_dry', 'bounced_back', 'touching_zero_overlap', 'touching_capillary_clump'])
@pytest.mark.parametrize('integration', ['explicit', 'implicit'])
def test_spheres_resting_on_each_other_keep_the_invariants(spec, integration):
    campaign.check(dict(spec, integration=integration))


# Found by the campaign (seeds 3 and 5) and fixed with TOUCHING_CAPILLARY_CLUMP: a 0.2 mm sphere with a
# Willett capillary bridge on a floor rising at 0.05 m/s (a kinematic boundary), explicit at the
# collision step, was stopped by the guard at step 250 (kinetic + elastic 6 % above what was put in):
# the guard left out the capillary work of the last step, which is booked at the next one.
RISING_FLOOR_CAPILLARY = dict(DRY_BOUNCE, radius=0.0002, capillaryModel='willett', surfaceTension=0.0625, lift=0.05, seed=0)


def test_a_capillary_sphere_on_a_rising_floor_is_not_stopped():
    campaign.check(RISING_FLOOR_CAPILLARY)


# Open defect the campaign found once capillary bridges were drawn on a rising floor (seed 6), kept
# as a strict xfail: two touching 0.2 mm spheres with Willett bridges at 1000 Pa·s, implicit, on a
# floor rising at 0.05 m/s: O.energy's balance is off by 6.7 % of the energy through the scene (the
# floor's work 5.55e-10 J against 5.11e-10 J of kinetic energy, viscous dissipation and gravity).
# Without the capillary force, explicit, at 100 Pa·s, apart or at 0.01 m/s it closes; the guard does
# not stop it.  Suspected: the floor's work booked with the implicit force of the step before.
RISING_FLOOR_IMPLICIT_CAPILLARY = dict(TOUCHING_CAPILLARY_CLUMP, n=2, radius=0.0002, viscosity=1000.0, normalModel='adamsPerchard',
                                       surfaceTension=0.06640625, integration='implicit', lift=0.05, clump=False)


@pytest.mark.xfail(strict=True, reason='open defect: energy balance 6.7 % off, capillary + implicit on a rising floor')
def test_an_implicit_capillary_pair_on_a_rising_floor_closes_its_balance():
    campaign.check(RISING_FLOOR_IMPLICIT_CAPILLARY)


# Not a defect (2026-12-03, seeds 8 and 9, shrunk): an implicit scene with Goldman's model (here with
# a clump), saved and resumed, is bit-identical for 65 steps and then drifts to 7e-11 (positions)
# and 1.3e-9 (velocities) of the largest by step 200.  At step 64 an interaction is erased; the loaded scene's container, which lacks the
# collider's unsaved potential interactions, then holds the bridges in another order, and the
# products are summed in another order.  campaign.RESUMED bounds this round-off.
RESUMED_CLUMP_ROUNDOFF = dict(SAVED_IN_A_BOX, n=12, radius=0.0002, boundary='floor', tangentialModel='goldman', integration='implicit',
                              clump=True, seed=0)


def test_a_resumed_clump_scene_follows_the_continued_one_to_round_off():
    campaign.check(RESUMED_CLUMP_ROUNDOFF)
