// Goldman's small-gap tangential coefficients C_T (P8), C_R (P9) and C_W (goldman model, §2).
#include "test_support.hpp"
#include "viscbridge/core/models/tangential/GoldmanCoefficients.hpp"
#include <cmath>
#include <gtest/gtest.h>

using namespace viscbridge;
using vbtest::kPi;

// P8, P9 (with +0.2526) and C_W written out: μ = 0.8 Pa·s, r̄ = 1 mm, S = 10 µm (ln(r̄/S) = ln 100).
TEST(GoldmanCoefficients, ValuesAtSmallGap)
{
	const double mu = 0.8, rBar = 1e-3, S = 1e-5;
	const double k  = 6 * kPi * mu * rBar;
	const double L  = std::log(100.0);
	const GoldmanCoefficients c = goldmanCoefficients(k, rBar, S);
	const double cT = k * (8.0 / 15.0 * L + 0.9588); // P8
	const double cR = k * (2.0 / 15.0 * L + 0.2526); // P9
	const double cW = k * (8.0 / 15.0 * L + 0.5089); // C_W
	EXPECT_NEAR(c.translation, cT, 1e-14 * cT);
	EXPECT_NEAR(c.coupling, cR, 1e-14 * cR);
	EXPECT_NEAR(c.rotation, cW, 1e-14 * cW);
	// The same numbers from Python: 6π·0.8e-3·(…).
	EXPECT_NEAR(c.translation, 0.05149533956562427, 1e-14);
	EXPECT_NEAR(c.coupling, 0.013068362308516348, 1e-14);
	EXPECT_NEAR(c.rotation, 0.04471100739834404, 1e-14);
}

// At S = r̄ the logarithm vanishes and each coefficient is 6πμ r̄ times its constant.  In particular
// C_R = +0.2526·6πμ r̄ > 0: with the misprinted "− 0.2526" it would be negative here (physics.md P9, §9).
TEST(GoldmanCoefficients, ConstantsAtGapEqualReducedRadius)
{
	const double rBar = 2e-3, k = 6 * kPi * 1.0 * rBar;
	const GoldmanCoefficients c = goldmanCoefficients(k, rBar, rBar);
	EXPECT_NEAR(c.translation / k, 0.9588, 1e-15);
	EXPECT_NEAR(c.coupling / k, 0.2526, 1e-15);
	EXPECT_NEAR(c.rotation / k, 0.5089, 1e-15);
}

// C_R > 0 over every gap a bridge can have (S_rup ≲ 1.5 r̄ for V ≤ 10 %, §2), and further out to
// where ln(r̄/S) = −0.2526·15/2, i.e. S = 6.65 r̄.
TEST(GoldmanCoefficients, CouplingPositiveInsideBridges)
{
	const double rBar = 1e-3, k = 1.0;
	for (double rel = 1e-6; rel <= 6.6; rel *= 1.1)
		EXPECT_GT(goldmanCoefficients(k, rBar, rel * rBar).coupling, 0.0) << "S/r̄=" << rel;
	EXPECT_LT(goldmanCoefficients(k, rBar, 6.7 * rBar).coupling, 0.0);
}

// Claims in TangentialViscous.hpp: C_T > 0 up to S ≈ 6 r̄ (root at r̄·e^{0.9588·15/8} = 6.036 r̄), and
// C_T C_W ≥ C_R² (the goldman model's dissipativity) up to S = 2.4215 r̄ (root found by bisection).
TEST(GoldmanCoefficients, SignChangesWhereTheHeaderSays)
{
	const double rBar = 1e-3, k = 1.0;
	EXPECT_GT(goldmanCoefficients(k, rBar, 6.03 * rBar).translation, 0.0);
	EXPECT_LT(goldmanCoefficients(k, rBar, 6.04 * rBar).translation, 0.0);
	const auto det = [&](double rel) {
		const GoldmanCoefficients c = goldmanCoefficients(k, rBar, rel * rBar);
		return c.translation * c.rotation - c.coupling * c.coupling;
	};
	for (double rel = 1e-6; rel < 2.42; rel *= 1.05) EXPECT_GT(det(rel), 0.0) << "S/r̄=" << rel;
	EXPECT_GT(det(2.421), 0.0);
	EXPECT_LT(det(2.422), 0.0);
}
