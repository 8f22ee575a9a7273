// Tangential viscous models (physics.md §2): force and torque formulas, the wall side, rigid
// rotation and the coefficient floors.  Dissipation is in test_tangential_dissipation.cpp.
#include "test_support.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/models/tangential/TangentialViscous.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace viscbridge;
using vbtest::kPi;

namespace {
// A fixed, generic configuration: n = e_z, u ⟂ n, both spheres spinning about all three axes,
// S below S_min so that the arms use S and the coefficients use S_min (P6).
struct Config {
	double mu = 0.8, r1 = 1e-3, r2 = 2e-3, S = 2e-6, sMin = 5e-6;
	Vec3   n{ 0, 0, 1 }, u{ 0.01, -0.02, 0 }, w1{ 3, -1, 5 }, w2{ -2, 4, 1 };
	double rBar() const { return r1 * r2 / (r1 + r2); } // §1, by hand
	double sEff() const { return std::max(S, sMin); }
	TangentialKinematics kin() const { return { n, u, w1, w2, r1, r2, S, sEff() }; }
	double k() const { return 6 * kPi * mu * rBar(); }
	double L() const { return std::log(rBar() / sEff()); }
	double cT() const { return k() * (8.0 / 15.0 * L() + 0.9588); } // P8
	double cR() const { return k() * (2.0 / 15.0 * L() + 0.2526); } // P9
	double cW() const { return k() * (8.0 / 15.0 * L() + 0.5089); } // C_W
};

void expectVecNear(const Vec3& a, const Vec3& b, double tol, const char* what)
{
	EXPECT_LE((a - b).norm(), tol) << what << ": got " << a.transpose() << ", expected " << b.transpose();
}
} // namespace

// P7: F = −(C_T u + C_R s), s = (r1 ω1 + r2 ω2) × n, torques r_k n × F.
TEST(TangentialViscous, WashinoFormula)
{
	const Config  c;
	const auto   res = WashinoTangential(c.mu, c.rBar()).evaluate(c.kin());
	const Vec3   s   = (c.r1 * c.w1 + c.r2 * c.w2).cross(c.n);
	const Vec3   F   = -(c.cT() * c.u + c.cR() * s);
	const double tol = 1e-13 * F.norm();
	EXPECT_NEAR(res.ct, c.cT(), 1e-13 * c.cT());
	EXPECT_NEAR(res.cr, c.cR(), 1e-13 * c.cR());
	expectVecNear(res.force1, F, tol, "force1");
	expectVecNear(res.torque1, c.r1 * c.n.cross(F), c.r1 * tol, "torque1");
	expectVecNear(res.torque2, c.r2 * c.n.cross(F), c.r2 * tol, "torque2");
}

// slip (§2): F = −C_T (u + s̃), s̃ from the mid-gap arms r_k + S/2 (actual S, not S_eff), torques
// (r_k + S/2) n × F, no coupling coefficient, all dissipation is "sliding": C_T |u + s̃|².
TEST(TangentialViscous, SlipFormula)
{
	const Config  c;
	const auto   res = SlipTangential(c.mu, c.rBar()).evaluate(c.kin());
	const double a1 = c.r1 + c.S / 2, a2 = c.r2 + c.S / 2;
	const Vec3   slip = c.u + (a1 * c.w1 + a2 * c.w2).cross(c.n);
	const Vec3   F    = -c.cT() * slip;
	const double tol  = 1e-13 * F.norm();
	EXPECT_NEAR(res.ct, c.cT(), 1e-13 * c.cT());
	EXPECT_EQ(res.cr, 0.0);
	expectVecNear(res.force1, F, tol, "force1");
	expectVecNear(res.torque1, a1 * c.n.cross(F), a1 * tol, "torque1");
	expectVecNear(res.torque2, a2 * c.n.cross(F), a2 * tol, "torque2");
	EXPECT_NEAR(res.dissipationSliding, c.cT() * slip.squaredNorm(), 1e-13 * c.cT() * slip.squaredNorm());
	EXPECT_EQ(res.dissipationRolling, 0.0);
}

// goldman (§2): F = −(C_T u + C_R s); torques r_k n × F_s with F_s = −(C_R u + C_W s).
TEST(TangentialViscous, GoldmanFormula)
{
	const Config  c;
	const auto   res = GoldmanTangential(c.mu, c.rBar()).evaluate(c.kin());
	const Vec3   s   = (c.r1 * c.w1 + c.r2 * c.w2).cross(c.n);
	const Vec3   F   = -(c.cT() * c.u + c.cR() * s);
	const Vec3   Fs  = -(c.cR() * c.u + c.cW() * s);
	const double tol = 1e-13 * (F.norm() + Fs.norm());
	expectVecNear(res.force1, F, tol, "force1");
	expectVecNear(res.torque1, c.r1 * c.n.cross(Fs), c.r1 * tol, "torque1");
	expectVecNear(res.torque2, c.r2 * c.n.cross(Fs), c.r2 * tol, "torque2");
	// The torques are not r_k n × F: that is what distinguishes goldman from washino here.
	EXPECT_GT((res.torque1 - c.r1 * c.n.cross(F)).norm(), 1e-3 * res.torque1.norm());
}

// A side that is not a sphere (radius 0) has arm 0: its angular velocity is ignored (it enters
// through V in the pair kernel) and it receives no torque from the model.
TEST(TangentialViscous, WallSideHasNoArm)
{
	Config c;
	c.r2 = 0;
	const double rBar = c.r1; // §1: r̄ = r_sphere against a wall
	const Vec3   s    = (c.r1 * c.w1).cross(c.n);
	TangentialKinematics k = c.kin(), kStill = c.kin();
	kStill.omega2 = Vec3::Zero();
	const auto w  = WashinoTangential(c.mu, rBar).evaluate(k);
	const auto w0 = WashinoTangential(c.mu, rBar).evaluate(kStill);
	EXPECT_EQ(w.force1, w0.force1);
	EXPECT_EQ(w.torque2, Vec3::Zero());
	const double L  = std::log(rBar / c.sEff());
	const double cT = 6 * kPi * c.mu * rBar * (8.0 / 15.0 * L + 0.9588), cR = 6 * kPi * c.mu * rBar * (2.0 / 15.0 * L + 0.2526);
	expectVecNear(w.force1, -(cT * c.u + cR * s), 1e-13 * w.force1.norm(), "washino wall force1");
	const auto sl = SlipTangential(c.mu, rBar).evaluate(k);
	EXPECT_EQ(sl.torque2, Vec3::Zero());
	expectVecNear(sl.force1, -cT * (c.u + ((c.r1 + c.S / 2) * c.w1).cross(c.n)), 1e-13 * sl.force1.norm(), "slip wall force1");
	EXPECT_EQ(GoldmanTangential(c.mu, rBar).evaluate(k).torque2, Vec3::Zero());
}

// §2: with slip, a pair in rigid rotation (v_k = ω × (x_k − c), any centre c) feels no force: the
// mid-gap points of both surfaces move together.  Checked in overlap, touching and open.
TEST(TangentialViscous, SlipRigidRotationOfSpherePairGivesNoForce)
{
	std::mt19937 g(7);
	for (double rel : { -1e-3, 0.0, 1e-4, 0.05, 0.5 }) {
		for (int i = 0; i < 50; ++i) {
			const double r1 = vbtest::logUniform(g, 1e-4, 1e-2), r2 = vbtest::logUniform(g, 1e-4, 1e-2);
			const double rBar = reducedRadius(r1, r2), S = rel * rBar, sMin = 1e-4 * rBar;
			const Vec3   n = vbtest::randomUnit(g), omega = vbtest::randomVec(g, 100.0), centre = vbtest::randomVec(g, 1e-2);
			const Vec3   x1 = vbtest::randomVec(g, 1e-2), x2 = x1 + (r1 + r2 + S) * n;
			const Vec3   vr = omega.cross(x1 - centre) - omega.cross(x2 - centre);
			const Vec3   u  = vr - vr.dot(n) * n;
			const auto   res = SlipTangential(1.0, rBar).evaluate({ n, u, omega, omega, r1, r2, S, std::max(S, sMin) });
			// u + s̃ cancels to rounding of its largest terms, the velocities ω × (x_k − c).
			const double scale = res.ct * omega.norm() * ((x1 - centre).norm() + (x2 - centre).norm() + r1 + r2);
			ASSERT_GT(scale, 0);
			ASSERT_LE(res.force1.norm(), 1e-12 * scale) << "S/r̄=" << rel << " i=" << i;
			ASSERT_LE(res.torque1.norm() + res.torque2.norm(), 1e-12 * scale * (r1 + r2 + S)) << "S/r̄=" << rel << " i=" << i;
			ASSERT_LE(res.dissipationSliding, 1e-24 * scale * scale / res.ct);
		}
	}
}

// The same for a sphere against a wall turning with it: the wall's bridge end is the mid-gap
// point x1 + (r1 + S/2) n, moving with the wall's rigid velocity; the wall side has radius 0.
TEST(TangentialViscous, SlipRigidRotationAgainstWallGivesNoForce)
{
	std::mt19937 g(8);
	for (double rel : { 0.0, 1e-4, 0.05, 0.5 }) {
		for (int i = 0; i < 50; ++i) {
			const double r1 = vbtest::logUniform(g, 1e-4, 1e-2), S = rel * r1;
			const Vec3   n = vbtest::randomUnit(g), omega = vbtest::randomVec(g, 100.0), centre = vbtest::randomVec(g, 1e-2);
			const Vec3   x1 = vbtest::randomVec(g, 1e-2), anchor = x1 + (r1 + S / 2) * n;
			const Vec3   vr = omega.cross(x1 - centre) - omega.cross(anchor - centre);
			const Vec3   u  = vr - vr.dot(n) * n;
			const auto   res = SlipTangential(1.0, r1).evaluate({ n, u, omega, omega, r1, 0.0, S, std::max(S, 1e-4 * r1) });
			const double scale = res.ct * omega.norm() * ((x1 - centre).norm() + (anchor - centre).norm() + r1);
			ASSERT_LE(res.force1.norm(), 1e-12 * scale) << "S/r=" << rel << " i=" << i;
		}
	}
}

// physics.md §2: under P7 (washino) the same rigid rotation gives a spurious force
// F = (C_T (r1 + r2 + S) − C_R (r1 + r2)) ω × n (u = −(r1+r2+S) ω×n, s = (r1+r2) ω×n), for ω ⟂ n.
TEST(TangentialViscous, WashinoRigidRotationGivesSpuriousForce)
{
	const double r1 = 1e-3, r2 = 1e-3, S = 0.0, sMin = 1e-6, rBar = 5e-4;
	const Vec3   n{ 0, 0, 1 }, omega{ 10, 0, 0 };
	const Vec3   u   = -(r1 + r2 + S) * omega.cross(n);
	const auto   res = WashinoTangential(1.0, rBar).evaluate({ n, u, omega, omega, r1, r2, S, sMin });
	const Vec3   expected = (res.ct * (r1 + r2 + S) - res.cr * (r1 + r2)) * omega.cross(n);
	EXPECT_NEAR((res.force1 - expected).norm(), 0.0, 1e-13 * expected.norm());
	EXPECT_GT(res.force1.norm(), 0.5 * res.ct * (r1 + r2) * omega.norm()); // C_T ≈ 4 C_R: not small
}

// slip: C_T of P8 changes sign at S = 6.036 r̄; the floor keeps the model dissipative beyond it.
TEST(TangentialViscous, SlipCoefficientFloorBeyondSixRadii)
{
	const double rBar = 1e-3;
	const Vec3   n{ 0, 0, 1 }, u{ 0.1, 0, 0 }, w{ 0, 5, 0 };
	const auto   inside = SlipTangential(1.0, rBar).evaluate({ n, u, w, w, 2e-3, 2e-3, 6.0 * rBar, 6.0 * rBar });
	EXPECT_GT(inside.ct, 0.0);
	const auto beyond = SlipTangential(1.0, rBar).evaluate({ n, u, w, w, 2e-3, 2e-3, 7.0 * rBar, 7.0 * rBar });
	EXPECT_EQ(beyond.ct, 0.0);
	EXPECT_EQ(beyond.force1, Vec3::Zero());
	EXPECT_EQ(beyond.dissipationSliding, 0.0);
}

// goldman: where C_T C_W < C_R² (S > 2.42 r̄) the coupling is limited to √(C_T C_W); beyond
// S = 2.597 r̄ C_W < 0 is floored at 0, so the coupling vanishes too.
TEST(TangentialViscous, GoldmanCouplingLimitBeyondDissipativeRange)
{
	const double rBar = 1e-3, mu = 1.0, k = 6 * kPi * mu * rBar;
	const Vec3   n{ 0, 0, 1 }, u{ 0.1, 0, 0 }, w{ 0, 5, 0 };
	{
		const double S  = 2.5 * rBar, L = std::log(1 / 2.5);
		const double cT = k * (8.0 / 15.0 * L + 0.9588), cR = k * (2.0 / 15.0 * L + 0.2526), cW = k * (8.0 / 15.0 * L + 0.5089);
		ASSERT_GT(cR * cR, cT * cW); // the unlimited coupling would be non-dissipative here
		const auto res = GoldmanTangential(mu, rBar).evaluate({ n, u, w, w, 2e-3, 2e-3, S, S });
		EXPECT_NEAR(res.cr, std::sqrt(cT * cW), 1e-13 * cR);
		EXPECT_NEAR(res.dissipationRolling, 0.0, 1e-15 * res.dissipationSliding); // determinant 0
	}
	{
		const auto res = GoldmanTangential(mu, rBar).evaluate({ n, u, w, w, 2e-3, 2e-3, 3.0 * rBar, 3.0 * rBar });
		EXPECT_EQ(res.cr, 0.0);
		EXPECT_EQ(res.torque1, Vec3::Zero());
		EXPECT_GT(res.ct, 0.0);
	}
}
