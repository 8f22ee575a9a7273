// Bridge life in the pair kernel (physics.md §2 "Bridge life"): formation at contact or within
// formationDistance, persistence up to the rupture distance S_rup (P11), no re-formation before the
// next contact, and no interaction at all beyond contact when no viscous effect is selected.
#include "pair_test_support.hpp"
#include <gtest/gtest.h>

using namespace viscbridge;
using namespace vbtest;

namespace {
using BridgeModels  = PairModels<AdamsPerchard, SlipTangential, NoContactDamping>;
const double kRBar  = kRadius / 2;
const double kMEff  = sphereMass(kRadius) / 2;
BridgeModels bridgeModels() { return { AdamsPerchard(1.0, kRBar), SlipTangential(1.0, kRBar), {} }; }

// One evaluation at gap S with the spheres approaching at 1 mm/s along n = e_x.
bool step(const BridgeModels& m, const PairParams& p, PairState& st, double S, PairOutput& out)
{
	const PairInput in = spherePair(Vec3::Zero(), Vec3::UnitX(), kRadius, kRadius, S, Vec3(1e-3, 0, 0), Vec3::Zero(), Vec3::Zero(),
	                                Vec3::Zero(), 1e-8);
	return evaluatePair<false>(m, p, st, in, out);
}
} // namespace

TEST(BridgeLife, FormsAtContactLivesUntilRuptureThenStaysBroken)
{
	const BridgeModels m = bridgeModels();
	const PairParams   p = referenceParams(kMEff); // formationDistance = 0
	ASSERT_NEAR(p.sRup / kRadius, 0.347, 5e-4);
	PairState  st;
	PairOutput out;
	// Approaching but not yet touching: no bridge, the interaction may be erased.
	EXPECT_FALSE(step(m, p, st, 0.5 * p.sRup, out));
	EXPECT_FALSE(st.bridge);
	// Contact (S ≤ 0; S = 0 counts) forms the bridge.
	EXPECT_TRUE(step(m, p, st, 0.0, out));
	EXPECT_TRUE(st.bridge);
	// Separating: kept, with a viscous force, for 0 < S ≤ S_rup.
	for (double rel : { 1e-6, 0.1, 0.5, 0.999, 1.0 }) {
		EXPECT_TRUE(step(m, p, st, rel * p.sRup, out)) << "S/S_rup=" << rel;
		EXPECT_TRUE(st.bridge) << "S/S_rup=" << rel;
		EXPECT_GT(out.cn, 0.0) << "S/S_rup=" << rel;
		EXPECT_LT(out.force1.dot(Vec3::UnitX()), 0.0) << "S/S_rup=" << rel; // resists the approach velocity
	}
	// Beyond S_rup: ruptured, erase.
	EXPECT_FALSE(step(m, p, st, p.sRup * (1 + 1e-9), out));
	EXPECT_FALSE(st.bridge);
	// Coming back within S_rup does not re-form it at 0 < S …
	for (double rel : { 0.9, 0.1, 1e-6 }) {
		EXPECT_FALSE(step(m, p, st, rel * p.sRup, out)) << "S/S_rup=" << rel;
		EXPECT_FALSE(st.bridge) << "S/S_rup=" << rel;
	}
	// … only the next contact does.
	EXPECT_TRUE(step(m, p, st, -1e-9, out));
	EXPECT_TRUE(st.bridge);
}

// formationDistance > 0: a bridge forms at S ≤ formationDistance without contact.
TEST(BridgeLife, FormsWithinFormationDistance)
{
	const BridgeModels m = bridgeModels();
	const PairParams   p = referenceParams(kMEff, 0.2 * referenceParams(kMEff).sRup);
	PairOutput         out;
	{
		PairState st;
		EXPECT_FALSE(step(m, p, st, 1.01 * p.formationDistance, out));
		EXPECT_FALSE(st.bridge);
		EXPECT_TRUE(step(m, p, st, p.formationDistance, out)); // S ≤ formationDistance
		EXPECT_TRUE(st.bridge);
		EXPECT_GT(out.cn, 0.0);
		// Once formed it lives to S_rup, beyond formationDistance, …
		EXPECT_TRUE(step(m, p, st, 0.9 * p.sRup, out));
		EXPECT_TRUE(st.bridge);
		// … and ruptures beyond S_rup.
		EXPECT_FALSE(step(m, p, st, 1.1 * p.sRup, out));
		EXPECT_FALSE(st.bridge);
	}
	{
		PairState st;
		EXPECT_TRUE(step(m, p, st, 0.5 * p.formationDistance, out));
		EXPECT_TRUE(st.bridge);
	}
}

// A formationDistance beyond S_rup cannot create a bridge that would at once be ruptured.
TEST(BridgeLife, FormationDistanceBeyondRuptureIsCappedAtRupture)
{
	const BridgeModels m  = bridgeModels();
	const double       sR = referenceParams(kMEff).sRup;
	const PairParams   p  = referenceParams(kMEff, 2 * sR);
	PairOutput         out;
	PairState          st;
	EXPECT_FALSE(step(m, p, st, 1.5 * sR, out));
	EXPECT_FALSE(st.bridge);
	EXPECT_TRUE(step(m, p, st, 0.9 * sR, out));
	EXPECT_TRUE(st.bridge);
}

// With no viscous effect the kernel is YADE's Law2_ScGeom_MindlinPhys_Mindlin: the interaction is
// erased as soon as S > 0 (returns false), kept in contact.
TEST(BridgeLife, WithoutViscousEffectsErasedAsSoonAsSeparated)
{
	using Dry = PairModels<NoNormalViscous, NoTangentialViscous, NoContactDamping>;
	static_assert(!Dry::hasBridge);
	const Dry        m{};
	const PairParams p = referenceParams(kMEff, 0.2 * referenceParams(kMEff).sRup); // formationDistance ignored
	PairState        st;
	PairOutput       out;
	const auto       dryStep = [&](double S) {
		const PairInput in = spherePair(Vec3::Zero(), Vec3::UnitX(), kRadius, kRadius, S, Vec3(1e-3, 0, 0), Vec3::Zero(), Vec3::Zero(),
		                                Vec3::Zero(), 1e-8);
		return evaluatePair<false>(m, p, st, in, out);
	};
	EXPECT_TRUE(dryStep(-1e-7));
	EXPECT_GT(out.force1.norm(), 0.0); // Hertz repulsion
	EXPECT_TRUE(dryStep(0.0));
	EXPECT_FALSE(dryStep(1e-15));
	EXPECT_FALSE(dryStep(0.1 * p.formationDistance));
	EXPECT_FALSE(st.bridge);
	// With contact damping only, still no bridge.
	using Damped = PairModels<NoNormalViscous, NoTangentialViscous, RestitutionContactDamping>;
	static_assert(!Damped::hasBridge);
}

// Either viscous term alone makes a bridge.
TEST(BridgeLife, EitherViscousTermAloneMakesABridge)
{
	const PairParams p = referenceParams(kMEff);
	const PairInput  touch = spherePair(Vec3::Zero(), Vec3::UnitX(), kRadius, kRadius, 0.0, Vec3(1e-3, 0, 0), Vec3::Zero(), Vec3::Zero(),
	                                    Vec3::Zero(), 1e-8);
	PairInput apart = touch;
	apart.S         = 0.5 * p.sRup;
	PairOutput out;
	{
		const PairModels<AdamsPerchard, NoTangentialViscous, NoContactDamping> m{ AdamsPerchard(1.0, kRBar), {}, {} };
		PairState st;
		EXPECT_TRUE(evaluatePair<false>(m, p, st, touch, out));
		EXPECT_TRUE(evaluatePair<false>(m, p, st, apart, out));
		EXPECT_GT(out.cn, 0.0);
	}
	{
		const PairModels<NoNormalViscous, SlipTangential, NoContactDamping> m{ {}, SlipTangential(1.0, kRBar), {} };
		PairState st;
		EXPECT_TRUE(evaluatePair<false>(m, p, st, touch, out));
		EXPECT_TRUE(evaluatePair<false>(m, p, st, apart, out));
		EXPECT_GT(out.ct, 0.0);
		EXPECT_EQ(out.cn, 0.0);
	}
}

// A bridge without contact carries no elastic shear history into the next contact.
TEST(BridgeLife, ShearHistoryClearedWhenNotInContact)
{
	const BridgeModels m = bridgeModels();
	const PairParams   p = referenceParams(kMEff);
	PairState          st;
	PairOutput         out;
	PairInput in = spherePair(Vec3::Zero(), Vec3::UnitX(), kRadius, kRadius, -1e-7, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
	                          1e-8, Vec3(0, 1e-9, 0));
	ASSERT_TRUE(evaluatePair<false>(m, p, st, in, out));
	EXPECT_GT(st.shearElastic.norm(), 0.0);
	in.S              = 1e-6;
	in.shearIncrement = Vec3::Zero();
	ASSERT_TRUE(evaluatePair<false>(m, p, st, in, out));
	EXPECT_EQ(st.shearElastic, Vec3::Zero());
}
