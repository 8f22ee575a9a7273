// One interaction, one time step: Hertz–Mindlin contact plus the effects of the liquid bridge,
// composed at compile time from the models of SubModels.hpp (no branch or call for an effect the
// interaction did not select).
//
// Forces follow physics.md §1: n points from body 1 to body 2 and a force F is the one on body 1
// (body 2 receives −F).  Every velocity-dependent force is evaluated from the velocities the
// integrator stores (v_{n−1/2} for YADE's leapfrog): explicit Euler in velocity (§1).
//
// The kernel works in place on a Record: the interaction's state and outputs listed in PairRecord.hpp
// (ViscBridgePhys has them as attributes, PairRecord as plain members); shearElastic arrives rotated
// into the current contact frame by the caller.
// Outputs of an effect the interaction does not have are never written (they keep their zeros).
#pragma once
#include "viscbridge/core/pair/PairConstants.hpp"
#include "viscbridge/core/pair/PairEnergy.hpp"
#include "viscbridge/core/pair/PairRecord.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <cmath>

namespace viscbridge {

struct BodyKinematics {
	Vec3   pos, vel, angVel;
	double radius; // true radius of a sphere; 0 for a wall, facet or box
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
	// Whether there is liquid for a bridge to form (a pair that takes it from the particles' films
	// asks them, physics.md L0; a fixed-volume pair always has it).
	bool liquid = true;
};

// What the step puts on the two bodies.
struct PairForces {
	Vec3 force1 = Vec3::Zero(), torque1 = Vec3::Zero(), torque2 = Vec3::Zero();
};

// Whether model M books the work of a conservative force (with or without energy tracking).
template <class M> inline constexpr bool booksWork = M::capabilities.enabled && M::capabilities.conservative;

// The models one kernel is compiled for.
template <class N, class T, class D, class C> struct Combo {
	using Normal = N;
	using Tangential = T;
	using Damping = D;
	using Capillary = C;
	static constexpr bool hasBridge = N::capabilities.beyondContact || T::capabilities.beyondContact || C::capabilities.beyondContact;
	// a conservative force's work is booked with or without energy tracking (the guard counts it)
	static constexpr bool booksWorkAlways = booksWork<N> || booksWork<T> || booksWork<D> || booksWork<C>;
};

// The bridge end on a side that is not a sphere: the point of the wall facing the sphere, moved
// towards it by the fraction `armGapFraction` of the gap (mid-gap for `slip`; physics.md P0a).
inline Vec3 wallAnchor(const BodyKinematics& sphere, const Vec3& towardsWall, double S, double armGapFraction)
{
	return sphere.pos + (sphere.radius + (1.0 - armGapFraction) * S) * towardsWall;
}

namespace kernel {

	// Where a bridge forms (physics.md P11): at contact or within formationDistance, never beyond its
	// own rupture distance.
	inline bool formsAt(const PairConstants& k, double S) { return S <= 0 || (S <= k.formationDistance && S <= k.sRup); }

	// Bridge life (P11): forms where formsAt says and there is liquid, ruptures beyond S_rup, then
	// nothing until the next formation.
	template <class R> bool bridgeLives(const PairConstants& k, R& r, double S, bool liquid)
	{
		if (r.bridge) {
			if (S > k.sRup) r.bridge = false;
		} else if (formsAt(k, S) && liquid) {
			r.bridge = true;
		}
		return r.bridge;
	}

	// Hertz–Mindlin contact, step by step as YADE's Law2_ScGeom_MindlinPhys_Mindlin (P2a, P2b).
	template <class D, bool E, class R> void contact(const PairConstants& k, R& r, const PairInput& in, PairForces& f, PairEnergy& e)
	{
		const double delta = -in.S, root = std::sqrt(delta);
		const double Fn    = k.contact.kno * delta * root;
		r.kn               = 1.5 * k.contact.kno * root;
		r.ks               = k.contact.kso * root;
		Vec3       normalForce   = Fn * in.n; // YADE sense (on body 2)
		Vec3&      shearElastic  = r.shearElastic;
		[[maybe_unused]] const double previousShear2 = shearElastic.squaredNorm();
		shearElastic -= r.ks * in.shearIncrement;
		[[maybe_unused]] double cs = 0;
		if constexpr (D::capabilities.enabled) {
			const D&     d             = k.damping.template as<D>();
			const double cn            = 2. * std::sqrt(k.mEff * r.kn) * d.betan;
			cs                         = 2. * std::sqrt(k.mEff * r.ks) * d.betas;
			const Vec3   incidentVn    = in.n.dot(in.contactRelVel) * in.n;
			Vec3         normalViscous = cn * incidentVn;
			const Vec3   normTemp      = normalForce - normalViscous;
			if (normTemp.dot(in.n) < 0.0) { // damping may not make a non-adhesive contact attract
				normalForce   = Vec3::Zero();
				normalViscous = normalViscous + normTemp;
			} else {
				normalForce -= normalViscous;
			}
			if constexpr (E) e[EnergyKey::contactDampDissip] += normalViscous.dot(incidentVn * in.dt);
		}
		Vec3         shearForce;
		const double maxFs = normalForce.norm() * k.contact.tanPhi;
		if (shearElastic.squaredNorm() > maxFs * maxFs) { // Coulomb sliding
			[[maybe_unused]] const Vec3 trial = shearElastic;
			shearElastic *= maxFs / shearElastic.norm();
			shearForce = shearElastic;
			// at an overlap of exactly 0 (spheres placed touching) ks and the sliding limit are 0: the
			// shear force goes to 0 and the shear energy stored until now is what sliding dissipates (E3)
			if constexpr (E) e[EnergyKey::plastDissip] += r.ks > 0 ? ((trial - shearElastic) / r.ks).dot(shearElastic) : r.shearPotential;
			if (!(r.ks > 0)) r.shearPotential = 0;
		} else if constexpr (D::capabilities.enabled) {
			const Vec3 shearViscous = cs * (in.shearIncrement / in.dt);
			shearForce              = shearElastic - shearViscous;
			if constexpr (E) e[EnergyKey::contactDampDissip] += shearViscous.dot(in.shearIncrement);
		} else {
			shearForce = shearElastic;
		}
		if constexpr (E) {
			// Hertz: ∫ kno δ^{3/2} dδ.  Mindlin's stiffness changes with δ, so |Fs|²/(2ks) is not the
			// work stored in shear; the increments (|Fs|² − |Fs_prev|²)/(2ks) at the current ks are,
			// and keep the energy balance closed (Coulomb sliding is counted in dissipFriction; E3).
			if (r.ks > 0) r.shearPotential += 0.5 * (shearElastic.squaredNorm() - previousShear2) / r.ks;
			e[EnergyKey::elastPotential] = 0.4 * k.contact.kno * delta * delta * root + r.shearPotential;
		}
		r.normalContactForce = -normalForce;
		r.shearContactForce  = -shearForce;
		f.force1             = r.normalContactForce + r.shearContactForce;
		f.torque1            = (in.contactPoint - in.b1.pos).cross(f.force1);
		f.torque2            = -(in.contactPoint - in.b2.pos).cross(f.force1);
	}

	// The bridge's ends: the relative velocity V1 − V2 of its ends, their anchors on wall sides.
	struct BridgeEnds {
		bool wall1, wall2;
		Vec3 anchor1, anchor2, vr;
		double vn;
	};
	template <class T> BridgeEnds bridgeEnds(const PairInput& in)
	{
		BridgeEnds b { in.b1.radius <= 0, in.b2.radius <= 0, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 0 };
		Vec3       V1 = in.b1.vel, V2 = in.b2.vel;
		if (b.wall1) {
			b.anchor1 = wallAnchor(in.b2, -in.n, in.S, T::armGapFraction);
			V1 += in.b1.angVel.cross(b.anchor1 - in.b1.pos);
		}
		if (b.wall2) {
			b.anchor2 = wallAnchor(in.b1, in.n, in.S, T::armGapFraction);
			V2 += in.b2.angVel.cross(b.anchor2 - in.b2.pos);
		}
		b.vr = V1 - V2;
		b.vn = b.vr.dot(in.n);
		return b;
	}

	// The previous step's forces did their work while the velocities went from the recorded ones to
	// the current ones (E1): booked now, then this step's are recorded.  capillaryForce is the
	// magnitude of this step's pull.
	template <class N, class T, class C, bool E, bool Imp, class R>
	void bookWork(R& r, const BridgeEnds& b, const TangentialViscousResult& t, double capillaryForce, double dt, PairEnergy& e)
	{
		if (r.workPending) {
			const double meanVn = 0.5 * (r.workVn + b.vn);
			if constexpr (E && !Imp && N::capabilities.enabled) e[EnergyKey::viscDissipNormal] = r.workCn * r.workVn * meanVn * dt;
			if constexpr (E && !Imp && T::capabilities.enabled) {
				const TangentialResistance m { r.workM1[0], r.workM1[1], r.workM2[0], r.workM2[1] };
				const TangentialWork       w = tangentialWork(m, r.workU, r.workS, t.u, t.s);
				e[EnergyKey::viscDissipTangential]         = w.sliding * dt;
				e[EnergyKey::viscDissipRotational]         = w.rolling * dt;
			}
			// the pull +F n on body 1 has the power F·(V1 − V2)·n on the pair (P21)
			if constexpr (C::capabilities.enabled) e[EnergyKey::capillaryWork] = -r.workCapillary * meanVn * dt;
		}
		// recorded whenever this runs, so that a record is never older than the step before
		r.workVn = b.vn;
		if constexpr (!Imp && N::capabilities.enabled) r.workCn = r.cn;
		if constexpr (!Imp && T::capabilities.enabled) {
			r.workU  = t.u;
			r.workS  = t.s;
			r.workM1 = Vec2(t.resistance.m11, t.resistance.m12);
			r.workM2 = Vec2(t.resistance.m21, t.resistance.m22);
		}
		if constexpr (C::capabilities.enabled) r.workCapillary = capillaryForce;
		r.workPending = true;
	}

	// The implicit solver's description of the bridge's damping (P15), instead of its forces.
	template <class T, class R> void describeDamping(R& r, const PairInput& in, const BridgeEnds& b, const TangentialViscousResult& t)
	{
		ViscousBlock& block = r.implicitBlock;
		block.valid         = true;
		block.n             = in.n;
		block.cn            = r.cn;
		block.resistance    = t.resistance;
		block.a1            = b.wall1 ? 0.0 : in.b1.radius + T::armGapFraction * in.S;
		block.a2            = b.wall2 ? 0.0 : in.b2.radius + T::armGapFraction * in.S;
		block.r1            = b.wall1 ? Vec3(b.anchor1 - in.b1.pos) : Vec3::Zero();
		block.r2            = b.wall2 ? Vec3(b.anchor2 - in.b2.pos) : Vec3::Zero();
		r.normalViscousForce = r.shearViscousForce = Vec3::Zero(); // set by the solver from the implicit velocities
	}

	// The bridge's forces (P3–P9, P19–P20) on top of the contact's.
	template <class Cm, bool E, bool Imp, class R> void bridge(const PairConstants& k, R& r, const PairInput& in, PairForces& f, PairEnergy& e)
	{
		using N = typename Cm::Normal;
		using T = typename Cm::Tangential;
		using C = typename Cm::Capillary;
		const double     sEff = clampedGap(in.S, k.sMin);
		const BridgeEnds b    = bridgeEnds<T>(in);
		Vec3             onWall1 = Vec3::Zero(); // what acts on body 1 through the bridge's wall anchors
		TangentialViscousResult t;
		if constexpr (N::capabilities.enabled) {
			r.cn                 = k.normal.template as<N>().coefficient(sEff);
			r.normalViscousForce = -r.cn * b.vn * in.n; // P3: −C^n v_r^n
		}
		if constexpr (T::capabilities.enabled) {
			t                   = k.tangential.template as<T>().evaluate({ in.n, b.vr - b.vn * in.n, in.b1.angVel, in.b2.angVel, in.b1.radius, in.b2.radius, in.S, sEff });
			r.shearViscousForce = t.force1;
			r.ct                = t.ct;
			r.cr                = t.cr;
		}
		double pull = 0;
		if constexpr (C::capabilities.enabled) {
			pull             = k.capillary.template as<C>().force(in.S);
			r.capillaryForce = pull * in.n; // attraction: towards body 2
			f.force1 += r.capillaryForce;
			onWall1 += r.capillaryForce;
		}
		if constexpr (E || C::capabilities.enabled) bookWork<N, T, C, E, Imp>(r, b, t, pull, in.dt, e);
		else r.workPending = false; // work is booked between two steps that both record it
		if constexpr (Imp) {
			describeDamping<T>(r, in, b, t);
		} else {
			const Vec3 viscous1 = r.normalViscousForce + r.shearViscousForce;
			f.force1 += viscous1;
			f.torque1 += t.torque1;
			f.torque2 += t.torque2;
			onWall1 += viscous1;
		}
		if (b.wall1) f.torque1 += (b.anchor1 - in.b1.pos).cross(onWall1);
		if (b.wall2) f.torque2 += (b.anchor2 - in.b2.pos).cross(-onWall1);
	}

	// After rupture: nothing of the bridge is left.
	template <class R> void forgetBridge(R& r)
	{
		r.workPending = false;
		r.cn = r.ct = r.cr = 0;
		r.normalViscousForce = r.shearViscousForce = r.capillaryForce = Vec3::Zero();
	}

} // namespace kernel

// Evaluates one step of interaction r with the models of Cm (E: track energy; Imp: leave the
// viscous forces to the implicit solver, describing them in r.implicitBlock).  Returns false when
// the interaction should be erased (no contact, no bridge); f receives the forces to apply.
template <class Cm, bool E, bool Imp, class R> bool evaluatePair(const PairConstants& k, R& r, const PairInput& in, PairForces& f, PairEnergy& e)
{
	const bool contact = in.S <= 0;
	r.separation       = in.S;
	if constexpr (Cm::hasBridge) {
		if (!kernel::bridgeLives(k, r, in.S, in.liquid)) {
			kernel::forgetBridge(r);
			if (!contact) return false;
		}
	} else if (!contact) {
		return false;
	}
	f = PairForces();
	if (contact) {
		kernel::contact<typename Cm::Damping, E>(k, r, in, f, e);
	} else if (r.kn != 0) { // the contact just ended: a new one starts without tangential history
		r.kn = r.ks        = 0;
		r.shearElastic     = r.normalContactForce = r.shearContactForce = Vec3::Zero();
		r.shearPotential   = 0;
	}
	if constexpr (Cm::hasBridge)
		if (r.bridge) kernel::bridge<Cm, E, Imp>(k, r, in, f, e);
	// YADE's sense, so that its stress and force utilities see every force: sustained by body 2
	Vec3 normal = r.normalContactForce, shear = r.shearContactForce;
	if constexpr (Cm::Normal::capabilities.enabled) normal += r.normalViscousForce;
	if constexpr (Cm::Capillary::capabilities.enabled) normal += r.capillaryForce;
	if constexpr (Cm::Tangential::capabilities.enabled) shear += r.shearViscousForce;
	r.normalForce = -normal;
	r.shearForce  = -shear;
	return true;
}

} // namespace viscbridge
