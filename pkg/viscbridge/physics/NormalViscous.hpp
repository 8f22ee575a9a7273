// Normal viscous force models F_v^n = -C^n v_r^n (P3), selectable per scene.
//
// Each model is a small value type built once per interaction (when the physics is created) with
// coefficient(S) evaluated at the clamped gap S = max(S, S_min) (P6).  `enabled` lets the pair
// kernel drop every trace of an unselected model at compile time.
#pragma once
#include "Vector.hpp"
#include <cmath>

namespace viscbridge {

struct NoNormalViscous {
	static constexpr bool enabled = false;
	static constexpr const char* name = "none";
	double coefficient(double) const { return 0; }
};

// P4 (Adams & Perchard 1985): C^n = 6πμ r̄² / S.
struct AdamsPerchard {
	static constexpr bool enabled = true;
	static constexpr const char* name = "adamsPerchard";
	double sixPiMuR2; // 6πμ r̄²
	AdamsPerchard(double viscosity, double rBar) : sixPiMuR2(6 * pi * viscosity * rBar * rBar) {}
	double coefficient(double S) const { return sixPiMuR2 / S; }
};

// P5 (Pitois et al. 2000): C^n = 6πμ r̄²/S · [1 − (1 + V/(π r̄ S²))^(−1/2)]².
// The bracket is written as −expm1(−½ log1p(x)) with x = V/(π r̄ S²): it keeps full precision for
// small x (large gaps, small bridges) where 1 − (1+x)^(−1/2) ≈ x/2 would cancel.
struct Pitois {
	static constexpr bool enabled = true;
	static constexpr const char* name = "pitois";
	double sixPiMuR2; // 6πμ r̄²
	double a2;        // V/(π r̄)
	Pitois(double viscosity, double rBar, double volume)
	        : sixPiMuR2(6 * pi * viscosity * rBar * rBar)
	        , a2(volume / (pi * rBar))
	{
	}
	// Pitois' volume factor [1 − (1 + V/(π r̄ S²))^(−1/2)]² ∈ (0, 1]; → 1 as V → ∞ (Adams–Perchard).
	double volumeFactor(double S) const
	{
		const double bracket = -std::expm1(-0.5 * std::log1p(a2 / (S * S)));
		return bracket * bracket;
	}
	double coefficient(double S) const { return sixPiMuR2 / S * volumeFactor(S); }
};

} // namespace viscbridge
