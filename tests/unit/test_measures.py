"""viscbridge.measures without YADE: the instability criterion on numbers."""
from viscbridge.measures import instability


def test_criterion_on_numbers():
    assert instability(1.0, 2.0) is None                      # dissipated part of what was released
    assert instability(1.0, 0.5, initial_kinetic=0.6) is None  # initial motion counts
    assert 'exceeds' in instability(2.1, 2.0)
    assert 'non-finite' in instability(float('nan'), 1.0)
    assert 'non-finite' in instability(1.0, float('inf'))
