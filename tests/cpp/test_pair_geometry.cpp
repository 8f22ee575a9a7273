// Reduced radius and mass (§1), the clamped gap (P6) and the rupture distance (P11).
#include "test_support.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include <cmath>
#include <gtest/gtest.h>

using namespace viscbridge;
using vbtest::kPi;

// §1: r̄ = r_i r_j/(r_i + r_j).  1 mm and 3 mm give 3/4 mm; equal spheres give r/2.
TEST(ReducedRadius, SphereSphere)
{
	EXPECT_NEAR(reducedRadius(1e-3, 3e-3), 0.75e-3, 1e-18);
	EXPECT_NEAR(reducedRadius(3e-3, 1e-3), 0.75e-3, 1e-18); // symmetric
	EXPECT_NEAR(reducedRadius(0.5e-3, 0.5e-3), 0.25e-3, 1e-18);
}

// §1: against a wall or facet (passed as radius 0) r̄ is the sphere's radius, on either side.
TEST(ReducedRadius, WallSideHasRadiusZero)
{
	EXPECT_EQ(reducedRadius(0.0, 2e-3), 2e-3);
	EXPECT_EQ(reducedRadius(2e-3, 0.0), 2e-3);
	// A large sphere approaches the wall limit continuously: r̄ → r as r_j → ∞.
	EXPECT_NEAR(reducedRadius(2e-3, 1e6), 2e-3, 1e-11);
}

// §1: m* = m_i m_j/(m_i + m_j); a fixed body (wall, fixed particle) leaves the other body's mass.
TEST(ReducedMass, DynamicAndFixed)
{
	EXPECT_NEAR(reducedMass(2.0, true, 6.0, true), 2.0 * 6.0 / 8.0, 1e-15);
	EXPECT_EQ(reducedMass(2.0, false, 6.0, true), 6.0);
	EXPECT_EQ(reducedMass(2.0, true, 6.0, false), 2.0);
	// A fixed body's mass is irrelevant even when it is tiny (e.g. a facet with zero mass).
	EXPECT_EQ(reducedMass(0.0, false, 6.0, true), 6.0);
}

// P6: S_eff = max(S, S_min), also in overlap (S < 0).
TEST(ClampedGap, MaxOfGapAndMinimum)
{
	const double sMin = 1e-6;
	EXPECT_EQ(clampedGap(3e-6, sMin), 3e-6); // open gap above S_min: unchanged
	EXPECT_EQ(clampedGap(1e-7, sMin), sMin); // small gap: clamped
	EXPECT_EQ(clampedGap(sMin, sMin), sMin); // at the boundary
	EXPECT_EQ(clampedGap(0.0, sMin), sMin);  // touching
	EXPECT_EQ(clampedGap(-5e-6, sMin), sMin); // overlap: never negative, so C^n stays finite and positive
}

// P11 (Lian 1993): S_rup = (1 + θ/2) V^(1/3).
TEST(RuptureDistance, LianFormula)
{
	const double V = 2.7e-11; // V^(1/3) = 3e-4
	EXPECT_NEAR(ruptureDistance(V, 0.0), 3e-4, 1e-15);
	const double theta = 40 * kPi / 180;
	EXPECT_NEAR(ruptureDistance(V, theta), (1 + 0.5 * theta) * 3e-4, 1e-15);
}

// physics.md R3: V = 1 % of a sphere of radius r and θ = 0 give S_rup = 0.347 r (independent of r).
TEST(RuptureDistance, PhysicsMdExampleR3)
{
	for (double r : { 1e-4, 5e-4, 2e-3 }) {
		const double V = 0.01 * 4.0 / 3.0 * kPi * r * r * r;
		// (0.01·4π/3)^(1/3) = 0.347293…; physics.md quotes 3 digits.
		EXPECT_NEAR(ruptureDistance(V, 0.0) / r, 0.347, 5e-4);
		EXPECT_NEAR(ruptureDistance(V, 0.0) / r, std::cbrt(0.01 * 4.0 / 3.0 * kPi), 1e-12);
	}
}
