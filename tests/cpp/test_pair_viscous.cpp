// The viscous bridge inside the pair kernel: sign convention (P3), continuity through contact (P6),
// energy bookkeeping (§6), the power balance with moving walls and rigid rotation under slip.
#include "pair_test_support.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace viscbridge;
using namespace vbtest;

namespace {
const double kRBar = kRadius / 2, kMEff = sphereMass(kRadius) / 2, kMu = 1.0;
template <class T> using Bridge = PairModels<AdamsPerchard, T, NoContactDamping>;
template <class T> Bridge<T> bridge(double rBar = kRBar) { return { AdamsPerchard(kMu, rBar), T(kMu, rBar), {} }; }
PairState formed()
{
	PairState st;
	st.bridge = true; // formed at an earlier contact
	return st;
}
} // namespace

// P3: F_v^n = −C^n v_r^n with v_r = V1 − V2.  Approaching (V1 towards body 2): the force on body 1
// points along −n with magnitude C^n(max(S, S_min)) |v_n|; separating: along +n.
TEST(PairViscous, NormalForceSignAndMagnitude)
{
	const PairParams p = referenceParams(kMEff);
	const Vec3       n = Vec3(0, 0.6, 0.8);
	for (double S : { 0.5 * p.sMin, 3 * p.sMin, 0.2 * p.sRup }) {
		const double cn = 6 * kPi * kMu * kRBar * kRBar / std::max(S, p.sMin); // P4 at the clamped gap, P6
		for (double v : { 0.02, -0.02 }) { // v > 0: approaching
			PairState  st = formed();
			PairOutput out;
			const PairInput in = spherePair(Vec3::Zero(), n, kRadius, kRadius, S, 0.5 * v * n, -0.5 * v * n, Vec3::Zero(), Vec3::Zero(), 1e-8);
			ASSERT_TRUE(evaluatePair<false>(bridge<SlipTangential>(), p, st, in, out));
			EXPECT_NEAR(out.cn, cn, 1e-13 * cn);
			EXPECT_NEAR(out.force1.dot(n), -cn * v, 1e-13 * cn * std::abs(v)) << "S=" << S << " v=" << v;
			EXPECT_NEAR((out.force1 + out.force1.dot(n) * -n).norm(), 0.0, 1e-13 * cn * std::abs(v)); // purely normal
		}
	}
}

// Pitois through the kernel: C^n is the model's coefficient at max(S, S_min).
TEST(PairViscous, PitoisCoefficientThroughKernel)
{
	const PairParams p = referenceParams(kMEff);
	const double     V = 0.01 * 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;
	const PairModels<Pitois, NoTangentialViscous, NoContactDamping> m{ Pitois(kMu, kRBar, V), {}, {} };
	for (double S : { 0.5 * p.sMin, 0.1 * kRadius }) {
		PairState  st = formed();
		PairOutput out;
		ASSERT_TRUE(evaluatePair<false>(m, p, st, spherePair(Vec3::Zero(), Vec3::UnitZ(), kRadius, kRadius, S, Vec3(0, 0, 1), Vec3::Zero(),
		                                                     Vec3::Zero(), Vec3::Zero(), 1e-8),
		                         out));
		const double s = std::max(S, p.sMin), x = V / (kPi * kRBar * s * s), b = 1 - 1 / std::sqrt(1 + x); // P5
		EXPECT_NEAR(out.cn, 6 * kPi * kMu * kRBar * kRBar / s * b * b, 1e-12 * out.cn);
	}
}

// P6 / §2: the total normal force on body 1 at fixed approach speed is continuous through contact.
// At S = ±ε (ε < S_min) the viscous part is the same C^n(S_min) v and Hertz adds only kno ε^{3/2}.
TEST(PairViscous, NormalForceContinuousThroughContact)
{
	const PairParams p = referenceParams(kMEff);
	const Vec3       n = Vec3::UnitX();
	const double     w = 0.01;
	const auto       normalForce = [&](double S) {
		PairState       st = formed();
		PairOutput      out;
		const PairInput in = spherePair(Vec3::Zero(), n, kRadius, kRadius, S, w * n, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 1e-8);
		EXPECT_TRUE(evaluatePair<false>(bridge<SlipTangential>(), p, st, in, out));
		return out.force1.dot(n);
	};
	const double eps = 1e-9 * kRadius;
	const double Fv  = 6 * kPi * kMu * kRBar * kRBar / p.sMin * w;
	const double jump = normalForce(-eps) - normalForce(eps);
	EXPECT_NEAR(normalForce(eps), -Fv, 1e-13 * Fv);
	EXPECT_NEAR(jump, -p.contact.kno * std::pow(eps, 1.5), 1e-13 * Fv); // just the Hertz onset
	EXPECT_LT(std::abs(jump), 1e-9 * Fv);
	// And the force is continuous where the clamp releases (S = S_min): 1/S changes by 2e-9 there.
	EXPECT_NEAR(normalForce(p.sMin * (1 + 1e-9)) / normalForce(p.sMin * (1 - 1e-9)), 1.0, 2e-9);
}

// §6: a step's viscous dissipation is the work of its forces while the velocities go from the ones
// the forces used to the ones that follow, known at the next step: with unchanged velocities it is
// C^n v_n² Δt and the tangential model's rates times Δt, reported one step later.
TEST(PairViscous, DissipationOfOneStep)
{
	const PairParams p  = referenceParams(kMEff);
	const double     dt = 3e-8, S = 0.01 * kRadius;
	const Vec3       n  = Vec3(0, 0.6, 0.8);
	const Vec3       v1(0.01, -0.02, 0.03), v2(-0.005, 0, 0.01), w1(5, -3, 1), w2(0, 2, 7);
	PairState        st = formed();
	PairOutput       out;
	const PairInput  in = spherePair(Vec3::Zero(), n, kRadius, kRadius, S, v1, v2, w1, w2, dt);
	ASSERT_TRUE(evaluatePair<true>(bridge<SlipTangential>(), p, st, in, out));
	EXPECT_EQ(out.dissipNormal, 0.0); // nothing done yet: the step's work shows at the next step
	EXPECT_EQ(out.dissipTangential, 0.0);
	ASSERT_TRUE(evaluatePair<true>(bridge<SlipTangential>(), p, st, in, out));
	const double vn = (v1 - v2).dot(n), cn = 6 * kPi * kMu * kRBar * kRBar / S;
	EXPECT_NEAR(out.dissipNormal, cn * vn * vn * dt, 1e-13 * cn * vn * vn * dt);
	const Vec3 u   = (v1 - v2) - vn * n;
	const auto res = SlipTangential(kMu, kRBar).evaluate({ n, u, w1, w2, kRadius, kRadius, S, S });
	EXPECT_GT(res.dissipationSliding, 0.0);
	EXPECT_NEAR(out.dissipTangential, res.dissipationSliding * dt, 1e-13 * res.dissipationSliding * dt);
	EXPECT_EQ(out.dissipRotational, 0.0);
	EXPECT_EQ(out.dissipFriction, 0.0);
	EXPECT_EQ(out.dissipContactDamping, 0.0);
	// Without tracking nothing is filled.
	PairOutput quiet;
	ASSERT_TRUE(evaluatePair<false>(bridge<SlipTangential>(), p, st, in, quiet));
	EXPECT_EQ(quiet.dissipNormal, 0.0);
	EXPECT_EQ(quiet.dissipTangential, 0.0);
}

// Random configurations: kind 0 two spheres, 1 a wall on side 1, 2 a wall on side 2.  A wall's
// reference point (its pos) is anywhere: the kernel places its bridge end from the sphere, n and S.
namespace {
struct Configuration {
	double r1, r2, rBar, S;
	Vec3   n, x1, x2;
};

Configuration randomConfiguration(std::mt19937& g, int kind, double relS)
{
	Configuration c;
	c.r1   = kind == 1 ? 0 : logUniform(g, 1e-4, 1e-3);
	c.r2   = kind == 2 ? 0 : logUniform(g, 1e-4, 1e-3);
	c.rBar = reducedRadius(c.r1, c.r2);
	c.S    = relS >= 0 ? relS * c.rBar : logUniform(g, 1e-5 * c.rBar, 2 * c.rBar);
	c.n    = randomUnit(g);
	const Vec3 sphere = randomVec(g, 1e-2), wallRef = randomVec(g, 1e-2);
	c.x1 = kind == 1 ? wallRef : sphere;
	c.x2 = kind == 0 ? Vec3(sphere + (c.r1 + c.r2 + c.S) * c.n) : kind == 1 ? sphere : wallRef;
	return c;
}

PairParams paramsFor(double rBar)
{
	PairParams p = referenceParams(kMEff);
	p.sMin       = 1e-4 * rBar;
	p.sRup       = 3 * rBar;
	return p;
}
} // namespace

// Power balance of the whole viscous bridge with moving and turning bodies, walls on either side:
// P = F1·v1 + T1·ω1 − F1·v2 + T2·ω2 (centre velocities and the torques the kernel returns, a wall
// being a rigid body) must equal −(dissipNormal + dissipTangential + dissipRotational)/Δt.  It is
// ≤ 0 for slip and goldman; for washino only the balance holds.
namespace {
template <class T> void checkKernelPowerBalance(unsigned seed, bool mustDissipate)
{
	std::mt19937 g(seed);
	const double dt = 1e-8;
	for (int i = 0; i < 3000; ++i) {
		const int            kind = i % 3;
		const Configuration  c    = randomConfiguration(g, kind, -1);
		const BodyKinematics b1   = body(c.x1, c.r1, randomVec(g, 0.1), randomVec(g, 100.0));
		const BodyKinematics b2   = body(c.x2, c.r2, randomVec(g, 0.1), randomVec(g, 100.0));
		PairState            st   = formed();
		PairOutput           out;
		// the second call reports the first step's work; with unchanged velocities that is −P·Δt
		ASSERT_TRUE(evaluatePair<true>(bridge<T>(c.rBar), paramsFor(c.rBar), st, pairInput(c.n, c.S, b1, b2, dt), out));
		ASSERT_TRUE(evaluatePair<true>(bridge<T>(c.rBar), paramsFor(c.rBar), st, pairInput(c.n, c.S, b1, b2, dt), out));
		const double P = out.force1.dot(b1.vel) + out.torque1.dot(b1.angVel) - out.force1.dot(b2.vel) + out.torque2.dot(b2.angVel);
		const double magnitude = out.force1.norm() * (b1.vel.norm() + b2.vel.norm()) + out.torque1.norm() * b1.angVel.norm()
		        + out.torque2.norm() * b2.angVel.norm();
		const double dissipated = (out.dissipNormal + out.dissipTangential + out.dissipRotational) / dt;
		ASSERT_GT(magnitude, 0.0);
		ASSERT_NEAR(-P, dissipated, 1e-10 * magnitude) << "i=" << i << " kind=" << kind;
		if (mustDissipate) {
			ASSERT_LE(P, 1e-12 * magnitude) << "i=" << i << " kind=" << kind;
		}
	}
}
} // namespace

TEST(PairViscous, PowerBalanceSlip) { checkKernelPowerBalance<SlipTangential>(101, true); }
TEST(PairViscous, PowerBalanceGoldman) { checkKernelPowerBalance<GoldmanTangential>(202, true); }
TEST(PairViscous, PowerBalanceWashino) { checkKernelPowerBalance<WashinoTangential>(303, false); }

// §2 slip: a pair in rigid rotation (v_k = ω × (x_k − c), ω_k = ω) feels no viscous force or torque,
// for two spheres and for a sphere against a wall turning with it (the wall's motion enters via V).
TEST(PairViscous, SlipRigidRotationThroughKernel)
{
	std::mt19937 g(77);
	for (int kind = 0; kind < 3; ++kind) {
		for (double rel : { 0.0, 0.01, 0.3 }) {
			for (int i = 0; i < 20; ++i) {
				const Configuration  c = randomConfiguration(g, kind, rel);
				const Vec3           omega = randomVec(g, 100.0), centre = randomVec(g, 1e-2);
				const BodyKinematics b1 = body(c.x1, c.r1, omega.cross(c.x1 - centre), omega);
				const BodyKinematics b2 = body(c.x2, c.r2, omega.cross(c.x2 - centre), omega);
				PairState            st = formed();
				PairOutput           out;
				ASSERT_TRUE(evaluatePair<false>(bridge<SlipTangential>(c.rBar), paramsFor(c.rBar), st, pairInput(c.n, c.S, b1, b2, 1e-8), out));
				// Rounding scale: the largest velocities |ω| |x − c| (|x|, |c| ≤ 1.8e-2) times C_T.
				const double scale = out.ct * omega.norm() * 5e-2;
				ASSERT_GT(out.ct, 0.0);
				EXPECT_LE(out.force1.norm(), 1e-12 * scale) << "kind=" << kind << " S/r̄=" << rel;
				EXPECT_LE(out.torque1.norm() + out.torque2.norm(), 1e-12 * scale * 5e-2) << "kind=" << kind << " S/r̄=" << rel;
			}
		}
	}
	// Contrast: washino in the same motion (two spheres, touching) does feel a force (physics.md §2).
	const Configuration  c = randomConfiguration(g, 0, 0.0);
	const Vec3           omega = Vec3(0, 0, 50).cross(c.n).normalized() * 50; // ⟂ n
	const BodyKinematics b1 = body(c.x1, c.r1, omega.cross(c.x1), omega), b2 = body(c.x2, c.r2, omega.cross(c.x2), omega);
	PairState            st = formed();
	PairOutput           out;
	ASSERT_TRUE(evaluatePair<false>(bridge<WashinoTangential>(c.rBar), paramsFor(c.rBar), st, pairInput(c.n, c.S, b1, b2, 1e-8), out));
	EXPECT_GT(out.force1.norm(), 0.1 * out.ct * omega.norm() * (c.r1 + c.r2));
}

// §6: the dissipation reported for a step is F_prev·(v_prev + v_now)/2·Δt (the leapfrog work of the
// previous step's force), here with the normal relative velocity halved between the two calls.
TEST(PairViscous, DissipationUsesVelocitiesBeforeAndAfter)
{
	const PairParams p  = referenceParams(kMEff);
	const double     dt = 3e-8, S = 0.01 * kRadius;
	const Vec3       n(1, 0, 0), zero = Vec3::Zero();
	PairState        st = formed();
	PairOutput       out;
	const double     w = 0.02; // approach speed, then half of it
	const PairModels<AdamsPerchard, NoTangentialViscous, NoContactDamping> normalOnly { AdamsPerchard(kMu, kRBar), {}, {} };
	ASSERT_TRUE(evaluatePair<true>(normalOnly, p, st,
	                               spherePair(zero, n, kRadius, kRadius, S, Vec3(w, 0, 0), zero, zero, zero, dt), out));
	ASSERT_TRUE(evaluatePair<true>(normalOnly, p, st,
	                               spherePair(zero, n, kRadius, kRadius, S, Vec3(0.5 * w, 0, 0), zero, zero, zero, dt), out));
	const double cn = 6 * kPi * kMu * kRBar * kRBar / S;
	EXPECT_NEAR(out.dissipNormal, cn * w * 0.75 * w * dt, 1e-13 * cn * w * w * dt);
}
