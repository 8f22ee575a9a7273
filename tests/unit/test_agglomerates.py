"""Agglomerates as connected components of the bridge graph (no YADE: the pure part)."""
import numpy
import pytest

from viscbridge.analysis.agglomerates import components, transitions


def test_chains_and_lone_spheres_by_hand():
    # bodies 3..9: a chain 3-4-5, a pair 7-8, lone 6 and 9
    a = components([3, 4, 5, 6, 7, 8, 9], [(3, 4), (4, 5), (7, 8)], [1, 1, 1, 1, 1, 1, 1])
    assert list(a.sizes) == [3, 2, 1, 1] and a.largest == 3 and a.count == 4
    assert [a.label_of(i) for i in (3, 4, 5, 7, 8, 6, 9)] == [0, 0, 0, 1, 1, 2, 3]  # ties: smallest id first
    assert a.coordination == pytest.approx(6 / 7)
    assert a.mass_fractions == pytest.approx([3 / 7, 2 / 7, 1 / 7, 1 / 7])
    with pytest.raises(KeyError, match='not a member'):
        a.label_of(0)


def test_a_ring_is_one_agglomerate_and_masses_weigh_it():
    a = components([0, 1, 2, 3], [(0, 1), (1, 2), (2, 3), (3, 0)], [1, 2, 3, 4])
    assert list(a.sizes) == [4] and a.coordination == 2.0 and list(a.mass_fractions) == [1.0]


def test_liquid_per_agglomerate_and_its_cov():
    a = components([0, 1, 2], [(0, 1)], [1, 1, 1], liquid=[1.0, 3.0, 2.0])
    assert list(a.liquid) == [4.0, 2.0]
    assert a.liquid_cov == pytest.approx(numpy.std([1, 3, 2]) / 2)


def test_transitions_count_breakage_and_coalescence():
    before = components([1, 2, 3, 4, 5, 6], [(1, 2), (2, 3), (5, 6)], [1] * 6)  # {1,2,3} {4} {5,6}
    # {1,2,3} breaks into {1} and {2,3}; {2,3} takes up {4}: one broke, one formed by coalescence;
    # {5,6} stays whole; body 7 appears and body 6 is gone (only common spheres count)
    after = components([1, 2, 3, 4, 5, 7], [(2, 3), (3, 4)], [1] * 6)
    assert transitions(before, after) == (1, 1)
    assert transitions(before, before) == (0, 0)
    assert transitions(before, components([9], [], [1])) == (0, 0)
    whole = components([1, 2, 3, 4, 5, 6], [(1, 2), (2, 3), (3, 4), (4, 5), (5, 6)], [1] * 6)
    assert transitions(before, whole) == (0, 1) and transitions(whole, before) == (1, 0)


def test_size_distribution_bins_double():
    a = components(list(range(10)), [(0, 1), (1, 2), (2, 3), (4, 5)], [1] * 10)
    counts, edges = a.size_distribution()
    assert counts.sum() == a.count == 6  # sizes 4, 2, 1, 1, 1, 1
    assert counts[0] == 4 and edges[0] == 1
    mass, _ = a.size_distribution(by='mass')
    assert mass.sum() == pytest.approx(1.0)
    with pytest.raises(ValueError, match='by='):
        a.size_distribution(by='volume')


def test_linear_scaling_of_a_large_random_graph():
    rng = numpy.random.default_rng(1)
    n = 100000
    edges = rng.integers(0, n, size=(150000, 2))
    a = components(numpy.arange(n), edges, numpy.ones(n))
    assert a.sizes.sum() == n and a.sizes[0] > n / 2  # above the percolation threshold (mean degree 3)
