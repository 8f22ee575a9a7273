// Dissipativity of the tangential models (physics.md §2, "P7 is not dissipative").
//
// Power of the tangential bridge force on the pair: body 1 receives force1 and torque1, body 2
// receives −force1 and torque2, so P = force1·(V1 − V2) + torque1·ω1 + torque2·ω2, where the
// tangential part of V1 − V2 is u (the normal part does no work against a tangential force).
// A wall side (radius 0) takes no torque and its motion is already in V2, so its ω counts as 0.
#include "test_support.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/models/tangential/TangentialViscous.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace viscbridge;
using vbtest::kPi;

namespace {

struct PowerCheck {
	double power;     // P
	double magnitude; // |F||u| + |T1||ω1| + |T2||ω2|: the size of the terms that P sums
};

PowerCheck powerOf(const TangentialViscousResult& r, const TangentialKinematics& k)
{
	const Vec3 w1 = k.radius1 > 0 ? k.omega1 : Vec3::Zero();
	const Vec3 w2 = k.radius2 > 0 ? k.omega2 : Vec3::Zero();
	return { r.force1.dot(k.u) + r.torque1.dot(w1) + r.torque2.dot(w2),
		     r.force1.norm() * k.u.norm() + r.torque1.norm() * w1.norm() + r.torque2.norm() * w2.norm() };
}

// One random relative motion (brief: random unit n, u ⟂ n, ω1, ω2, radii incl. a wall, S in
// [1e-5 r̄, 2 r̄], sEff = max(S, S_min)); viscosity and S_min random too.
struct RandomMotion {
	double               mu, rBar;
	TangentialKinematics k;
};

RandomMotion randomMotion(std::mt19937& g, int i)
{
	double r1 = vbtest::logUniform(g, 1e-5, 1e-2), r2 = vbtest::logUniform(g, 1e-5, 1e-2);
	if (i % 4 == 1) r1 = 0; // wall on side 1
	if (i % 4 == 2) r2 = 0; // wall on side 2
	const double rBar = reducedRadius(r1, r2);
	const double S    = vbtest::logUniform(g, 1e-5 * rBar, 2 * rBar);
	const double sMin = vbtest::logUniform(g, 1e-5 * rBar, 1e-2 * rBar);
	const Vec3   n    = vbtest::randomUnit(g);
	const double U    = vbtest::logUniform(g, 1e-4, 10.0); // sliding speed
	const Vec3   u    = U * vbtest::randomPerpendicularUnit(g, n);
	// Surface speeds r ω comparable to U, from 1e-2 to 1e2 times it, in any direction (incl. spin).
	const Vec3 w1 = vbtest::logUniform(g, 1e-2, 1e2) * U / rBar * vbtest::randomUnit(g);
	const Vec3 w2 = vbtest::logUniform(g, 1e-2, 1e2) * U / rBar * vbtest::randomUnit(g);
	return { vbtest::logUniform(g, 1e-3, 1e3), rBar, { n, u, w1, w2, r1, r2, S, std::max(S, sMin) } };
}

template <class Model> void checkDissipativeAndSplit(unsigned seed)
{
	std::mt19937 g(seed);
	for (int i = 0; i < 10000; ++i) {
		const RandomMotion m   = randomMotion(g, i);
		const auto         res = Model(m.mu, m.rBar).evaluate(m.k);
		const PowerCheck   p   = powerOf(res, m.k);
		ASSERT_GT(p.magnitude, 0) << "i=" << i;
		// A wall side never gets a torque from the model.
		if (m.k.radius1 == 0) {
			ASSERT_EQ(res.torque1, Vec3::Zero()) << "i=" << i;
		}
		if (m.k.radius2 == 0) {
			ASSERT_EQ(res.torque2, Vec3::Zero()) << "i=" << i;
		}
		// P ≤ 0 up to the rounding of the sum of its terms.
		ASSERT_LE(p.power, 1e-12 * p.magnitude) << "i=" << i << " S/r̄=" << m.k.S / m.rBar;
		// −P = sliding + rolling, both nonnegative (Cholesky split of a positive semidefinite form).
		ASSERT_NEAR(-p.power, res.dissipationSliding + res.dissipationRolling, 1e-10 * p.magnitude) << "i=" << i;
		ASSERT_GE(res.dissipationSliding, 0.0) << "i=" << i;
		ASSERT_GE(res.dissipationRolling, -1e-12 * p.magnitude) << "i=" << i;
	}
}

} // namespace

TEST(TangentialDissipation, SlipIsDissipativeForRandomMotions) { checkDissipativeAndSplit<SlipTangential>(12345); }

TEST(TangentialDissipation, GoldmanIsDissipativeForRandomMotions) { checkDissipativeAndSplit<GoldmanTangential>(54321); }

// washino's split still adds up to −P, even though the rolling part can be negative.
TEST(TangentialDissipation, WashinoSplitAddsUpToMinusPower)
{
	std::mt19937 g(999);
	for (int i = 0; i < 10000; ++i) {
		const RandomMotion m   = randomMotion(g, i);
		const auto         res = WashinoTangential(m.mu, m.rBar).evaluate(m.k);
		const PowerCheck   p   = powerOf(res, m.k);
		ASSERT_NEAR(-p.power, res.dissipationSliding + res.dissipationRolling, 1e-10 * p.magnitude) << "i=" << i;
	}
}

// physics.md §2: P = −[C_T|u|² + (C_T + C_R) u·s + C_R|s|²].  With s = −α u the bracket is
// |u|² (C_T − (C_T + C_R) α + C_R α²), negative for 1 < α < C_T/C_R: the force does positive work.
TEST(TangentialDissipation, WashinoHasMotionsWithPositivePower)
{
	const double mu = 1.0, r1 = 1e-3, r2 = 1e-3, rBar = 5e-4, S = 1e-3 * rBar, sMin = 1e-5 * rBar;
	const Vec3   n{ 0, 0, 1 }, u{ 0.1, 0, 0 };
	const double L  = std::log(rBar / S);
	const double cT = 6 * kPi * mu * rBar * (8.0 / 15.0 * L + 0.9588); // P8
	const double cR = 6 * kPi * mu * rBar * (2.0 / 15.0 * L + 0.2526); // P9
	const double alpha = 0.5 * (1 + cT / cR);                            // midway between the roots
	const Vec3   s     = -alpha * u;
	// r1 ω1 × n = s with ω1 = (n × s)/r1, because (n × s) × n = s for s ⟂ n; body 2 does not spin.
	const Vec3 w1 = n.cross(s) / r1, w2 = Vec3::Zero();
	const TangentialKinematics k{ n, u, w1, w2, r1, r2, S, std::max(S, sMin) };
	const auto       res = WashinoTangential(mu, rBar).evaluate(k);
	const PowerCheck p   = powerOf(res, k);
	const double expected = -(cT * u.squaredNorm() + (cT + cR) * u.dot(s) + cR * s.squaredNorm());
	EXPECT_GT(expected, 0.0);
	EXPECT_NEAR(p.power, expected, 1e-12 * p.magnitude);
	EXPECT_GT(p.power, 0.05 * p.magnitude); // not a rounding artefact
	EXPECT_LT(res.dissipationRolling, 0.0);
	// The same motion under slip and goldman dissipates.
	EXPECT_LT(powerOf(SlipTangential(mu, rBar).evaluate(k), k).power, 0.0);
	EXPECT_LT(powerOf(GoldmanTangential(mu, rBar).evaluate(k), k).power, 0.0);
}

// ---- free decay of a sphere sliding and spinning next to a fixed wall, at frozen S -------------
// Explicit Euler in velocity (as YADE's leapfrog, §1): m v̇ = F, I ω̇ = T1, the wall is body 2.
namespace {
struct Decay {
	double ke0, keEnd, dissipated; // kinetic energies and ∫(−P) dt
	bool   monotone;               // KE never increased by more than rounding
};

template <class Model> Decay decay(const Model& model, double r, double S, double sMin, Vec3 v, Vec3 w, double dt, int steps)
{
	const double rho = 2500, m = rho * 4.0 / 3.0 * kPi * r * r * r, I = 0.4 * m * r * r;
	const Vec3   n{ 0, 0, 1 }; // sphere below the wall; v ⟂ n stays ⟂ n (the force is tangential)
	const auto   ke = [&](const Vec3& v_, const Vec3& w_) { return 0.5 * m * v_.squaredNorm() + 0.5 * I * w_.squaredNorm(); };
	Decay        d{ ke(v, w), 0, 0, true };
	double       kePrev = d.ke0;
	for (int i = 0; i < steps; ++i) {
		const auto res = model.evaluate({ n, v, w, Vec3::Zero(), r, 0.0, S, std::max(S, sMin) });
		d.dissipated += (res.dissipationSliding + res.dissipationRolling) * dt;
		v += res.force1 / m * dt;
		w += res.torque1 / I * dt;
		const double k = ke(v, w);
		if (k > kePrev * (1 + 1e-14)) d.monotone = false;
		kePrev = k;
	}
	d.keEnd = kePrev;
	return d;
}
} // namespace

// physics.md §2 acceptance: KE never increases and KE + ∫(−P)dt = KE₀ to O(Δt).  The Euler defect
// per step is Δt²/2 (|F|²/m + |T|²/I) > 0, so the balance error is first order: it halves with Δt.
// The end state is known exactly, because the force and the torque change v and ω in fixed ratio
// (explicit Euler keeps that invariant too), and the spin about n is never touched:
//   goldman (C_T C_W > C_R² at this gap): all tangential motion stops, KE_end = ½ I (ω₀·n)²;
//   slip: s̃ − β u is conserved (s̃ = a ω × n, a = r + S/2, β = m a²/I) and the motion ends rolling
//   without slip, u_f = (β u₀ − s̃₀)/(1 + β) = −s̃_f, KE_end = ½ m |u_f|² + ½ I |u_f|²/a² + ½ I (ω₀·n)².
TEST(TangentialDissipation, SlipAndGoldmanFreeDecayLoseEnergyAndBalanceIt)
{
	const double r = 1e-3, mu = 0.1, S = 1e-3 * r, sMin = 1e-4 * r;
	const double cT  = 6 * kPi * mu * r * (8.0 / 15.0 * std::log(1e3) + 0.9588);
	const double m   = 2500 * 4.0 / 3.0 * kPi * r * r * r, I = 0.4 * m * r * r;
	const double tau = m / cT; // translational decay time (≈ 1.2 ms); slowest goldman mode ≈ 1.1 τ
	const Vec3   n{ 0, 0, 1 };
	std::mt19937 g(4);
	for (int trial = 0; trial < 3; ++trial) {
		const Vec3   v{ vbtest::uniform(g, -0.1, 0.1), vbtest::uniform(g, -0.1, 0.1), 0 };
		const Vec3   w = vbtest::randomVec(g, 0.1 / r);
		const double keSpin = 0.5 * I * w.dot(n) * w.dot(n);
		const double a = r + S / 2, beta = m * a * a / I;
		const Vec3   uf = (beta * v - (a * w).cross(n)) / (1 + beta);
		const double keRolling = 0.5 * m * uf.squaredNorm() + 0.5 * I * uf.squaredNorm() / (a * a) + keSpin;
		const auto check = [&](const auto& model, const char* name, double keEndExpected) {
			const Decay coarse = decay(model, r, S, sMin, v, w, tau / 1000, 20 * 1000);
			const Decay fine   = decay(model, r, S, sMin, v, w, tau / 2000, 20 * 2000);
			EXPECT_TRUE(coarse.monotone) << name;
			EXPECT_TRUE(fine.monotone) << name;
			EXPECT_NEAR(coarse.keEnd, keEndExpected, 1e-10 * coarse.ke0) << name;
			EXPECT_GT(coarse.dissipated, 0.01 * coarse.ke0) << name;
			const double errCoarse = coarse.keEnd + coarse.dissipated - coarse.ke0;
			const double errFine   = fine.keEnd + fine.dissipated - fine.ke0;
			EXPECT_GT(errCoarse, 0.0) << name;
			EXPECT_LT(errCoarse, 5e-3 * coarse.ke0) << name;
			EXPECT_NEAR(errCoarse / errFine, 2.0, 0.1) << name; // first order in Δt
		};
		check(SlipTangential(mu, r), "slip", keRolling);
		check(GoldmanTangential(mu, r), "goldman", keSpin);
	}
}

// physics.md §2: under washino a sphere that starts sliding without spin next to a wall ends with
// more kinetic energy, ×1.089 at S = 1e-3 r.  Closed form: u̇ = F/m and ṡ = (r²/I) F = 2.5 F/m
// (s = r ω × n), so s − 2.5 u is conserved (also by explicit Euler, exactly); the motion stops
// when C_T u + C_R s = 0, i.e. u_f = 2.5 u₀/(2.5 + q), s_f = −q u_f with q = C_T/C_R, and
// KE_f/KE₀ = (u_f² + 0.4 s_f²)/u₀².
TEST(TangentialDissipation, WashinoSlidingSphereGainsKineticEnergy)
{
	const double r = 1e-3, mu = 0.1, S = 1e-3 * r, sMin = 1e-4 * r;
	const double L  = std::log(1e3);
	const double cT = 6 * kPi * mu * r * (8.0 / 15.0 * L + 0.9588), cR = 6 * kPi * mu * r * (2.0 / 15.0 * L + 0.2526);
	const double q = cT / cR, uf = 2.5 / (2.5 + q);
	const double gain = uf * uf * (1 + 0.4 * q * q);
	EXPECT_NEAR(gain, 1.089, 5e-4); // the number quoted in physics.md
	const double m = 2500 * 4.0 / 3.0 * kPi * r * r * r, tau = m / cT;
	const Decay  d = decay(WashinoTangential(mu, r), r, S, sMin, Vec3(0.05, 0, 0), Vec3::Zero(), tau / 1000, 20 * 1000);
	EXPECT_FALSE(d.monotone);
	EXPECT_NEAR(d.keEnd / d.ke0, gain, 1e-9); // converged: the residual decays as e^{−20(1 + 2.5/q)}
	// The washino "dissipation" over the run is negative: energy was injected.
	EXPECT_LT(d.dissipated, 0.0);
}
