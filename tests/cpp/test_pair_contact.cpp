// The Hertz–Mindlin contact inside the pair kernel, step by step as YADE's
// Law2_ScGeom_MindlinPhys_Mindlin: Hertz force and tangent stiffnesses, Coulomb limit with its
// friction dissipation, and the restitution contact damping.
#include "pair_test_support.hpp"
#include <cmath>
#include <gtest/gtest.h>

using namespace viscbridge;
using namespace vbtest;

namespace {
using Dry    = PairModels<NoNormalViscous, NoTangentialViscous, NoContactDamping>;
using Damped = PairModels<NoNormalViscous, NoTangentialViscous, RestitutionContactDamping>;
const double kMEff = sphereMass(kRadius) / 2;
const Vec3   kN    = Vec3(1, 2, 2) / 3; // a generic unit normal
const Vec3   kT    = Vec3(2, 1, -2) / 3; // unit, ⟂ kN

PairInput restingOverlap(double delta, const Vec3& shearIncrement = Vec3::Zero(), const Vec3& v1 = Vec3::Zero())
{
	return spherePair(Vec3(1e-3, 0, 0), kN, kRadius, kRadius, -delta, v1, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 1e-7, shearIncrement);
}
} // namespace

// Hertz: F_n = kno δ^{3/2} repulsive (on body 1 along −n), kn = 3/2 kno δ^{1/2} = dF_n/dδ,
// ks = kso δ^{1/2}, stored energy (2/5) kno δ^{5/2}; a central force exerts no torque.
TEST(PairContact, HertzForceAndStiffness)
{
	const PairParams p = referenceParams(kMEff);
	ASSERT_NEAR(std::abs(kT.dot(kN)), 0.0, 1e-15);
	for (double delta : { 1e-9, 1e-7, 2e-6 }) {
		PairState  st;
		PairOutput out;
		ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(delta), out));
		const double Fn = p.contact.kno * std::pow(delta, 1.5);
		EXPECT_NEAR(out.force1.dot(kN), -Fn, 1e-13 * Fn) << "δ=" << delta;
		EXPECT_NEAR((out.force1 - out.force1.dot(kN) * kN).norm(), 0.0, 1e-13 * Fn);
		EXPECT_NEAR((out.normalContact + Fn * kN).norm(), 0.0, 1e-13 * Fn);
		EXPECT_NEAR(out.kn, 1.5 * p.contact.kno * std::sqrt(delta), 1e-13 * out.kn);
		EXPECT_NEAR(out.ks, p.contact.kso * std::sqrt(delta), 1e-13 * out.ks);
		EXPECT_NEAR(out.elasticPotential, 0.4 * p.contact.kno * std::pow(delta, 2.5), 1e-13 * out.elasticPotential);
		EXPECT_NEAR(out.torque1.norm() + out.torque2.norm(), 0.0, 1e-13 * Fn * kRadius);
		// kn is the tangent stiffness: central difference of F_n(δ), truncation O(h²) ~ 1e-8 relative.
		const double h = 1e-4 * delta;
		PairOutput   plus, minus;
		PairState    s1, s2;
		evaluatePair<false>(Dry{}, p, s1, restingOverlap(delta + h), plus);
		evaluatePair<false>(Dry{}, p, s2, restingOverlap(delta - h), minus);
		EXPECT_NEAR((minus.force1 - plus.force1).dot(kN) / (2 * h), out.kn, 1e-6 * out.kn) << "δ=" << delta;
	}
}

// Below the Coulomb limit the shear force is elastic: shearElastic −= ks Δ, so body 1 is pulled along
// the displacement Δ of side 2 relative to side 1 with ks Δ; no friction dissipation.
TEST(PairContact, ElasticShearBelowCoulombLimit)
{
	const PairParams p     = referenceParams(kMEff);
	const double     delta = 1e-6, ks = p.contact.kso * std::sqrt(delta);
	const Vec3       D     = 1e-10 * kT;
	PairState        st;
	PairOutput       out;
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(delta, D), out));
	ASSERT_LT(ks * D.norm(), p.contact.tanPhi * p.contact.kno * std::pow(delta, 1.5));
	EXPECT_NEAR((out.shearContact - ks * D).norm(), 0.0, 1e-13 * ks * D.norm());
	EXPECT_NEAR((st.shearElastic + ks * D).norm(), 0.0, 1e-13 * ks * D.norm()); // YADE sense (on body 2)
	EXPECT_EQ(out.dissipFriction, 0.0);
	// Torques of the contact force applied at the contact point (YADE's applyForceAtContactPoint).
	const PairInput in = restingOverlap(delta, D);
	EXPECT_NEAR((out.torque1 - (in.contactPoint - in.b1.pos).cross(out.force1)).norm(), 0.0, 1e-13 * out.force1.norm() * kRadius);
	EXPECT_NEAR((out.torque2 + (in.contactPoint - in.b2.pos).cross(out.force1)).norm(), 0.0, 1e-13 * out.force1.norm() * kRadius);
	EXPECT_GT(out.torque1.norm(), 0.0);
	// A second step accumulates the history: 2 ks Δ.
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(delta, D), out));
	EXPECT_NEAR((out.shearContact - 2 * ks * D).norm(), 0.0, 1e-13 * ks * D.norm());
}

// Coulomb: after a large shear increment |F_s| = tanφ F_n exactly, along Δ, and the energy dissipated
// by sliding is the plastic slip times the force: (ks|Δ| − F_max) F_max / ks > 0.
TEST(PairContact, CoulombLimitAndFrictionDissipation)
{
	const PairParams p     = referenceParams(kMEff);
	const double     delta = 1e-6, ks = p.contact.kso * std::sqrt(delta);
	const double     Fn    = p.contact.kno * std::pow(delta, 1.5), maxFs = p.contact.tanPhi * Fn;
	const Vec3       D     = 1e-4 * kT; // ks|Δ| ≫ F_max
	PairState        st;
	PairOutput       out;
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(delta, D), out));
	ASSERT_GT(ks * D.norm(), 10 * maxFs);
	EXPECT_LE(out.shearContact.norm(), p.contact.tanPhi * out.normalContact.norm() * (1 + 1e-14));
	EXPECT_NEAR(out.shearContact.norm(), maxFs, 1e-13 * maxFs);
	EXPECT_NEAR(out.shearContact.normalized().dot(kT), 1.0, 1e-14);
	EXPECT_GT(out.dissipFriction, 0.0);
	EXPECT_NEAR(out.dissipFriction, (ks * D.norm() - maxFs) * maxFs / ks, 1e-12 * maxFs * D.norm());
	// The stored shear energy is that of the limited spring.
	EXPECT_NEAR(out.elasticPotential, 0.4 * p.contact.kno * std::pow(delta, 2.5) + 0.5 * maxFs * maxFs / ks, 1e-12 * out.elasticPotential);
}

// Restitution damping (YADE's en): c_n = 2β√(m* kn), c_s = 2β√(m* ks), dissipation c v² Δt.
TEST(PairContact, RestitutionDampingForceAndDissipation)
{
	const PairParams p     = referenceParams(kMEff);
	const double     beta  = dampingRatioFromRestitution(0.5);
	const Damped     m{ {}, {}, RestitutionContactDamping{ beta, beta } };
	const double     delta = 1e-6, w = 0.01, dt = 1e-7;
	const double     Fn = p.contact.kno * std::pow(delta, 1.5), kn = 1.5 * p.contact.kno * std::sqrt(delta);
	const double     cn = 2 * beta * std::sqrt(kMEff * kn);
	{ // approaching at w: the damping adds to the repulsion
		PairState  st;
		PairOutput out;
		ASSERT_TRUE(evaluatePair<true>(m, p, st, restingOverlap(delta, Vec3::Zero(), w * kN), out));
		EXPECT_NEAR(out.force1.dot(kN), -(Fn + cn * w), 1e-12 * (Fn + cn * w));
		EXPECT_NEAR(out.dissipContactDamping, cn * w * w * dt, 1e-12 * cn * w * w * dt);
	}
	{ // separating so fast that the damping would pull: the normal force is cut at zero (no attraction)
		const double wSep = 10 * Fn / cn;
		PairState    st;
		PairOutput   out;
		ASSERT_TRUE(evaluatePair<true>(m, p, st, restingOverlap(delta, Vec3::Zero(), -wSep * kN), out));
		EXPECT_EQ(out.normalContact.norm(), 0.0);
		// The damping then dissipates only what the Hertz force stored: F_n w Δt.
		EXPECT_NEAR(out.dissipContactDamping, Fn * wSep * dt, 1e-12 * Fn * wSep * dt);
	}
	{ // shear damping below the Coulomb limit: F_s = ks Δ + c_s Δ/Δt on body 1
		const double ks = p.contact.kso * std::sqrt(delta), cs = 2 * beta * std::sqrt(kMEff * ks);
		const Vec3   D  = 1e-11 * kT;
		PairState    st;
		PairOutput   out;
		ASSERT_TRUE(evaluatePair<true>(m, p, st, restingOverlap(delta, D), out));
		const Vec3 expected = ks * D + cs * D / dt;
		ASSERT_LT(expected.norm(), p.contact.tanPhi * Fn);
		EXPECT_NEAR((out.shearContact - expected).norm(), 0.0, 1e-12 * expected.norm());
		EXPECT_NEAR(out.dissipContactDamping, cs * D.squaredNorm() / dt, 1e-12 * cs * D.squaredNorm() / dt);
	}
}

// Stored shear energy: Mindlin's ks changes with δ, so the kernel accumulates the increments
// (|Fs|² − |Fs_prev|²)/(2 ks) at the current ks (PairKernel.hpp).  At constant δ they telescope to
// |Fs|²/(2ks); after separation the history and its energy are gone.  The shear increment is sized
// to end at 80 % of the Coulomb limit; the shear energy (a few % of the Hertz energy) is compared
// after subtracting the Hertz part, far above the rounding of that subtraction (1e-16 of Hertz).
TEST(PairContact, ShearPotentialAccumulatesIncrements)
{
	const PairParams p  = referenceParams(kMEff);
	const double     d1 = 1e-6, d2 = 2e-6;
	const double     ks1 = p.contact.kso * std::sqrt(d1), ks2 = p.contact.kso * std::sqrt(d2);
	const double     limit1 = p.contact.tanPhi * p.contact.kno * std::pow(d1, 1.5);
	const Vec3       D      = 0.8 * limit1 / (3 * ks1 + ks2) * kT;
	const auto       hertz  = [&](double d) { return 0.4 * p.contact.kno * std::pow(d, 2.5); };
	PairState        st;
	PairOutput       out;
	for (int i = 1; i <= 3; ++i) { // constant δ: ½ |i ks Δ|²/ks
		ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(d1, D), out));
		const double shear = 0.5 * ks1 * (i * D).squaredNorm();
		EXPECT_NEAR(out.elasticPotential - hertz(d1), shear, 1e-9 * shear) << "step " << i;
	}
	const double fs1 = 3 * ks1 * D.norm(), fs2 = fs1 + ks2 * D.norm();
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(d2, D), out));
	EXPECT_NEAR(out.shearContact.norm(), fs2, 1e-12 * fs2); // still elastic
	const double shear = 0.5 * fs1 * fs1 / ks1 + 0.5 * (fs2 * fs2 - fs1 * fs1) / ks2;
	EXPECT_NEAR(out.elasticPotential - hertz(d2), shear, 1e-9 * shear);
	EXPECT_GT(std::abs(shear - 0.5 * fs2 * fs2 / ks2), 0.1 * shear); // differs from |Fs|²/(2ks)
	// Separation clears it (no bridge with the dry models: the interaction is erased) …
	EXPECT_FALSE(evaluatePair<true>(Dry{}, p, st, restingOverlap(-1e-9), out));
	// … and a bridge model keeps the interaction but not the shear energy.
	const PairModels<AdamsPerchard, NoTangentialViscous, NoContactDamping> wet{ AdamsPerchard(1.0, kRadius / 2), {}, {} };
	PairState st2;
	ASSERT_TRUE(evaluatePair<true>(wet, p, st2, restingOverlap(d1, D), out));
	EXPECT_GT(st2.shearPotential, 0.0);
	ASSERT_TRUE(evaluatePair<true>(wet, p, st2, restingOverlap(-1e-9), out));
	EXPECT_EQ(st2.shearPotential, 0.0);
	EXPECT_EQ(out.elasticPotential, 0.0);
}

// Spheres placed exactly touching (overlap 0, found by the property-based campaign with a touching
// packing): ks = 0 and the Coulomb limit is 0, so a shear force carried from the previous steps
// slides to zero in one step.  The friction dissipation is then the shear energy stored until now,
// finite (it was ((trial − F)/ks)·F = (x/0)·0 = NaN), and nothing stays stored.
TEST(PairContact, SlidingAtZeroOverlapReleasesTheStoredShearEnergy)
{
	const PairParams p     = referenceParams(kMEff);
	const double     delta = 1e-8;
	const Vec3       D     = 1e-13 * kT; // elastic at δ: below the Coulomb limit
	PairState        st;
	PairOutput       loaded;
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(delta, D), loaded));
	ASSERT_GT(st.shearElastic.norm(), 0.0);
	const double stored = st.shearPotential; // |F_s|²/(2 ks) of the first step
	ASSERT_NEAR(stored, 0.5 * st.shearElastic.squaredNorm() / loaded.ks, 1e-12 * stored);
	ASSERT_GT(stored, 0.0);
	PairOutput touching;
	ASSERT_TRUE(evaluatePair<true>(Dry{}, p, st, restingOverlap(0.0), touching));
	EXPECT_TRUE(std::isfinite(touching.dissipFriction));
	EXPECT_NEAR(touching.dissipFriction, stored, 1e-12 * stored);
	EXPECT_EQ(touching.elasticPotential, 0.0);
	EXPECT_EQ(st.shearElastic.norm(), 0.0);
}
