// Goldman, Cox & Brenner (1967) small-gap resistance coefficients of a sphere near a plane, in
// the reduced-radius form used by the paper (physics.md §2).
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <cmath>

namespace viscbridge {

struct GoldmanCoefficients {
	double translation; // C_T (P8): force from relative sliding
	double coupling;    // C_R (P9): force from relative rotation, = torque from sliding (reciprocity)
	double rotation;    // C_W: torque-equivalent force from relative rotation
};

// C_T = 6πμ r̄ [(8/15) ln(r̄/S) + 0.9588]            (P8)
// C_R = 6πμ r̄ [(2/15) ln(r̄/S) + 0.2526]            (P9; + sign: the published paper prints −, a misprint, physics.md §9)
// C_W = 6πμ r̄ [(8/15) ln(r̄/S) + 0.5089]            (goldman model, physics.md §2)
// S is the clamped gap max(S, S_min) (P6).
inline GoldmanCoefficients goldmanCoefficients(double sixPiMuR, double rBar, double S)
{
	const double L = std::log(rBar / S);
	return { sixPiMuR * (8.0 / 15.0 * L + 0.9588), sixPiMuR * (2.0 / 15.0 * L + 0.2526), sixPiMuR * (8.0 / 15.0 * L + 0.5089) };
}

} // namespace viscbridge
