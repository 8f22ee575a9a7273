// The linear maps of one interaction as the time step sees it (physics.md P16–P18): its damping at
// its stiffest — bridge coefficients at S_min (P6), where they are largest, and the contact's
// dashpots at the current stiffness — and its stiffness: Hertz–Mindlin's tangent stiffness at the
// contact point and the capillary force's largest |dF/dS| (P22).  Built from the same constants and
// models the law's kernel uses.
#pragma once
#include "viscbridge/core/pair/PairConstants.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include <cmath>

namespace viscbridge {

// What the maps depend on now.
struct PairNow {
	Vec3   n;
	double S;                // gap, negative in overlap
	double radius1, radius2; // true radii, 0 for a wall side
	double kn, ks;           // Hertz–Mindlin tangent stiffness now (0 without contact)
	bool   bridge;
};

struct PairMaps {
	ViscousBlock damping, stiffness;
};

namespace detail {
	// The bridge's viscous damping with every coefficient at S_min (computed with the constants).
	inline void stiffestBridgeDamping(const PairConstants& k, const PairNow& p, ViscousBlock& d)
	{
		d.cn         = k.stiffestNormal;
		d.resistance = k.stiffestTangential;
		d.a1         = detail::arm(p.radius1, k.armGapFraction * p.S);
		d.a2         = detail::arm(p.radius2, k.armGapFraction * p.S);
	}
}

// viscousExplicit: whether the bridges' viscous forces are explicit (with implicit integration
// they leave the time step, P15).
inline PairMaps pairMaps(const PairConstants& k, const ModelSelection& s, const PairNow& p, bool viscousExplicit)
{
	PairMaps     m;
	const bool   contact = p.S <= 0;
	const double contactArm1 = detail::arm(p.radius1, 0.5 * std::min(p.S, 0.0)), contactArm2 = detail::arm(p.radius2, 0.5 * std::min(p.S, 0.0));
	m.damping.n = m.stiffness.n = p.n;
	m.damping.a1 = m.stiffness.a1 = contactArm1;
	m.damping.a2 = m.stiffness.a2 = contactArm2;
	if (p.bridge && viscousExplicit) detail::stiffestBridgeDamping(k, p, m.damping);
	if (contact) {
		visitModel(s.damping, DampingModels(), [&](auto i) { // P2b: 2β√(m* k), at the contact point
			using D = DampingModels::At<decltype(i)::value>;
			if constexpr (D::capabilities.enabled) {
				const D&     d  = k.damping.as<D>();
				const double cn = 2 * d.betan * std::sqrt(k.mEff * p.kn), cs = 2 * d.betas * std::sqrt(k.mEff * p.ks);
				m.damping.cn += cn;
				m.damping.resistance.m11 += cs, m.damping.resistance.m12 += cs, m.damping.resistance.m21 += cs, m.damping.resistance.m22 += cs;
			}
		});
		m.stiffness.cn = p.kn;
		m.stiffness.resistance = { p.ks, p.ks, p.ks, p.ks };
	}
	if (p.bridge) m.stiffness.cn += k.capillaryStiffness; // the pull's |dF/dS| acts along n
	m.damping.valid = m.damping.cn > 0 || m.damping.resistance.m11 > 0 || m.damping.resistance.m22 > 0;
	m.stiffness.valid = m.stiffness.cn > 0 || m.stiffness.resistance.m11 > 0;
	return m;
}

} // namespace viscbridge
