// Building PairInput/PairParams for evaluatePair the way YADE's ScGeom would fill them, and the
// kernel called with the models as values and the state and the outputs apart (the form these tests
// are written in), on top of the product's evaluatePair.
#pragma once
#include "test_support.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/pair/PairKernel.hpp"

namespace vbtest {

using namespace viscbridge;

// Reference particles of physics.md §3/§5: r = 0.5 mm, ρ = 2500 kg/m³.
inline constexpr double kRadius = 5e-4, kDensity = 2500;
inline double sphereMass(double r) { return kDensity * 4.0 / 3.0 * kPi * r * r * r; }

// A sphere (radius r > 0) or a wall (radius 0) with its motion.
inline BodyKinematics body(const Vec3& pos, double radius, const Vec3& vel = Vec3::Zero(), const Vec3& angVel = Vec3::Zero())
{
	return { pos, vel, angVel, radius };
}

// Rigid-body velocity of body b at point x.
inline Vec3 pointVelocity(const BodyKinematics& b, const Vec3& x) { return b.vel + b.angVel.cross(x - b.pos); }

// PairInput for gap S along n (body 1 → body 2).  The contact point is ScGeom's, pos1 + (r1 + S/2) n
// for a sphere on side 1 (on a wall side 1 it is measured from the sphere on side 2); contactRelVel
// is ScGeom::getIncidentVel, the velocity of side 2 minus side 1 at the contact point.
inline PairInput pairInput(const Vec3& n, double S, const BodyKinematics& b1, const BodyKinematics& b2, double dt,
                           const Vec3& shearIncrement = Vec3::Zero())
{
	PairInput in;
	in.n            = n;
	in.S            = S;
	in.contactPoint = b1.radius > 0 ? Vec3(b1.pos + (b1.radius + S / 2) * n) : Vec3(b2.pos - (b2.radius + S / 2) * n);
	in.b1           = b1;
	in.b2           = b2;
	in.contactRelVel  = pointVelocity(b2, in.contactPoint) - pointVelocity(b1, in.contactPoint);
	in.shearIncrement = shearIncrement;
	in.dt             = dt;
	return in;
}

// Two spheres of radii r1, r2 at gap S along n; sphere 1 at x1.
inline PairInput spherePair(const Vec3& x1, const Vec3& n, double r1, double r2, double S, const Vec3& v1, const Vec3& v2,
                            const Vec3& w1, const Vec3& w2, double dt, const Vec3& shearIncrement = Vec3::Zero())
{
	return pairInput(n, S, body(x1, r1, v1, w1), body(x1 + (r1 + r2 + S) * n, r2, v2, w2), dt, shearIncrement);
}

// Hertz–Mindlin constants of two equal 0.5 mm spheres, E = 1e7 Pa, ν = 0.3, φ = 0.5 rad.
inline HertzMindlinConstants referenceContact(double r1 = kRadius, double r2 = kRadius)
{
	const ElasticProperties m{ 1e7, 0.3, 0.5 };
	return hertzMindlinConstants(m, m, r1, r2);
}

// The numbers of a pair that do not belong to a model.
struct PairParams {
	HertzMindlinConstants contact;
	double                mEff, sMin, sRup, formationDistance;
};

template <class N, class T, class D, class C = NoCapillary> struct PairModels {
	N                     normal;
	T                     tangential;
	D                     damping;
	C                     capillary {};
	static constexpr bool hasBridge = Combo<N, T, D, C>::hasBridge;
};

using PairState = PairRecord;

// What one step gave: forces, the record's outputs, the energy.
struct PairOutput {
	Vec3   force1 = Vec3::Zero(), torque1 = Vec3::Zero(), torque2 = Vec3::Zero();
	Vec3   normalContact = Vec3::Zero(), shearContact = Vec3::Zero(), normalViscous = Vec3::Zero(), shearViscous = Vec3::Zero();
	Vec3   capillary = Vec3::Zero();
	double kn = 0, ks = 0, cn = 0, ct = 0, cr = 0;
	double dissipNormal = 0, dissipTangential = 0, dissipRotational = 0, dissipContactDamping = 0, dissipFriction = 0;
	double elasticPotential = 0, capillaryWork = 0;
	ViscousBlock block;
};

template <class N, class T, class D, class C> PairConstants constantsOf(const PairModels<N, T, D, C>& m, const PairParams& p)
{
	PairConstants k;
	k.contact           = p.contact;
	k.mEff              = p.mEff;
	k.sMin              = p.sMin;
	k.sRup              = p.sRup;
	k.formationDistance = p.formationDistance;
	k.normal.store(m.normal);
	k.tangential.store(m.tangential);
	k.damping.store(m.damping);
	k.capillary.store(m.capillary);
	return k;
}

template <bool E, bool Imp = false, class N, class T, class D, class C>
bool evaluatePair(const PairModels<N, T, D, C>& m, const PairParams& p, PairState& st, const PairInput& in, PairOutput& out)
{
	PairForces f;
	PairEnergy e;
	const bool keep = viscbridge::evaluatePair<Combo<N, T, D, C>, E, Imp>(constantsOf(m, p), st, in, f, e);
	out             = PairOutput();
	if (!keep) return false;
	out.force1        = f.force1;
	out.torque1       = f.torque1;
	out.torque2       = f.torque2;
	out.normalContact = st.normalContactForce;
	out.shearContact  = st.shearContactForce;
	out.normalViscous = st.normalViscousForce;
	out.shearViscous  = st.shearViscousForce;
	out.capillary     = st.capillaryForce;
	out.kn = st.kn, out.ks = st.ks, out.cn = st.cn, out.ct = st.ct, out.cr = st.cr;
	using K = EnergyKey;
	out.dissipNormal = e[K::viscDissipNormal], out.dissipTangential = e[K::viscDissipTangential], out.dissipRotational = e[K::viscDissipRotational];
	out.dissipContactDamping = e[K::contactDampDissip], out.dissipFriction = e[K::plastDissip];
	out.elasticPotential = e[K::elastPotential], out.capillaryWork = e[K::capillaryWork];
	out.block = st.implicitBlock;
	return true;
}

// Bridge of 1 % of a particle's volume, θ = 0 (physics.md R2/R3), S_min = 1e-4 r.
inline PairParams referenceParams(double mEff, double formationDistance = 0)
{
	const double V = 0.01 * 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;
	return { referenceContact(), mEff, 1e-4 * kRadius, ruptureDistance(V, 0.0), formationDistance };
}

} // namespace vbtest
