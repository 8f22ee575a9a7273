// Normal viscous force models F_v^n = −C^n v_r^n (physics.md P3), one slot of SubModels.hpp.
//
// A model is a small value type holding its constants, built once per interaction; coefficient(S)
// is evaluated at the clamped gap S = max(S, S_min) (P6).
#pragma once
#include "viscbridge/core/models/SubModel.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <cmath>

namespace viscbridge {

struct NoNormalViscous {
	static constexpr const char*                name         = "none";
	static constexpr Capabilities               capabilities { false, true, false, false, true };
	static constexpr std::array<EnergyKey, 0> energyKeys {};
	static NoNormalViscous make(const BridgeInputs&) { return {}; }
	double                 coefficient(double) const { return 0; }
	double                 stepCoefficient(const BridgeInputs&) const { return 0; }
};

// P4 (Adams & Perchard 1985): C^n = 6πμ r̄² / S.
struct AdamsPerchard {
	static constexpr const char*                name         = "adamsPerchard";
	static constexpr Capabilities               capabilities { true, true, false, true, true };
	static constexpr std::array<EnergyKey, 1> energyKeys { EnergyKey::viscDissipNormal };
	double                                      sixPiMuR2; // 6πμ r̄²
	AdamsPerchard(double viscosity, double rBar) : sixPiMuR2(6 * pi * viscosity * rBar * rBar) {}
	static AdamsPerchard make(const BridgeInputs& b) { return AdamsPerchard(b.viscosity, b.rBar); }
	double               coefficient(double S) const { return sixPiMuR2 / S; }
	// the stiffest the dashpot gets: at S_min (coefficients are constant below it, P6)
	double stepCoefficient(const BridgeInputs& b) const { return coefficient(b.sMin); }
};

// P5 (Pitois et al. 2000): C^n = 6πμ r̄²/S · [1 − (1 + V/(π r̄ S²))^(−1/2)]².
// The bracket is written as −expm1(−½ log1p(x)) with x = V/(π r̄ S²): it keeps full precision for
// small x (large gaps, small bridges) where 1 − (1+x)^(−1/2) ≈ x/2 would cancel.
struct Pitois {
	static constexpr const char*                name         = "pitois";
	static constexpr Capabilities               capabilities { true, true, false, true, true };
	static constexpr std::array<EnergyKey, 1> energyKeys { EnergyKey::viscDissipNormal };
	double                                      sixPiMuR2; // 6πμ r̄²
	double                                      a2;        // V/(π r̄)
	Pitois(double viscosity, double rBar, double volume)
	        : sixPiMuR2(6 * pi * viscosity * rBar * rBar)
	        , a2(volume / (pi * rBar))
	{
	}
	static Pitois make(const BridgeInputs& b) { return Pitois(b.viscosity, b.rBar, b.volume); }
	// Pitois' volume factor [1 − (1 + V/(π r̄ S²))^(−1/2)]² ∈ (0, 1]; → 1 as V → ∞ (Adams–Perchard).
	double volumeFactor(double S) const
	{
		const double bracket = -std::expm1(-0.5 * std::log1p(a2 / (S * S)));
		return bracket * bracket;
	}
	double coefficient(double S) const { return sixPiMuR2 / S * volumeFactor(S); }
	double stepCoefficient(const BridgeInputs& b) const { return coefficient(b.sMin); }
};

} // namespace viscbridge
