// Capillary models (physics.md §8, P19–P22) and their place in the pair kernel.
#include "pair_test_support.hpp"
#include "viscbridge/core/models/capillary/Capillary.hpp"
#include <gtest/gtest.h>

using namespace vbtest;

namespace {
constexpr double kGamma = 0.072, kRBar = kRadius / 2;
const double     kVolume = 0.01 * 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius; // 1 % of a particle

// P19 written out here from Willett et al.: F = 2πRγ cosθ/(1 + 2.1 s⁺ + 10 s⁺²), s⁺ = (S/2)√(R/V).
double willett(double R, double theta, double S) { const double s = S / 2 * std::sqrt(R / kVolume); return 2 * kPi * R * kGamma * std::cos(theta) / (1 + 2.1 * s + 10 * s * s); }

// P20 written out from Rabinovich et al.: d = (S/2)(−1 + √(1 + 2V/(πRS²))), α = √(2d/R),
// F = 2πRγ [cos θ/(1 + S/(2d)) + sin α sin(θ + α)].
double rabinovich(double R, double theta, double S)
{
	const double d = S / 2 * (-1 + std::sqrt(1 + 2 * kVolume / (kPi * R * S * S))), alpha = std::sqrt(2 * d / R);
	return 2 * kPi * R * kGamma * (std::cos(theta) / (1 + S / (2 * d)) + std::sin(alpha) * std::sin(theta + alpha));
}

template <class M> double numericalStiffness(const M& m, double S) { const double h = 1e-6 * S; return -(m.force(S + h) - m.force(S - h)) / (2 * h); }
} // namespace

// The force at contact: 2πRγ cos θ with R = r for equal spheres (Willett), 2r against a wall.
TEST(Capillary, WillettForceAtContact)
{
	for (double theta : { 0.0, 0.5, 1.2 }) {
		EXPECT_NEAR(WillettCapillary(kRBar, kGamma, theta, kVolume).force(0.0), 2 * kPi * kRadius * kGamma * std::cos(theta), 1e-15);
		EXPECT_NEAR(WillettCapillary(kRadius, kGamma, theta, kVolume).force(0.0), 4 * kPi * kRadius * kGamma * std::cos(theta), 1e-15); // wall
		// held at its contact value in overlap
		EXPECT_EQ(WillettCapillary(kRBar, kGamma, theta, kVolume).force(-1e-6), WillettCapillary(kRBar, kGamma, theta, kVolume).force(0.0));
	}
}

TEST(Capillary, ForceAgainstGapFollowsTheFormulas)
{
	const double sRup = ruptureDistance(kVolume, 0.0);
	for (double theta : { 0.0, 0.6 })
		for (double f : { 1e-4, 0.01, 0.1, 0.5, 1.0 }) {
			const double S = f * sRup;
			EXPECT_NEAR(WillettCapillary(kRBar, kGamma, theta, kVolume).force(S), willett(kRadius, theta, S), 1e-13 * willett(kRadius, theta, 0));
			EXPECT_NEAR(RabinovichCapillary(kRBar, kGamma, theta, kVolume).force(S), rabinovich(kRadius, theta, S), 1e-12 * rabinovich(kRadius, theta, S));
		}
	// Rabinovich at contact: the limit of its formula, 2πRγ [cos θ + sin α₀ sin(θ + α₀)], α₀ = (2V/(πR³))^¼
	const double alpha0 = std::pow(2 * kVolume / (kPi * std::pow(kRadius, 3)), 0.25);
	EXPECT_NEAR(RabinovichCapillary(kRBar, kGamma, 0.3, kVolume).force(0.0), 2 * kPi * kRadius * kGamma * (std::cos(0.3) + std::sin(alpha0) * std::sin(0.3 + alpha0)),
	            1e-12);
	EXPECT_NEAR(RabinovichCapillary(kRBar, kGamma, 0.3, kVolume).force(1e-12 * kRadius) / RabinovichCapillary(kRBar, kGamma, 0.3, kVolume).force(0.0), 1.0, 1e-5);
	// the pull weakens with the gap: F(S_rup)/F(0) = 0.100 for Willett at V = 1 %, θ = 0 (physics.md §8)
	EXPECT_NEAR(WillettCapillary(kRBar, kGamma, 0, kVolume).force(sRup) / WillettCapillary(kRBar, kGamma, 0, kVolume).force(0), 0.100, 0.002);
}

// P22: the stiffness is −dF/dS, and the step's stiffness is its maximum over the bridge's life.
TEST(Capillary, StiffnessIsTheSlopeAndItsMaximumIsFound)
{
	const double     sRup = ruptureDistance(kVolume, 0.0);
	BridgeInputs     in;
	in.sRup = sRup;
	for (double theta : { 0.0, 0.8 }) {
		const WillettCapillary    w(kRBar, kGamma, theta, kVolume);
		const RabinovichCapillary r(kRBar, kGamma, theta, kVolume);
		double                    maxW = 0, maxR = 0;
		for (int k = 1; k <= 4000; ++k) {
			const double S = sRup * k / 4000.0;
			EXPECT_NEAR(w.stiffness(S), numericalStiffness(w, S), 1e-6 * w.stiffness(S) + 1e-12);
			EXPECT_NEAR(r.stiffness(S), numericalStiffness(r, S), 1e-5 * r.stiffness(S) + 1e-12);
			maxW = std::max(maxW, w.stiffness(S));
			maxR = std::max(maxR, r.stiffness(S));
		}
		EXPECT_NEAR(w.stepStiffness(in), maxW, 1e-3 * maxW); // the closed form is the maximum
		EXPECT_GE(r.stepStiffness(in), maxR);                  // sampled with a margin: never below
		EXPECT_LE(r.stepStiffness(in), 1.1 * maxR);
	}
	EXPECT_EQ(WillettCapillary(kRBar, kGamma, 0, kVolume).stiffness(-1e-7), 0.0); // in overlap: constant
}

// P21: Willett's closed-form work is the integral of its force.
TEST(Capillary, WillettWorkIsTheIntegralOfTheForce)
{
	const double           sRup = ruptureDistance(kVolume, 0.0);
	const WillettCapillary w(kRBar, kGamma, 0, kVolume);
	double                 integral = 0;
	const int              n        = 200000;
	for (int k = 0; k < n; ++k)
		integral += w.force(sRup * (k + 0.5) / n) * sRup / n;
	EXPECT_NEAR(w.work(0.0, sRup), integral, 1e-7 * integral);
	EXPECT_NEAR(w.work(0.0, sRup) / (w.force(0) * kRadius), 0.1275, 0.0005); // physics.md §8
	EXPECT_NEAR(w.work(-1e-7, sRup) - w.work(0, sRup), w.force(0) * 1e-7, 1e-20);
}

// In the kernel: a capillary bridge without viscosity forms at contact, pulls along n, and in a
// frictionless conservative approach the kinetic energy and the booked capillary work balance.
TEST(Capillary, KernelPullsAlongTheNormalAndBooksItsWork)
{
	using Cap          = PairModels<NoNormalViscous, NoTangentialViscous, NoContactDamping, WillettCapillary>;
	const Cap    m     { {}, {}, {}, WillettCapillary(kRBar, kGamma, 0, kVolume) };
	static_assert(Cap::hasBridge, "a capillary model makes a bridge");
	const double mEff  = sphereMass(kRadius) / 2;
	PairParams   p     = referenceParams(mEff, 0.3 * ruptureDistance(kVolume, 0)); // formed within 0.3 S_rup
	PairState    st;
	PairOutput   out;
	// two spheres at rest at S = 0.2 S_rup: the pull makes them approach
	double       S = 0.2 * p.sRup, w = 0, work = 0;
	const double dt = 2e-7;
	double       ke0 = 0;
	for (int step = 0; step < 4000 && S > 0; ++step) {
		const PairInput in = spherePair(Vec3::Zero(), Vec3::UnitX(), kRadius, kRadius, S, Vec3(w / 2, 0, 0), Vec3(-w / 2, 0, 0), Vec3::Zero(), Vec3::Zero(), dt);
		ASSERT_TRUE(evaluatePair<false>(m, p, st, in, out));
		EXPECT_TRUE(st.bridge);
		EXPECT_GT(out.force1.dot(Vec3::UnitX()), 0);             // towards body 2
		EXPECT_NEAR(out.force1.cross(Vec3::UnitX()).norm(), 0, 1e-18);
		EXPECT_NEAR(out.capillary.norm(), m.capillary.force(S), 1e-18);
		work += out.capillaryWork;
		// leapfrog for the relative motion: w = approach speed (v1 − v2)·n
		w += dt * out.force1.dot(Vec3::UnitX()) / mEff;
		S -= w * dt;
	}
	ASSERT_LE(S, 0) << "the pull brought the pair into contact";
	const double ke = 0.5 * mEff * w * w - ke0;
	// the kinetic energy is what the pull did (booked with the sign of a dissipation, −W), up to the
	// work of the last step, which is booked at the next one
	EXPECT_NEAR(ke + work, 0, 0.02 * ke);
}
