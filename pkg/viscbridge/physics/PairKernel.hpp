// One interaction, one time step: Hertz–Mindlin contact plus the selected viscous-bridge terms,
// composed at compile time from the sub-models (no branch or call for an unselected effect).
//
// Forces follow physics.md §1: n points from body 1 to body 2 and the force F is the one on body 1
// (body 2 receives −F).  Every velocity-dependent force is evaluated from the velocities the
// integrator stores (v_{n−1/2} for YADE's leapfrog): explicit Euler in velocity (§1).
#pragma once
#include "ContactDamping.hpp"
#include "HertzMindlin.hpp"
#include "NormalViscous.hpp"
#include "PairGeometry.hpp"
#include "TangentialViscous.hpp"
#include "Vector.hpp"

namespace viscbridge {

struct BodyKinematics {
	Vec3   pos, vel, angVel;
	double radius; // true radius of a sphere; 0 for a wall, facet or box
};

// Fixed per interaction (set when its physics is created).
struct PairParams {
	HertzMindlinConstants contact;
	double                mEff;              // m* (§1)
	double                sMin;              // S_min of P6 [m]
	double                sRup;              // rupture distance, P11 [m]
	double                formationDistance; // a bridge forms at S ≤ this (0: at contact) [m]
};

// Per step.  contactRelVel and shearIncrement are YADE's ScGeom incident velocity (side 2 minus
// side 1, at the contact point) and shear increment: the contact law uses them as YADE's does.
struct PairInput {
	Vec3           n;
	double         S; // gap, negative in overlap
	Vec3           contactPoint;
	BodyKinematics b1, b2; // body 2 already shifted into body 1's periodic image
	Vec3           contactRelVel;
	Vec3           shearIncrement;
	double         dt;
};

// The viscous forces of the last step, kept (with energy tracking) until the next step shows the
// velocities they produced: their work is then W = F·(v_before + v_after)/2·Δt, consistent with
// the kinetic energy YADE's leapfrog reports (physics.md §6).
struct ViscousWorkRecord {
	bool                 pending = false;
	double               cn = 0, vn = 0;                    // normal: C^n and v_r·n
	Vec3                 u = Vec3::Zero(), s = Vec3::Zero(); // tangential kinematics
	TangentialResistance resistance;
};

// Carried from step to step.  The caller rotates shearElastic into the current contact frame
// (YADE's ScGeom::rotate) before each call.
struct PairState {
	Vec3              shearElastic   = Vec3::Zero(); // elastic tangential force, YADE sense (on body 2)
	double            shearPotential = 0;            // elastic energy stored in shear (tracked with energy only)
	bool              bridge         = false;
	ViscousWorkRecord lastViscous;
};

// A bridge's damping as a linear map, for the implicit solver (P15): with dv = V1 − V2 (a wall side's
// V at its anchor, r_k from its centre), u = (I − nnᵀ)dv and s = (a1 ω1 + a2 ω2) × n, the force on
// body 1 is −(cn (n·dv) n + m11 u + m12 s), the torque on sphere side k is a_k n × (−(m21 u + m22 s)).
struct ViscousBlock {
	bool                 valid = false;
	Vec3                 n     = Vec3::Zero();
	double               cn    = 0;
	TangentialResistance resistance;
	double               a1 = 0, a2 = 0;              // arms of the sphere sides (0 for a wall side)
	Vec3                 r1 = Vec3::Zero(), r2 = Vec3::Zero(); // wall anchor − wall centre (0 for a sphere side)
};

struct PairOutput {
	Vec3   force1 = Vec3::Zero(), torque1 = Vec3::Zero(), torque2 = Vec3::Zero();
	Vec3   normalContact = Vec3::Zero(), shearContact = Vec3::Zero(); // on body 1
	Vec3   normalViscous = Vec3::Zero(), shearViscous = Vec3::Zero(); // on body 1
	double kn = 0, ks = 0, cn = 0, ct = 0, cr = 0;
	// Energy (filled only when tracking): dissipated during this step [J] and stored [J].
	double dissipNormal = 0, dissipTangential = 0, dissipRotational = 0, dissipContactDamping = 0, dissipFriction = 0;
	double elasticPotential = 0;
	ViscousBlock block; // filled instead of applying the viscous forces when they are implicit
};

template <class Normal, class Tangential, class Damping> struct PairModels {
	Normal     normal;
	Tangential tangential;
	Damping    damping;
	static constexpr bool hasBridge = Normal::enabled || Tangential::enabled;
};

// The bridge end on a side that is not a sphere: the point of the wall facing the sphere, moved
// towards it by the fraction `armGapFraction` of the gap (mid-gap for `slip`).
inline Vec3 wallAnchor(const BodyKinematics& sphere, const Vec3& towardsWall, double S, double armGapFraction)
{
	return sphere.pos + (sphere.radius + (1.0 - armGapFraction) * S) * towardsWall;
}

// Evaluates one step; returns false when the interaction should be erased (no contact, no bridge).
// ImplicitViscous: the viscous forces are left to the implicit solver (P15); the kernel describes
// them in out.block instead of applying them, and their work is accounted by the solver.
template <bool TrackEnergy, bool ImplicitViscous = false, class Normal, class Tangential, class Damping>
bool evaluatePair(const PairModels<Normal, Tangential, Damping>& m, const PairParams& p, PairState& st, const PairInput& in, PairOutput& out)
{
	constexpr bool hasBridge = PairModels<Normal, Tangential, Damping>::hasBridge;
	const double   S         = in.S;
	const bool     contact   = S <= 0;
	// Bridge life (physics.md §2): forms at contact or within formationDistance (never beyond its
	// own rupture distance), ruptures beyond S_rup (P11), then nothing until the next formation.
	if constexpr (hasBridge) {
		if (st.bridge) {
			if (S > p.sRup) st.bridge = false;
		} else if (contact || (S <= p.formationDistance && S <= p.sRup)) {
			st.bridge = true;
		}
		if (!contact && !st.bridge) return false;
	} else {
		if (!contact) return false;
	}
	out = PairOutput();

	// ---- Hertz–Mindlin contact, step by step as Law2_ScGeom_MindlinPhys_Mindlin ----------------
	Vec3 contactForce1 = Vec3::Zero();
	if (contact) {
		const double delta       = -S;
		const double Fn          = p.contact.kno * std::pow(delta, 1.5);
		out.kn                   = 3. / 2. * p.contact.kno * std::pow(delta, 0.5);
		out.ks                   = p.contact.kso * std::pow(delta, 0.5);
		Vec3       normalForce   = Fn * in.n; // YADE sense (on body 2)
		Vec3&      shearElastic  = st.shearElastic;
		[[maybe_unused]] const double previousShear2 = shearElastic.squaredNorm();
		const Vec3 incidentVs    = in.shearIncrement / in.dt;
		shearElastic             = shearElastic - out.ks * (incidentVs * in.dt);
		[[maybe_unused]] double cs = 0;
		if constexpr (Damping::enabled) {
			const double cn           = 2. * std::sqrt(p.mEff * out.kn) * m.damping.betan;
			cs                        = 2. * std::sqrt(p.mEff * out.ks) * m.damping.betas;
			const Vec3 incidentVn     = in.n.dot(in.contactRelVel) * in.n;
			Vec3       normalViscous  = cn * incidentVn;
			const Vec3 normTemp       = normalForce - normalViscous;
			if (normTemp.dot(in.n) < 0.0) { // damping may not make a non-adhesive contact attract
				normalForce   = Vec3::Zero();
				normalViscous = normalViscous + normTemp;
			} else {
				normalForce -= normalViscous;
			}
			if constexpr (TrackEnergy) out.dissipContactDamping += normalViscous.dot(incidentVn * in.dt);
		}
		Vec3         shearForce;
		const double maxFs = normalForce.norm() * p.contact.tanPhi;
		if (shearElastic.squaredNorm() > maxFs * maxFs) { // Coulomb sliding
			const Vec3 trial = shearElastic;
			shearElastic *= maxFs / shearElastic.norm();
			shearForce = shearElastic;
			if constexpr (TrackEnergy) out.dissipFriction += ((trial - shearElastic) / out.ks).dot(shearElastic);
		} else if constexpr (Damping::enabled) {
			const Vec3 shearViscous = cs * incidentVs;
			shearForce              = shearElastic - shearViscous;
			if constexpr (TrackEnergy) out.dissipContactDamping += shearViscous.dot(incidentVs * in.dt);
		} else {
			shearForce = shearElastic;
		}
		if constexpr (TrackEnergy) {
			// Hertz: ∫ kno δ^{3/2} dδ.  Mindlin's stiffness changes with δ, so |Fs|²/(2ks) is not
			// the work stored in shear; the increments (|Fs|² − |Fs_prev|²)/(2ks) at the current ks
			// are, and keep the energy balance closed (Coulomb sliding is counted in dissipFriction).
			if (out.ks > 0) st.shearPotential += 0.5 * (shearElastic.squaredNorm() - previousShear2) / out.ks;
			out.elasticPotential = 0.4 * p.contact.kno * std::pow(delta, 2.5) + st.shearPotential;
		}
		out.normalContact = -normalForce;
		out.shearContact  = -shearForce;
		contactForce1     = out.normalContact + out.shearContact;
		out.force1        = contactForce1;
		out.torque1       = (in.contactPoint - in.b1.pos).cross(contactForce1);
		out.torque2       = -(in.contactPoint - in.b2.pos).cross(contactForce1);
	} else {
		st.shearElastic   = Vec3::Zero(); // a new contact starts without tangential history
		st.shearPotential = 0;
	}

	// ---- viscous bridge (P3–P9) ------------------------------------------------------------------
	if constexpr (hasBridge) {
		if (!st.bridge) {
			st.lastViscous.pending = false;
			return true;
		}
		const double sEff   = clampedGap(S, p.sMin);
		const double lambda = Tangential::armGapFraction;
		const bool   wall1 = in.b1.radius <= 0, wall2 = in.b2.radius <= 0;
		Vec3         V1 = in.b1.vel, V2 = in.b2.vel, anchor1, anchor2;
		if (wall1) {
			anchor1 = wallAnchor(in.b2, -in.n, S, lambda);
			V1 += in.b1.angVel.cross(anchor1 - in.b1.pos);
		}
		if (wall2) {
			anchor2 = wallAnchor(in.b1, in.n, S, lambda);
			V2 += in.b2.angVel.cross(anchor2 - in.b2.pos);
		}
		const Vec3   vr = V1 - V2;
		const double vn = vr.dot(in.n);
		Vec3         viscous1 = Vec3::Zero(), viscousTorque1 = Vec3::Zero(), viscousTorque2 = Vec3::Zero();
		[[maybe_unused]] TangentialResistance resistance;
		// The previous step's viscous forces did their work while the velocities went from the
		// recorded ones to the current ones (in.dt is the step the integrator just made).
		[[maybe_unused]] ViscousWorkRecord& last = st.lastViscous;
		if constexpr (Normal::enabled) {
			out.cn            = m.normal.coefficient(sEff);
			out.normalViscous = -out.cn * vn * in.n; // P3: −C^n v_r^n
			viscous1 += out.normalViscous;
			if constexpr (TrackEnergy && !ImplicitViscous) {
				if (last.pending) out.dissipNormal = last.cn * last.vn * 0.5 * (last.vn + vn) * in.dt;
				last.cn = out.cn;
				last.vn = vn;
			}
		}
		if constexpr (Tangential::enabled) {
			const TangentialKinematics    k { in.n, vr - vn * in.n, in.b1.angVel, in.b2.angVel, in.b1.radius, in.b2.radius, S, sEff };
			const TangentialViscousResult t = m.tangential.evaluate(k);
			out.shearViscous                = t.force1;
			out.ct                          = t.ct;
			out.cr                          = t.cr;
			resistance                      = t.resistance;
			viscous1 += t.force1;
			viscousTorque1 = t.torque1;
			viscousTorque2 = t.torque2;
			if constexpr (TrackEnergy && !ImplicitViscous) {
				if (last.pending) {
					const TangentialWork w = tangentialWork(last.resistance, last.u, last.s, t.u, t.s);
					out.dissipTangential   = w.sliding * in.dt;
					out.dissipRotational   = w.rolling * in.dt;
				}
				last.u          = t.u;
				last.s          = t.s;
				last.resistance = t.resistance;
			}
		}
		if constexpr (ImplicitViscous) {
			// the forces above used the old velocities; the solver recomputes them from the new ones
			ViscousBlock& b = out.block;
			b.valid         = true;
			b.n             = in.n;
			b.cn            = out.cn;
			b.resistance    = resistance;
			b.a1            = wall1 ? 0.0 : in.b1.radius + lambda * S;
			b.a2            = wall2 ? 0.0 : in.b2.radius + lambda * S;
			if (wall1) b.r1 = anchor1 - in.b1.pos;
			if (wall2) b.r2 = anchor2 - in.b2.pos;
		} else {
			if constexpr (TrackEnergy) last.pending = true;
			out.force1 += viscous1;
			out.torque1 += viscousTorque1;
			out.torque2 += viscousTorque2;
			if (wall1) out.torque1 += (anchor1 - in.b1.pos).cross(viscous1);
			if (wall2) out.torque2 += (anchor2 - in.b2.pos).cross(-viscous1);
		}
	}
	return true;
}

} // namespace viscbridge
