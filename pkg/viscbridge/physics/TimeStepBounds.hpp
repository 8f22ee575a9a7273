// Time-step limits of the explicit scheme (physics.md §3).
#pragma once
#include "GoldmanCoefficients.hpp"
#include "ModelNames.hpp"
#include "NormalViscous.hpp"
#include "Vector.hpp"
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

// Weight of a tangential coefficient in P14: a tangential force at arm a moves a sphere's surface
// by (1/m)(1 + a²m/I) = (1/m)(1 + 2.5 (a/r)²) per unit force; with arm r that is the 3.5 of P14.
// 'slip' reaches the mid-gap point, a = r + S_min/2 (largest at S = S_min, constant below).
inline double tangentialWeight(TangentialModel model, double radius1, double radius2, double sMin)
{
	if (model != TangentialModel::slip) return 3.5;
	double worst = 1.0;
	for (double r : { radius1, radius2 })
		if (r > 0) worst = std::max(worst, (r + 0.5 * sMin) / r);
	return 1.0 + 2.5 * worst * worst;
}

// C_n + w_t C_t at S_min, the largest viscous damping a bridge can exert (coefficients grow as the
// gap closes and are constant below S_min, P6).  C_t = C_T for slip and goldman, max(C_T, C_R) for
// washino (physics.md §3), 0 without a tangential model.
inline double viscousStepCoefficient(NormalModel normal, TangentialModel tangential, double viscosity, double rBar, double volume, double sMin,
                                     double radius1, double radius2)
{
	if (viscosity <= 0) return 0;
	double c = 0;
	if (normal == NormalModel::adamsPerchard) c += AdamsPerchard(viscosity, rBar).coefficient(sMin);
	if (normal == NormalModel::pitois) c += Pitois(viscosity, rBar, volume).coefficient(sMin);
	if (tangential != TangentialModel::none) {
		const GoldmanCoefficients g  = goldmanCoefficients(6 * pi * viscosity * rBar, rBar, sMin);
		const double              ct = tangential == TangentialModel::washino ? std::max(g.translation, g.coupling) : g.translation;
		c += tangentialWeight(tangential, radius1, radius2, sMin) * std::max(ct, 0.0);
	}
	return c;
}

// Rayleigh-wave time of a sphere (Thornton; as YADE's utils.RayleighWaveTimeStep):
// T_R = π r √(ρ/G) / (0.1631 ν + 0.876605), G = E/(2(1+ν)).
inline double rayleighTime(double radius, double density, double young, double poisson)
{
	const double G = young / (2 * (1 + poisson));
	return pi * radius * std::sqrt(density / G) / (0.1631 * poisson + 0.876605);
}

} // namespace viscbridge
