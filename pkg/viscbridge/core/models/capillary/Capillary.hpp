// Capillary force of a liquid bridge (physics.md §8), one slot of SubModels.hpp.
//
// force(S) is the magnitude of the attraction at gap S (held at its contact value in overlap);
// stiffness(S) = |dF/dS| (P22, 0 in overlap); stepStiffness() its largest value over the bridge's
// life, 0 < S ≤ S_rup, which the time stepper uses like the viscous coefficients at S_min.  Both
// models use the Derjaguin radius R = 2 r̄ (R = r for equal spheres, 2r against a wall).
#pragma once
#include "viscbridge/core/models/SubModel.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <algorithm>
#include <cmath>

namespace viscbridge {

namespace detail {
	inline constexpr std::array<EnergyKey, 1> capillaryEnergyKeys { EnergyKey::capillaryWork };
	inline double derjaguinRadius(double rBar) { return 2 * rBar; }
	// the largest |dF/dS| of `model` over (0, sRup], sampled log-uniformly with a 5 % margin for
	// what falls between samples (used where no closed form is at hand)
	template <class M> double sampledMaxStiffness(const M& model, double sRup)
	{
		double best = model.stiffness(0.0);
		for (int k = 0; k <= 48; ++k)
			best = std::max(best, model.stiffness(sRup * std::pow(10.0, -6.0 * (1 - k / 48.0))));
		return 1.05 * best;
	}
}

struct NoCapillary {
	static constexpr const char*                name         = "none";
	static constexpr Capabilities               capabilities { false, false, true, false, true };
	static constexpr std::array<EnergyKey, 0> energyKeys {};
	static NoCapillary make(const BridgeInputs&) { return {}; }
	double             force(double) const { return 0; }
	double             stiffness(double) const { return 0; }
	double             stepCoefficient(const BridgeInputs&) const { return 0; }
	double             stepStiffness(const BridgeInputs&) const { return 0; }
};

// P19 (Willett et al. 2000, closed form; YADE's Willett_analytic for two spheres):
// F = 2πRγ cos θ / (1 + 2.1 s⁺ + 10 s⁺²), s⁺ = (S/2)√(R/V).
struct WillettCapillary {
	static constexpr const char*  name         = "willett";
	static constexpr Capabilities capabilities { true, false, true, true, true };
	static constexpr auto         energyKeys   = detail::capillaryEnergyKeys;
	double                        contactForce; // 2πRγ cos θ [N]
	double                        k;            // s⁺ per metre of gap, ½√(R/V) [1/m]
	WillettCapillary(double rBar, double surfaceTension, double contactAngle, double volume)
	        : contactForce(2 * pi * detail::derjaguinRadius(rBar) * surfaceTension * std::cos(contactAngle))
	        , k(0.5 * std::sqrt(detail::derjaguinRadius(rBar) / volume))
	{
	}
	static WillettCapillary make(const BridgeInputs& b) { return WillettCapillary(b.rBar, b.surfaceTension, b.contactAngle, b.volume); }
	double                  force(double S) const
	{
		const double s = S > 0 ? k * S : 0.0;
		return contactForce / (1 + 2.1 * s + 10 * s * s);
	}
	double stiffness(double S) const
	{
		if (S <= 0) return 0;
		const double s = k * S, d = 1 + 2.1 * s + 10 * s * s;
		return contactForce * k * (2.1 + 20 * s) / (d * d);
	}
	// P22: the maximum of |dF/dS| is at s⁺ where 600 s⁺² + 126 s⁺ − 11.18 = 0 (1.224 F(0)√(R/V))
	double stepStiffness(const BridgeInputs&) const
	{
		const double s = (-126 + std::sqrt(126.0 * 126.0 + 4 * 600 * 11.18)) / 1200;
		return stiffness(s / k);
	}
	double stepCoefficient(const BridgeInputs&) const { return 0; }
	// P21: U(S) = ∫_S^{S_rup} F dS′ = (F(0)/k)(2/q)[atan((20 s⁺_rup + 2.1)/q) − atan((20 s⁺ + 2.1)/q)],
	// q = √35.59; in overlap U(0) + F(0)|S|.
	double work(double S, double sRup) const
	{
		const double q = std::sqrt(35.59), s = S > 0 ? k * S : 0.0;
		const double U = contactForce / k * (2 / q) * (std::atan((20 * k * sRup + 2.1) / q) - std::atan((20 * s + 2.1) / q));
		return S > 0 ? U : U - contactForce * S;
	}
};

// P20 (Rabinovich et al. 2005, fixed volume): F = 2πRγ [cos θ/(1 + S/(2d)) + sin α sin(θ + α)],
// d = (S/2)(√(1 + x) − 1), x = 2V/(πRS²) (Pitois' x, P5), α = √(2d/R).  1/(1 + S/(2d)) is
// 1 − (1 + x)^(−1/2), written −expm1(−½ log1p(x)) so that it keeps its precision at large gaps.
struct RabinovichCapillary {
	static constexpr const char*  name         = "rabinovich";
	static constexpr Capabilities capabilities { true, false, true, true, true };
	static constexpr auto         energyKeys   = detail::capillaryEnergyKeys;
	double                        scale;        // 2πRγ [N]
	double                        cosTheta, theta, R;
	double                        c;            // 2V/(πR) [m²]: x = c/S²
	RabinovichCapillary(double rBar, double surfaceTension, double contactAngle, double volume)
	        : scale(2 * pi * detail::derjaguinRadius(rBar) * surfaceTension)
	        , cosTheta(std::cos(contactAngle))
	        , theta(contactAngle)
	        , R(detail::derjaguinRadius(rBar))
	        , c(2 * volume / (pi * detail::derjaguinRadius(rBar)))
	{
	}
	static RabinovichCapillary make(const BridgeInputs& b) { return RabinovichCapillary(b.rBar, b.surfaceTension, b.contactAngle, b.volume); }
	// the immersion depth d and the filling angle α; at contact d = √c/2
	double immersion(double S) const
	{
		if (S <= 0) return 0.5 * std::sqrt(c);
		const double x = c / (S * S);
		return 0.5 * S * x / (std::sqrt(1 + x) + 1);
	}
	double force(double S) const
	{
		const double alpha = std::sqrt(2 * immersion(S) / R);
		const double first = S > 0 ? -std::expm1(-0.5 * std::log1p(c / (S * S))) : 1.0;
		return scale * (cosTheta * first + std::sin(alpha) * std::sin(theta + alpha));
	}
	double stiffness(double S) const
	{
		const double Se = S > 0 ? S : 0.0;
		const double alpha = std::sqrt(2 * immersion(Se) / R);
		// d/dS of the first term and of d (their limits at contact: −1/√c and −½)
		double dFirst = -1 / std::sqrt(c), dImmersion = -0.5;
		if (Se > 0) {
			const double x = c / (Se * Se), root = std::sqrt(1 + x);
			dFirst     = -x / (root * (1 + x) * Se);
			dImmersion = 0.5 * x / (root + 1) - 0.5 * x / root;
		}
		return S <= 0 ? 0.0 : std::abs(scale * (cosTheta * dFirst + std::sin(theta + 2 * alpha) * dImmersion / (R * alpha)));
	}
	double stepStiffness(const BridgeInputs& b) const { return detail::sampledMaxStiffness(*this, b.sRup); }
	double stepCoefficient(const BridgeInputs&) const { return 0; }
};

} // namespace viscbridge
