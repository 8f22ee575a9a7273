// Hertz–Mindlin contact (physics.md §2, "Contact"), with the constants and the order of operations
// of YADE's Ip2_FrictMat_FrictMat_MindlinPhys + Law2_ScGeom_MindlinPhys_Mindlin, so that a scene
// with every viscous effect off follows YADE's own trajectories.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include "viscbridge/core/models/EnergyKeys.hpp"
#include <array>
#include <cmath>

namespace viscbridge {

struct ElasticProperties {
	double young, poisson, frictionAngle;
};

// The dry contact books its friction and its elastic energy (P2a, E3).
inline constexpr std::array<EnergyKey, 2> contactEnergyKeys { EnergyKey::plastDissip, EnergyKey::elastPotential };

struct HertzMindlinConstants {
	double kno;    // normal force Fn = kno δ^{3/2}
	double kso;    // tangential stiffness ks = kso δ^{1/2}
	double tanPhi; // Coulomb limit |Fs| ≤ tanφ Fn
};

// Same formulas as YADE's Ip2_FrictMat_FrictMat_MindlinPhys.  R is built from the radii YADE's
// geometry functor reports (for a wall or facet these include its artificial radius); this is the
// one place where that radius is used, to stay identical to YADE's contact law.
inline HertzMindlinConstants hertzMindlinConstants(const ElasticProperties& a, const ElasticProperties& b, double refR1, double refR2)
{
	const double Da = refR1 > 0 ? refR1 : refR2;
	const double Db = refR2 > 0 ? refR2 : refR1;
	const double Ga = a.young / (2 * (1 + a.poisson));
	const double Gb = b.young / (2 * (1 + b.poisson));
	const double G  = 1.0 / ((2 - a.poisson) / Ga + (2 - b.poisson) / Gb);
	const double E  = a.young * b.young / ((1. - a.poisson * a.poisson) * b.young + (1. - b.poisson * b.poisson) * a.young);
	const double R  = Da * Db / (Da + Db);
	return { 4. / 3. * E * std::sqrt(R), 8 * std::sqrt(R) * G, std::tan(std::min(a.frictionAngle, b.frictionAngle)) };
}

// Damping ratio β for a constant coefficient of restitution e (Thornton et al. 2013, (B6)–(B7)),
// as YADE's Ip2_FrictMat_FrictMat_MindlinPhys computes it from `en`.  e = 1 gives 0.
inline double dampingRatioFromRestitution(double e)
{
	if (e == 1.0) return 0;
	static constexpr double h[10] = { -6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757, -1489.915 };
	double poly = h[9];
	for (int i = 8; i >= 0; --i)
		poly = h[i] + e * poly;
	const double alpha = e * poly;
	return std::sqrt(1.0 / (1.0 - (1.0 + e) * (1.0 + e) * std::exp(alpha)) - 1.0);
}

} // namespace viscbridge
