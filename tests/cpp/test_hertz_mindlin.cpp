// Hertz–Mindlin constants and the restitution damping ratio, against YADE 2025.2.0's
// Ip2_FrictMat_FrictMat_MindlinPhys (pkg/dem/HertzMindlin.cpp), whose formulas are written out here.
#include "test_support.hpp"
#include "viscbridge/core/models/contact/HertzMindlin.hpp"
#include <cmath>
#include <gtest/gtest.h>

using namespace viscbridge;

namespace {
// YADE's formulas: Ga = E/(2(1+ν)), G = 1/((2−νa)/Ga + (2−νb)/Gb),
// E = EaEb/((1−νa²)Eb + (1−νb²)Ea), R = DaDb/(Da+Db) with a nonpositive radius replaced by the
// other one, kno = 4/3 E √R, kso = 8 √R G, tanφ = tan(min(φa, φb)).
HertzMindlinConstants yadeMindlin(const ElasticProperties& a, const ElasticProperties& b, double r1, double r2)
{
	const double Da = r1 > 0 ? r1 : r2, Db = r2 > 0 ? r2 : r1;
	const double Ga = a.young / (2 * (1 + a.poisson)), Gb = b.young / (2 * (1 + b.poisson));
	const double G  = 1 / ((2 - a.poisson) / Ga + (2 - b.poisson) / Gb);
	const double E  = a.young * b.young / ((1 - a.poisson * a.poisson) * b.young + (1 - b.poisson * b.poisson) * a.young);
	const double R  = Da * Db / (Da + Db);
	return { 4.0 / 3.0 * E * std::sqrt(R), 8 * std::sqrt(R) * G, std::tan(std::min(a.frictionAngle, b.frictionAngle)) };
}
} // namespace

// Two different materials and radii: every quantity differs between the sides.
TEST(HertzMindlin, ConstantsMatchYadeForDissimilarSpheres)
{
	const ElasticProperties a{ 1e7, 0.3, 0.5 }, b{ 5e8, 0.2, 0.3 };
	const HertzMindlinConstants c = hertzMindlinConstants(a, b, 1e-3, 2e-3), y = yadeMindlin(a, b, 1e-3, 2e-3);
	EXPECT_NEAR(c.kno, y.kno, 1e-14 * y.kno);
	EXPECT_NEAR(c.kso, y.kso, 1e-14 * y.kso);
	EXPECT_NEAR(c.tanPhi, y.tanPhi, 1e-15);
	// The same numbers from Python.
	EXPECT_NEAR(c.kno, 370496.3262263756, 1e-8);
	EXPECT_NEAR(c.kso, 458368.3467906286, 1e-8);
	EXPECT_NEAR(c.tanPhi, 0.30933624960962325, 1e-15);
	// Symmetric in the two sides.
	const HertzMindlinConstants swapped = hertzMindlinConstants(b, a, 2e-3, 1e-3);
	EXPECT_NEAR(swapped.kno, c.kno, 1e-14 * c.kno);
	EXPECT_NEAR(swapped.kso, c.kso, 1e-14 * c.kso);
}

// Equal materials: E* = E/(2(1−ν²)) and G* = G/(2(2−ν)) — the textbook Hertz–Mindlin constants.
TEST(HertzMindlin, EqualMaterialsReduceToTextbookValues)
{
	const double E = 2e8, nu = 0.25, r = 1.5e-3, R = r / 2;
	const ElasticProperties m{ E, nu, 0.4 };
	const HertzMindlinConstants c = hertzMindlinConstants(m, m, r, r);
	const double Estar = E / (2 * (1 - nu * nu)), Gstar = E / (2 * (1 + nu)) / (2 * (2 - nu));
	EXPECT_NEAR(c.kno, 4.0 / 3.0 * Estar * std::sqrt(R), 1e-14 * c.kno);
	EXPECT_NEAR(c.kso, 8 * Gstar * std::sqrt(R), 1e-14 * c.kso);
	EXPECT_NEAR(c.tanPhi, std::tan(0.4), 1e-15);
}

// A side with reference radius 0 (YADE's convention when one side has none): YADE replaces it by the
// other radius, so R = r/2; kept identical on purpose (HertzMindlin.hpp) for YADE's trajectories.
TEST(HertzMindlin, ZeroReferenceRadiusUsesTheOtherSideLikeYade)
{
	const ElasticProperties m{ 1e7, 0.3, 0.5 };
	for (const auto& [r1, r2] : { std::pair{ 0.0, 2e-3 }, std::pair{ 2e-3, 0.0 } }) {
		const HertzMindlinConstants c = hertzMindlinConstants(m, m, r1, r2), y = yadeMindlin(m, m, r1, r2);
		EXPECT_NEAR(c.kno, y.kno, 1e-14 * y.kno);
		EXPECT_NEAR(c.kso, y.kso, 1e-14 * y.kso);
		EXPECT_NEAR(c.kno, 231668.6930526285, 1e-8); // Python, R = 1e-3
	}
}

// Thornton et al. (2013) (B6)–(B7), as YADE computes betan from en.
TEST(DampingRatio, ValuesFromThorntonFit)
{
	EXPECT_EQ(dampingRatioFromRestitution(1.0), 0.0);
	EXPECT_NEAR(dampingRatioFromRestitution(0.5), 0.2330248576834424, 1e-14);
	EXPECT_NEAR(dampingRatioFromRestitution(0.9), 0.031306565990159074, 1e-15);
	EXPECT_NEAR(dampingRatioFromRestitution(0.1), 1.1342510657848295, 1e-13); // Python
}

// Less restitution needs more damping: β strictly decreasing on (0, 1].
TEST(DampingRatio, MonotoneDecreasingInRestitution)
{
	double previous = dampingRatioFromRestitution(0.001);
	EXPECT_GT(previous, 1.0);
	for (int i = 2; i <= 1000; ++i) {
		const double e = i * 0.001, beta = dampingRatioFromRestitution(e);
		ASSERT_LT(beta, previous) << "e=" << e;
		ASSERT_GE(beta, 0.0) << "e=" << e;
		previous = beta;
	}
}

// A property of the fit that YADE shares: β does not tend to 0 as e → 1⁻ (the polynomial is finite
// at e = 1), only e = 1 exactly gives 0.  A user asking for e = 0.999999 gets β ≈ 0.0045 (a linear
// dashpot with that ratio restitutes e ≈ 0.986) — documented here, not changed.
TEST(DampingRatio, FitDoesNotVanishJustBelowOne)
{
	EXPECT_NEAR(dampingRatioFromRestitution(0.999999), 0.004526832503024246, 1e-12);
	EXPECT_GT(dampingRatioFromRestitution(1.0 - 1e-15), 0.0045);
}
