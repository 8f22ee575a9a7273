// Whole trajectories through evaluatePair against physics.md §5's closed forms (R1–R3), for two equal
// spheres (r = 0.5 mm, ρ = 2500, so A = 6πμ r̄²/m* = 1.8 μ) moving along n = e_x.
//
// Integration as YADE's NewtonIntegrator (leapfrog, forces from x_n and v_{n−1/2}, §1), with a step
// Δt = f·min(m*/C^n(S), S/|w|) that follows the viscous time t_v (P12) and the time to close the
// gap: f = 1e-4 keeps the first-order error near 1e-4 relative, without millions of steps at S_min.
#include "pair_test_support.hpp"
#include <cmath>
#include <functional>
#include <gtest/gtest.h>

using namespace viscbridge;
using namespace vbtest;

namespace {
const double kRBar = kRadius / 2, kMass = sphereMass(kRadius), kMEff = kMass / 2;
const double kSMin = 1e-4 * kRadius;
const double kV    = 0.01 * 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius; // 1 % of a particle

struct Trajectory {
	double maxError = 0; // max |w_{n+1/2} − w_exact(S_{n+1/2})| along the way
	double wEnd     = 0; // relative speed of the last half step
	double sMax     = 0;
	bool   ruptured = false; // evaluatePair returned false
	long   steps    = 0;
};

// Relative speed w = (v1 − v2)·n > 0 for approach; `exact(S)` gives the closed-form w(S).
// Stops when S ≤ sStop (approach), when the pair ruptures, or when |w| < wStop.
template <class Models>
Trajectory integrate(const Models& m, PairParams p, double S0, double w0, const std::function<double(double)>& exact, double sStop, double wStop)
{
	const Vec3 n  = Vec3::UnitX();
	Vec3       x1 = Vec3::Zero(), x2 = (2 * kRadius + S0) * n;
	Vec3       v1 = 0.5 * w0 * n, v2 = -0.5 * w0 * n;
	PairState  st;
	st.bridge = true; // formed at an earlier contact
	Trajectory t;
	for (;;) {
		const double S = (x2 - x1).dot(n) - 2 * kRadius;
		PairOutput   out;
		if (!evaluatePair<false>(m, p, st, spherePair(x1, n, kRadius, kRadius, S, v1, v2, Vec3::Zero(), Vec3::Zero(), 1.0), out)) {
			t.ruptured = true;
			return t;
		}
		const double dt = 1e-4 * std::min(kMEff / out.cn, S / std::abs((v1 - v2).dot(n)));
		v1 += out.force1 / kMass * dt;
		v2 -= out.force1 / kMass * dt;
		x1 += v1 * dt;
		x2 += v2 * dt;
		++t.steps;
		const double sNew = (x2 - x1).dot(n) - 2 * kRadius, w = (v1 - v2).dot(n);
		t.wEnd     = w;
		t.sMax     = std::max(t.sMax, sNew);
		t.maxError = std::max(t.maxError, std::abs(w - exact(0.5 * (S + sNew))));
		if (sNew <= sStop || std::abs(w) < wStop || t.steps > 10000000) return t;
	}
}

using ApOnly     = PairModels<AdamsPerchard, NoTangentialViscous, NoContactDamping>;
using PitoisOnly = PairModels<Pitois, NoTangentialViscous, NoContactDamping>;
PairParams params() { return { referenceContact(), kMEff, kSMin, ruptureDistance(kV, 0.0), 0.0 }; }
} // namespace

TEST(PairTrajectories, ReducedViscousAccelerationIs1p8Mu)
{
	EXPECT_NEAR(6 * kPi * 1.0 * kRBar * kRBar / kMEff, 1.8, 1e-12); // physics.md §5
}

// R1 (Adams–Perchard approach): w(S) = w₀ − A ln(S₀/S).  μ = 1e-3, w₀ = 0.1 m/s, S₀ = 0.1 r:
// w(S_min = 1e-4 r) = 0.087566 m/s.
TEST(PairTrajectories, R1AdamsPerchardApproach)
{
	const double mu = 1e-3, A = 1.8 * mu, w0 = 0.1, S0 = 0.1 * kRadius;
	const auto   exact = [&](double S) { return w0 - A * std::log(S0 / S); };
	EXPECT_NEAR(exact(kSMin), 0.087566, 1e-6);
	const Trajectory t = integrate(ApOnly{ AdamsPerchard(mu, kRBar), {}, {} }, params(), S0, w0, exact, kSMin, 0.0);
	EXPECT_FALSE(t.ruptured);
	EXPECT_LT(t.maxError, 2e-5 * w0); // measured 5e-6 w₀
	EXPECT_NEAR(t.wEnd, exact(kSMin), 2e-5 * w0);
}

// R2 (Pitois approach): w(S) = w₀ − A[G(S₀) − G(S)], G(s) = ln s + ½ ln(s² + a²) − 2 ln(s + √(s² + a²)),
// a² = V/(π r̄).  μ = 1, w₀ = 15 m/s, S₀ = 0.1 r: w(S_min) = 4.3631 m/s (Adams–Perchard: 2.566).
TEST(PairTrajectories, R2PitoisApproach)
{
	const double mu = 1.0, A = 1.8 * mu, w0 = 15, S0 = 0.1 * kRadius, a2 = kV / (kPi * kRBar);
	const auto   G = [&](double s) { return std::log(s) + 0.5 * std::log(s * s + a2) - 2 * std::log(s + std::sqrt(s * s + a2)); };
	const auto   exact = [&](double S) { return w0 - A * (G(S0) - G(S)); };
	EXPECT_NEAR(exact(kSMin), 4.3631, 1e-4);
	EXPECT_NEAR(w0 - A * std::log(S0 / kSMin), 2.566, 1e-3);
	const Trajectory t = integrate(PitoisOnly{ Pitois(mu, kRBar, kV), {}, {} }, params(), S0, w0, exact, kSMin, 0.0);
	EXPECT_FALSE(t.ruptured);
	EXPECT_LT(t.maxError, 2e-3); // measured 3e-4 m/s
	EXPECT_NEAR(t.wEnd, exact(kSMin), 2e-3); // measured 3e-4 m/s (the last half step straddles S_min)
}

// R3 (separation from S_min at u₀): u(S) = u₀ − A ln(S/S_min); escapes iff u₀ > A ln(S_rup/S_min).
// V = 1 %, θ = 0, μ = 1: S_rup = 0.347 r, escape speed 14.67 m/s, u₀ = 20 m/s leaves at 5.325 m/s.
TEST(PairTrajectories, R3SeparationAndRupture)
{
	const double mu = 1.0, A = 1.8 * mu;
	const double escape = A * std::log(ruptureDistance(kV, 0.0) / kSMin);
	EXPECT_NEAR(escape, 14.67, 5e-3);
	const ApOnly m{ AdamsPerchard(mu, kRBar), {}, {} };
	{ // u₀ = 20 m/s: the bridge ruptures (evaluatePair returns false) at 5.325 m/s
		const double     u0    = 20;
		const auto       exact = [&](double S) { return -(u0 - A * std::log(S / kSMin)); }; // w = −u
		const Trajectory t     = integrate(m, params(), kSMin, -u0, exact, -1.0, 0.0);
		EXPECT_TRUE(t.ruptured);
		EXPECT_LT(t.maxError, 5e-3); // measured 1.1e-3 m/s, mostly from the first steps at S_min
		EXPECT_NEAR(-t.wEnd, 5.325, 5e-3);
	}
	{ // u₀ = 14.5 m/s < 14.67: the pair stops at S* = S_min e^{u₀/A} = 0.315 r inside the bridge
		const double     u0    = 14.5;
		const auto       exact = [&](double S) { return -(u0 - A * std::log(S / kSMin)); };
		const Trajectory t     = integrate(m, params(), kSMin, -u0, exact, -1.0, 1e-6 * u0);
		const double     sStar = kSMin * std::exp(u0 / A);
		EXPECT_FALSE(t.ruptured);
		EXPECT_LT(t.sMax, ruptureDistance(kV, 0.0));
		EXPECT_NEAR(t.sMax / sStar, 1.0, 3e-3); // measured 7e-4: 1e-3 m/s of error in u₀/A
	}
}
