// Time-step limits of the explicit scheme (physics.md §3).
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <algorithm>
#include <cmath>
#include <limits>

namespace viscbridge {

// P14: Δt ≤ 4/(d + √(d² + 4κ)) for one body with damping rate d and stiffness rate κ (both summed
// over its contacts with the mobilities 1/m_i + 1/m_j).  Dashpots alone (κ = 0): 2/d; springs
// alone (d = 0): 2/√κ.  Rigorous and sufficient; exact for an equal pair.
inline double networkLimit(double d, double kappa)
{
	if (d <= 0 && kappa <= 0) return std::numeric_limits<double>::infinity();
	return 4.0 / (d + std::sqrt(d * d + 4.0 * kappa));
}
inline double dashpotLimit(double d) { return d > 0 ? 2.0 / d : std::numeric_limits<double>::infinity(); }
inline double springLimit(double kappa) { return kappa > 0 ? 2.0 / std::sqrt(kappa) : std::numeric_limits<double>::infinity(); }

// The viscous coefficient of a bridge as the time step sees it (C_n + w_t C_t at S_min, P14a) is
// each model's stepCoefficient(), summed in PairConstants::viscousStepCoefficient.

// Rayleigh-wave time of a sphere (Thornton; as YADE's utils.RayleighWaveTimeStep):
// T_R = π r √(ρ/G) / (0.1631 ν + 0.876605), G = E/(2(1+ν)).
inline double rayleighTime(double radius, double density, double young, double poisson)
{
	const double G = young / (2 * (1 + poisson));
	return pi * radius * std::sqrt(density / G) / (0.1631 * poisson + 0.876605);
}

} // namespace viscbridge
