// Tangential viscous force models (physics.md §2), selectable per scene.
//
// Kinematics, with n the unit normal from body 1 to body 2 (YADE's ScGeom convention):
//   u = tangential part of the relative velocity V1 − V2 of the bridge ends     (v_r^t, P0)
//   s = (a1 ω1 + a2 ω2) × n                                                     (ω_r × n, P0)
// where a_k is the arm of side k: its radius r_k for a sphere (r_k + S/2 for `slip`, the mid-gap
// point) and 0 for a wall, facet or box, whose own motion enters through V_k instead.
// Every model returns the force on body 1 (body 2 gets the opposite), the torques on the sphere
// sides, and the viscous dissipation rate −P ≥ 0 split into a sliding part and a rolling part:
// writing −P = wᵀK w with w = (u, s) and K's symmetric part [[a, b], [b, c]], the split is the
// Cholesky form a|u + (b/a)s|² + (c − b²/a)|s|².  The second term is the dissipation that resists
// rolling; it is negative only for `washino`, whose K is indefinite (P7 is not dissipative).
#pragma once
#include "viscbridge/core/models/tangential/GoldmanCoefficients.hpp"
#include "viscbridge/core/models/SubModel.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include <algorithm>
#include <cmath>

namespace viscbridge {

struct TangentialViscousResult {
	Vec3   force1  = Vec3::Zero(); // on body 1
	Vec3   torque1 = Vec3::Zero(); // on body 1 (sphere side only)
	Vec3   torque2 = Vec3::Zero(); // on body 2 (sphere side only)
	double ct      = 0;            // C_T actually used [N·s/m]
	double cr      = 0;            // C_R actually used (0 for slip)
	double dissipationSliding = 0; // a|u + (b/a)s|²  [W]
	double dissipationRolling = 0; // (c − b²/a)|s|²  [W]
	Vec3   u = Vec3::Zero(), s = Vec3::Zero(); // the kinematics the force was computed from
	TangentialResistance resistance;
};

// Work done against the force of a previous step (kinematics uPrev, sPrev, resistance m) while the
// velocities went from (uPrev, sPrev) to (uNow, sNow): W = (m11 u_p + m12 s_p)·ū + (m21 u_p + m22 s_p)·s̄
// per unit time, ū, s̄ the means.  This is the leapfrog-consistent dissipation (it matches the
// change of kinetic energy YADE reports).  Split as the instantaneous power: the sliding part
// a(ū + (b/a)s̄)·(u_p + (b/a)s_p) with K's symmetric part [[a, b], [b, c]], the rest (the rolling
// resistance, and for washino the antisymmetric part of K) as rolling.
struct TangentialWork {
	double sliding = 0, rolling = 0;
};
inline TangentialWork tangentialWork(const TangentialResistance& m, const Vec3& uPrev, const Vec3& sPrev, const Vec3& uNow, const Vec3& sNow)
{
	const Vec3     uMid = 0.5 * (uPrev + uNow), sMid = 0.5 * (sPrev + sNow);
	const double   b = 0.5 * (m.m12 + m.m21), antisymmetric = 0.5 * (m.m21 - m.m12) * (uPrev.dot(sMid) - sPrev.dot(uMid));
	TangentialWork w;
	if (m.m11 > 0) {
		// written with b/m11 (exactly 1 for slip) so that slip's rolling part is exactly 0
		const double ratio = b / m.m11;
		w.sliding          = m.m11 * (uMid + ratio * sMid).dot(uPrev + ratio * sPrev);
		w.rolling          = (m.m22 - b * ratio) * sMid.dot(sPrev) + antisymmetric;
	} else {
		w.rolling = (m.m21 * uPrev + m.m22 * sPrev).dot(sMid) + m.m12 * sPrev.dot(uMid);
	}
	return w;
}

// Inputs shared by the models: S the actual gap (arms), sEff = max(S, S_min) (coefficients).
struct TangentialKinematics {
	Vec3   n, u, omega1, omega2;
	double radius1, radius2; // 0 for a side that is not a sphere
	double S, sEff;
};

struct NoTangentialViscous {
	static constexpr const char*                name           = "none";
	static constexpr Capabilities               capabilities   { false, true, false, false, true };
	static constexpr std::array<EnergyKey, 0> energyKeys     {};
	static constexpr double                     armGapFraction = 0;
	static NoTangentialViscous make(const BridgeInputs&) { return {}; }
	double                     stepCoefficient(const BridgeInputs&) const { return 0; }
};

namespace detail {
	inline double arm(double radius, double gapShare) { return radius > 0 ? radius + gapShare : 0.0; }
	inline double clampPositive(double x) { return x > 0 ? x : 0.0; }
	// Weight of a tangential coefficient in P14 (physics.md P14a): a tangential force at arm a moves a
	// sphere's surface by (1/m)(1 + 2.5 (a/r)²) per unit force; arm r gives the 3.5 of P14.
	inline double tangentialWeight(double radius1, double radius2, double armGap)
	{
		double worst = 1.0;
		for (double r : { radius1, radius2 })
			if (r > 0) worst = std::max(worst, (r + armGap) / r);
		return 1.0 + 2.5 * worst * worst;
	}
	inline constexpr std::array<EnergyKey, 2> tangentialEnergyKeys { EnergyKey::viscDissipTangential, EnergyKey::viscDissipRotational };
}

// P7 exactly, for reproducing the paper: F = −(C_T u + C_R s), torques r_k n × F.
// Not dissipative unless C_T = C_R (physics.md §2): a sliding sphere can gain kinetic energy.
struct WashinoTangential {
	static constexpr const char*  name           = "washino";
	static constexpr Capabilities capabilities   { true, false, false, true, false }; // not dissipative: no implicit solve
	static constexpr auto         energyKeys     = detail::tangentialEnergyKeys;
	static constexpr double       armGapFraction = 0; // arms are the radii
	double sixPiMuR, rBar;
	WashinoTangential(double viscosity, double rBar_) : sixPiMuR(6 * pi * viscosity * rBar_), rBar(rBar_) {}
	static WashinoTangential make(const BridgeInputs& b) { return WashinoTangential(b.viscosity, b.rBar); }
	// P14 with C_t = max(C_T, C_R) (physics.md P14a)
	double stepCoefficient(const BridgeInputs& b) const
	{
		const GoldmanCoefficients c = goldmanCoefficients(sixPiMuR, rBar, b.sMin);
		return 3.5 * detail::clampPositive(std::max(c.translation, c.coupling));
	}

	TangentialViscousResult evaluate(const TangentialKinematics& k) const
	{
		const GoldmanCoefficients c  = goldmanCoefficients(sixPiMuR, rBar, k.sEff);
		const double              a1 = detail::arm(k.radius1, 0), a2 = detail::arm(k.radius2, 0);
		const Vec3                s  = (a1 * k.omega1 + a2 * k.omega2).cross(k.n);
		TangentialViscousResult   r;
		r.ct                 = c.translation;
		r.cr                 = c.coupling;
		r.u                  = k.u;
		r.s                  = s;
		r.resistance         = { r.ct, r.cr, r.ct, r.cr };
		r.force1             = -(r.ct * k.u + r.cr * s);
		r.torque1            = a1 * k.n.cross(r.force1);
		r.torque2            = a2 * k.n.cross(r.force1);
		const double b       = 0.5 * (r.ct + r.cr);
		const Vec3   w       = k.u + (b / r.ct) * s;
		r.dissipationSliding = r.ct * w.squaredNorm();
		r.dissipationRolling = (r.cr - b * b / r.ct) * s.squaredNorm();
		return r;
	}
};

// Default model: F = −C_T (u + s̃), s̃ from the mid-gap arms r_k + S/2, torques (r_k + S/2) n × F.
// Dissipation −P = C_T |u + s̃|² ≥ 0, and a rigidly rotating pair feels no force.
struct SlipTangential {
	static constexpr const char*  name           = "slip";
	static constexpr Capabilities capabilities   { true, true, false, true, true };
	static constexpr auto         energyKeys     = detail::tangentialEnergyKeys;
	static constexpr double       armGapFraction = 0.5; // arms reach the mid-gap point
	double sixPiMuR, rBar;
	SlipTangential(double viscosity, double rBar_) : sixPiMuR(6 * pi * viscosity * rBar_), rBar(rBar_) {}
	static SlipTangential make(const BridgeInputs& b) { return SlipTangential(b.viscosity, b.rBar); }
	// P14 with the mid-gap arms r + S_min/2, largest at S = S_min (physics.md P14a)
	double stepCoefficient(const BridgeInputs& b) const
	{
		return detail::tangentialWeight(b.radius1, b.radius2, 0.5 * b.sMin) * detail::clampPositive(goldmanCoefficients(sixPiMuR, rBar, b.sMin).translation);
	}

	TangentialViscousResult evaluate(const TangentialKinematics& k) const
	{
		const double            half = 0.5 * k.S;
		const double            a1 = detail::arm(k.radius1, half), a2 = detail::arm(k.radius2, half);
		const Vec3              s    = (a1 * k.omega1 + a2 * k.omega2).cross(k.n);
		const Vec3              slip = k.u + s;
		TangentialViscousResult r;
		// C_T of P8 is positive up to S ≈ 6 r̄, far beyond any bridge's rupture distance; the floor
		// only guarantees that the model stays dissipative for any input.
		r.ct                 = detail::clampPositive(goldmanCoefficients(sixPiMuR, rBar, k.sEff).translation);
		r.u                  = k.u;
		r.s                  = s;
		r.resistance         = { r.ct, r.ct, r.ct, r.ct };
		r.force1             = -r.ct * slip;
		r.torque1            = a1 * k.n.cross(r.force1);
		r.torque2            = a2 * k.n.cross(r.force1);
		r.dissipationSliding = r.ct * slip.squaredNorm();
		return r;
	}
};

// Goldman's symmetric resistance form: force −(C_T u + C_R s), torques r_k n × F_s with
// F_s = −(C_R u + C_W s).  −P = C_T|u|² + 2C_R u·s + C_W|s|² ≥ 0 while C_T C_W ≥ C_R², which holds
// for S < 2.42 r̄ (every bridge of up to ~7 % of a particle's volume at any contact angle); beyond
// it C_R is limited to √(C_T C_W) so the model stays dissipative.  Faithful to a sphere near a wall;
// for a free pair the torques do not balance the force couple exactly.
struct GoldmanTangential {
	static constexpr const char*  name           = "goldman";
	static constexpr Capabilities capabilities   { true, true, false, true, true };
	static constexpr auto         energyKeys     = detail::tangentialEnergyKeys;
	static constexpr double       armGapFraction = 0;
	double sixPiMuR, rBar;
	GoldmanTangential(double viscosity, double rBar_) : sixPiMuR(6 * pi * viscosity * rBar_), rBar(rBar_) {}
	static GoldmanTangential make(const BridgeInputs& b) { return GoldmanTangential(b.viscosity, b.rBar); }
	double stepCoefficient(const BridgeInputs& b) const { return 3.5 * detail::clampPositive(goldmanCoefficients(sixPiMuR, rBar, b.sMin).translation); }

	TangentialViscousResult evaluate(const TangentialKinematics& k) const
	{
		GoldmanCoefficients c = goldmanCoefficients(sixPiMuR, rBar, k.sEff);
		c.translation         = detail::clampPositive(c.translation);
		c.rotation            = detail::clampPositive(c.rotation);
		const double limit    = std::sqrt(c.translation * c.rotation);
		c.coupling            = std::clamp(c.coupling, -limit, limit);

		const double            a1 = detail::arm(k.radius1, 0), a2 = detail::arm(k.radius2, 0);
		const Vec3              s  = (a1 * k.omega1 + a2 * k.omega2).cross(k.n);
		TangentialViscousResult r;
		r.ct                 = c.translation;
		r.cr                 = c.coupling;
		r.u                  = k.u;
		r.s                  = s;
		r.resistance         = { c.translation, c.coupling, c.coupling, c.rotation };
		r.force1             = -(c.translation * k.u + c.coupling * s);
		const Vec3 fs        = -(c.coupling * k.u + c.rotation * s);
		r.torque1            = a1 * k.n.cross(fs);
		r.torque2            = a2 * k.n.cross(fs);
		if (c.translation > 0) {
			const Vec3 w         = k.u + (c.coupling / c.translation) * s;
			r.dissipationSliding = c.translation * w.squaredNorm();
			r.dissipationRolling = (c.rotation - c.coupling * c.coupling / c.translation) * s.squaredNorm();
		} else {
			r.dissipationRolling = c.rotation * s.squaredNorm();
		}
		return r;
	}
};

} // namespace viscbridge
