"""The result of :func:`~viscbridge.criteria.critical_dt`: a table of :class:`Bound` rows and what they imply
(:class:`TimeStepCriteria`: the stable step, the step free of spurious rebounds, the governing bound
and the regime), and its text form.  Plain Python.
"""
from dataclasses import dataclass, field

__all__ = ['Bound', 'TimeStepCriteria']


@dataclass(frozen=True)
class Bound:
    """One time-step limit.

    kind: 'stability' (Δt above it diverges), 'design' (stable, but an approaching pair rebounds
    spuriously above it) or 'info' (a time scale, not a limit).  regime: 'viscous' when the limit is
    set by a bridge's viscous coefficient, 'collision' when by the dry contact; for the combined
    bounds (P13, P14) the part that dominates (viscous iff the dashpot-only limit is the smaller).
    """
    name: str
    value: float
    kind: str
    formula: str
    regime: str = ''


@dataclass
class TimeStepCriteria:
    """The result of :func:`~viscbridge.criteria.critical_dt`: every bound, and what they imply.

    stability_limit   min over 'stability' bounds: the largest stable Δt (apply a safety factor)
    no_rebound_limit  min(stability_limit, min over 'design' bounds)
    governing         name of the bound attaining stability_limit
    regime            'viscous' or 'collision': which physics sets the governing bound
    parameters        the inputs, after defaults (S_min, V) were filled in
    derived           r̄, m*, E*, G*, δ_max, k_n, k_t, C^n, C_T, C_R, C_W, t_v, ... (SI units)
    """
    bounds: list
    parameters: dict = field(default_factory=dict)
    derived: dict = field(default_factory=dict)
    stability_limit: float = field(init=False)
    no_rebound_limit: float = field(init=False)
    governing: str = field(init=False)
    regime: str = field(init=False)

    def __post_init__(self):
        stab = [b for b in self.bounds if b.kind == 'stability']
        best = min(stab, key=lambda b: b.value)  # first of equal values: table order
        self.stability_limit = best.value
        self.governing = best.name
        self.regime = best.regime
        design = [b.value for b in self.bounds if b.kind == 'design']
        self.no_rebound_limit = min([self.stability_limit] + design)

    def bound(self, name):
        """The :class:`Bound` called ``name`` (KeyError when it is not in the table)."""
        for b in self.bounds:
            if b.name == name:
                return b
        raise KeyError('no bound %r; bounds: %s' % (name, ', '.join(b.name for b in self.bounds)))

    def names(self):
        return [b.name for b in self.bounds]

    def as_dict(self):
        """Plain-data view: dicts, lists, floats, strings (t_v is inf when there is no normal dashpot)."""
        return {'stability_limit': self.stability_limit, 'no_rebound_limit': self.no_rebound_limit,
                'governing': self.governing, 'regime': self.regime,
                'bounds': [{'name': b.name, 'value': b.value, 'kind': b.kind, 'regime': b.regime,
                            'formula': b.formula} for b in self.bounds],
                'parameters': dict(self.parameters), 'derived': dict(self.derived)}

    def __str__(self):
        p = self.parameters
        head = ('ViscBridge time-step criteria: %s, r = %s m%s, rho = %g kg/m3, E = %g Pa, nu = %g, '
                'mu = %g Pa.s, S_min = %.4g m, %s / %s, %s, z = %g, v = %g m/s' % (
                    'sphere-wall' if p['wall'] else 'sphere-sphere', _g(p['radius']),
                    '' if p['wall'] or p['radius2'] == p['radius'] else ' & %s m' % _g(p['radius2']),
                    p['density'], p['young'], p['poisson'], p['viscosity'], p['s_min'],
                    p['normal_model'], p['tangential_model'], p['integration'], p['coordination'],
                    p['impact_velocity']))
        w = max(len(b.name) for b in self.bounds)
        rows = ['  %-*s  %-10s  %-9s  %-9s  %s' % (w, 'bound', 'value [s]', 'kind', 'regime', 'formula')]
        for b in self.bounds:
            rows.append('  %-*s  %-10s  %-9s  %-9s  %s' % (w, b.name, '%.4g' % b.value, b.kind,
                                                           b.regime or '-', b.formula))
        tail = ['stability limit:  %.4g s  (governing: %s, regime: %s)' % (
                    self.stability_limit, self.governing, self.regime),
                'no-rebound limit: %.4g s' % self.no_rebound_limit]
        return '\n'.join([head] + rows + tail)

    def __repr__(self):
        return ('TimeStepCriteria(stability_limit=%.4g, no_rebound_limit=%.4g, governing=%r, regime=%r)'
                % (self.stability_limit, self.no_rebound_limit, self.governing, self.regime))


def _g(x):
    return '%g' % x


def _regime(bridge_dashpot_limit, elastic_limit):
    """Dominant part of a combined bound: viscous iff the bridge dashpots alone give the smaller limit."""
    return 'viscous' if bridge_dashpot_limit < elastic_limit else 'collision'

