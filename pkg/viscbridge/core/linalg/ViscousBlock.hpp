// A linear damping (or stiffness) map of one bridge or contact between two bodies, in the form the
// implicit solver (P15) and the time step's network operator (P16–P18) both use.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"

namespace viscbridge {

// The resistance of a model in the (u, s) coordinates: force on body 1 F = −(m11 u + m12 s) and
// torque-force G = −(m21 u + m22 s), whose torques are a_k n × G.  The viscous power is then
// −(F·u + G·s) for any model.
struct TangentialResistance {
	double m11 = 0, m12 = 0, m21 = 0, m22 = 0;
};

// A bridge's damping as a linear map, for the implicit solver (P15): with dv = V1 − V2 (a wall side's
// V at its anchor, r_k from its centre), u = (I − nnᵀ)dv and s = (a1 ω1 + a2 ω2) × n, the force on
// body 1 is −(cn (n·dv) n + m11 u + m12 s), the torque on sphere side k is a_k n × (−(m21 u + m22 s)).
struct ViscousBlock {
	bool                 valid = false;
	Vec3                 n     = Vec3::Zero();
	double               cn    = 0;
	TangentialResistance resistance;
	double               a1 = 0, a2 = 0;                      // arms of the sphere sides (0 for a wall side)
	Vec3                 r1 = Vec3::Zero(), r2 = Vec3::Zero(); // wall anchor − wall centre (0 for a sphere side)
};

// The "resistance" of one bridge for given velocities: R with D·q = R (the forces are −R).
struct BridgeResistance {
	Vec3 force1, torque1, force2, torque2;
};

// The bridge map for given end velocities (see ViscousBlock): forces −force_k, torques −torque_k.
// `anchored` = false skips the wall-anchor terms, for a bridge with r1 = r2 = 0 (two spheres): the
// same map, fewer operations in the implicit solver's products.
template <bool anchored = true>
inline BridgeResistance bridgeResistance(const ViscousBlock& b, const Vec3& v1, const Vec3& w1, const Vec3& v2, const Vec3& w2, const Vec3& shiftVel)
{
	const Vec3   dv = anchored ? Vec3((v1 + w1.cross(b.r1)) - (v2 + w2.cross(b.r2) + shiftVel)) : Vec3(v1 - v2 - shiftVel);
	const double vn = b.n.dot(dv);
	const Vec3   u  = dv - vn * b.n;
	const Vec3   s  = (b.a1 * w1 + b.a2 * w2).cross(b.n);
	const auto&  m  = b.resistance;
	const Vec3   F  = b.cn * vn * b.n + m.m11 * u + m.m12 * s;
	const Vec3   nG = b.n.cross(m.m21 * u + m.m22 * s);
	if (!anchored) return { F, b.a1 * nG, -F, b.a2 * nG };
	return { F, b.a1 * nG + b.r1.cross(F), -F, b.a2 * nG - b.r2.cross(F) };
}

inline bool isAnchored(const ViscousBlock& b) { return !b.r1.isZero(0) || !b.r2.isZero(0); }

} // namespace viscbridge
