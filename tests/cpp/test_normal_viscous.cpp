// Normal viscous coefficients: Adams–Perchard (P4) and Pitois (P5), evaluated at the clamped gap.
#include "test_support.hpp"
#include "viscbridge/core/models/normal/NormalViscous.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace viscbridge;
using vbtest::kPi;

namespace {
// P5's volume factor written out directly (accurate where x = V/(π r̄ S²) is not tiny).
double pitoisFactorDirect(double V, double rBar, double S)
{
	const double x       = V / (kPi * rBar * S * S);
	const double bracket = 1.0 - 1.0 / std::sqrt(1.0 + x);
	return bracket * bracket;
}
} // namespace

TEST(NormalViscous, NoneHasZeroCoefficient)
{
	EXPECT_FALSE(NoNormalViscous::capabilities.enabled);
	EXPECT_EQ(NoNormalViscous().coefficient(1e-6), 0.0);
}

// P4: C^n = 6πμ r̄²/S.  μ = 1 Pa·s, r̄ = 0.25 mm (two 0.5 mm spheres), S = 1 µm.
TEST(NormalViscous, AdamsPerchardValue)
{
	const double mu = 1.0, rBar = 2.5e-4, S = 1e-6;
	const AdamsPerchard ap(mu, rBar);
	const double expected = 6 * kPi * mu * rBar * rBar / S; // P4
	EXPECT_NEAR(ap.coefficient(S), expected, 1e-14 * expected);
	EXPECT_NEAR(ap.coefficient(S), 1.1780972450961724, 1e-12); // same number from Python
	// 1/S: halving the gap doubles the coefficient; linear in μ.
	EXPECT_NEAR(ap.coefficient(S / 2), 2 * expected, 1e-14 * expected);
	EXPECT_NEAR(AdamsPerchard(3 * mu, rBar).coefficient(S), 3 * expected, 1e-14 * expected);
}

// P5: C^n = 6πμ r̄²/S · [1 − (1 + V/(π r̄ S²))^(−1/2)]².  V = 1 % of a 0.5 mm sphere, μ = 0.5,
// r̄ = 0.25 mm, S = 10 µm, so x = V/(π r̄ S²) = 66.7 and the direct formula has no cancellation.
TEST(NormalViscous, PitoisValueAndVolumeFactor)
{
	const double mu = 0.5, rBar = 2.5e-4, r = 5e-4, S = 1e-5;
	const double V = 0.01 * 4.0 / 3.0 * kPi * r * r * r;
	const Pitois p(mu, rBar, V);
	const double factor = pitoisFactorDirect(V, rBar, S);
	EXPECT_NEAR(p.volumeFactor(S), factor, 1e-13 * factor);
	EXPECT_NEAR(p.volumeFactor(S), 0.7716460555812202, 1e-13); // Python
	const double expected = 6 * kPi * mu * rBar * rBar / S * factor; // P5
	EXPECT_NEAR(p.coefficient(S), expected, 1e-13 * expected);
	EXPECT_NEAR(p.coefficient(S), 0.04545370461347817, 1e-13 * expected); // Python
	// Other gaps, x from 6.7e-3 to 6.7e4: expm1/log1p form agrees with the direct one (the direct
	// form loses ~4 digits at the smallest x, hence 1e-11).
	for (double s : { 1e-7, 1e-6, 1e-4, 1e-3 })
		EXPECT_NEAR(p.volumeFactor(s), pitoisFactorDirect(V, rBar, s), 1e-11 * pitoisFactorDirect(V, rBar, s)) << "S=" << s;
}

// §2: the factor is ≤ 1, so Pitois ≤ Adams–Perchard for every gap, volume and radius.
TEST(NormalViscous, PitoisNeverExceedsAdamsPerchard)
{
	std::mt19937 g(20240611);
	for (int i = 0; i < 10000; ++i) {
		const double mu = vbtest::logUniform(g, 1e-3, 1e3), rBar = vbtest::logUniform(g, 1e-6, 1e-2);
		const double V  = vbtest::logUniform(g, 1e-8, 1e2) * rBar * rBar * rBar;
		const double S  = vbtest::logUniform(g, 1e-7, 3.0) * rBar;
		const Pitois        p(mu, rBar, V);
		const AdamsPerchard ap(mu, rBar);
		const double        f = p.volumeFactor(S);
		ASSERT_GT(f, 0.0) << "i=" << i;
		ASSERT_LE(f, 1.0) << "i=" << i;
		ASSERT_LE(p.coefficient(S), ap.coefficient(S)) << "i=" << i;
	}
}

// §2: Pitois → Adams–Perchard as V → ∞.  The factor is ≈ 1 − 2/√x, so x = 1e16 gives 2e-8.
TEST(NormalViscous, PitoisTendsToAdamsPerchardForLargeVolume)
{
	const double mu = 1.0, rBar = 1e-3, S = 1e-5;
	const AdamsPerchard ap(mu, rBar);
	double previous = 0;
	for (double x : { 1e0, 1e4, 1e8, 1e12, 1e16 }) {
		const double ratio = Pitois(mu, rBar, x * kPi * rBar * S * S).coefficient(S) / ap.coefficient(S);
		EXPECT_GT(ratio, previous) << "x=" << x; // grows monotonically with V
		previous = ratio;
	}
	EXPECT_NEAR(previous, 1.0, 1e-6);
	EXPECT_NEAR(previous, 1.0 - 2e-8, 1e-12); // the asymptote 1 − 2/√x
}

// §2: for a small bridge at a large gap x → 0 and the bracket ≈ x/2 − 3x²/8.  Computing it as
// 1 − (1+x)^(−1/2) would keep no correct digit at x = 1e-12 (cancellation); the header must.
TEST(NormalViscous, PitoisSmallVolumeLimitHasNoCancellation)
{
	const double rBar = 1.0, S = 1.0;
	const Pitois p(1.0, rBar, 1e-12 * kPi);
	const double x       = p.a2 / (S * S); // = 1e-12 up to rounding; take the exact value used
	const double bracket = x / 2 - 3 * x * x / 8;  // next term 5x³/16 is 1e-24 relative
	EXPECT_NEAR(x, 1e-12, 1e-26);
	EXPECT_NEAR(p.volumeFactor(S), bracket * bracket, 1e-12 * bracket * bracket);
	EXPECT_NEAR(std::sqrt(p.volumeFactor(S)), bracket, 1e-12 * bracket);
}
