"""The fixed-seed subset of the property-based campaign (tools/campaign.py, issue 27): random wet
scenes within the documented ranges keep every invariant of campaign.check, and the cases the long
campaign found and shrank stay here as regression tests."""
import os
import sys

from hypothesis import HealthCheck, given, seed, settings

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, 'tools'))
import campaign  # noqa: E402


@seed(0)
@settings(max_examples=150, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(campaign.scene_specs())
def test_random_scenes_keep_the_invariants(spec):
    campaign.check(spec)


# Found by `./yadew run tools/campaign.py 1000 1` and shrunk by hypothesis: two dry spheres dropped
# on a floor at the time stepper's collision step (0.2 T_R).  During a contact the guard compared
# the kinetic energy of the half-step velocities with the elastic energy of the whole-step
# positions; they differ by about F·v·Δt/2, first order in Δt (up to 15 % of the impact energy
# mid-contact at 0.2 T_R), and the guard's 5 % margin stopped the run.  Fixed: the guard uses the
# time-centred ½m v_{n−1/2}·v_{n+1/2} (physics.md E5).
DRY_BOUNCE = {'n': 2, 'radius': 0.002, 'spread': 0.0, 'boundary': 'floor', 'viscosity': 1.0, 'normalModel': 'none',
              'tangentialModel': 'none', 'capillaryModel': 'none', 'surfaceTension': 0.0, 'liquidModel': 'fixed',
              'integration': 'explicit', 'speed': 0.0, 'seed': 136}


def test_a_dry_bounce_at_the_collision_step_is_not_stopped():
    campaign.check(DRY_BOUNCE)
