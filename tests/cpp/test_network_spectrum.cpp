// The network stability limit (physics.md §7, P16–P18): exact for a pair, and on random networks
// within its error bracket of the limit found by a dense eigen-solution and bisection.
#include "test_support.hpp"
#include "viscbridge/core/timestep/NetworkSpectrum.hpp"
#include "viscbridge/core/timestep/PairMaps.hpp"
#include <Eigen/Dense>
#include <gtest/gtest.h>

using namespace viscbridge;
using vbtest::kPi;

namespace {


Vec6 sphereScale(double m, double r) { return (Vec6() << Vec3::Constant(1 / std::sqrt(m)), Vec3::Constant(1 / std::sqrt(0.4 * m * r * r))).finished(); }

ViscousBlock block(const Vec3& n, double normal, double tangential, double a1, double a2)
{
	ViscousBlock b;
	b.valid      = normal > 0 || tangential > 0;
	b.n          = n;
	b.cn         = normal;
	b.resistance = { tangential, tangential, tangential, tangential };
	b.a1 = a1, b.a2 = a2;
	return b;
}

// The dense D̃ and K̃ of the operator, column by column.
void dense(const NetworkOperator& op, Eigen::MatrixXd& D, Eigen::MatrixXd& K)
{
	const long n = static_cast<long>(op.size());
	D.resize(n, n), K.resize(n, n);
	VecX e(n), Dy, Ky;
	for (long j = 0; j < n; ++j) {
		e.setZero();
		e[j] = 1;
		op.apply(e, Dy, Ky);
		D.col(j) = Dy, K.col(j) = Ky;
	}
}

// h* by bisection on λ_max(h²K̃ + 2hD̃) = 4 (P18).
double bisectedLimit(const NetworkOperator& op)
{
	Eigen::MatrixXd D, K;
	dense(op, D, K);
	auto lambda = [&](double h) { return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h * h * K + 2 * h * D, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff(); };
	double lo = 1e-15, hi = 1.0;
	while (lambda(hi) < 4) hi *= 2;
	for (int i = 0; i < 200; ++i) {
		const double mid = std::sqrt(lo * hi);
		(lambda(mid) < 4 ? lo : hi) = mid;
	}
	return std::sqrt(lo * hi);
}

// n spheres at random positions, bridges between neighbours, random coefficients over decades.
NetworkOperator randomNetwork(std::mt19937& g, int n, bool springs)
{
	NetworkOperator   op;
	std::vector<Vec3> pos;
	std::vector<double> radius;
	for (int i = 0; i < n; ++i) {
		radius.push_back(vbtest::uniform(g, 2e-4, 6e-4));
		pos.push_back(vbtest::randomVec(g, 2e-3));
		op.scale.push_back(sphereScale(2500 * 4.0 / 3.0 * kPi * std::pow(radius.back(), 3), radius.back()));
	}
	for (int i = 0; i < n; ++i)
		for (int j = i + 1; j < n; ++j)
			if ((pos[i] - pos[j]).norm() < 1.6e-3) {
				const Vec3   nrm = (pos[j] - pos[i]).normalized();
				const double c   = vbtest::logUniform(g, 1e-3, 10), ct = 0.05 * c, k = springs ? vbtest::logUniform(g, 1, 1e4) : 0;
				op.pairs.push_back({ i, j, block(nrm, c, ct, radius[i], radius[j]), block(nrm, k, 0.5 * k, radius[i], radius[j]) });
			}
	// a few bridges to a wall (no degrees of freedom on its side)
	for (int i = 0; i < n; i += 5) op.pairs.push_back({ i, -1, block(Vec3::UnitZ(), vbtest::logUniform(g, 1e-3, 10), 0, radius[i], 0), ViscousBlock() });
	return op;
}
} // namespace

// An equal pair with a normal dashpot: h* = 2 m*/C (P12), with a spring P13.
TEST(NetworkSpectrum, PairIsExact)
{
	const double m = 1.3e-6, r = 5e-4, C = 0.9, k = 40;
	for (double spring : { 0.0, k }) {
		NetworkOperator op;
		op.scale = { sphereScale(m, r), sphereScale(m, r) };
		op.pairs = { { 0, 1, block(Vec3::UnitX(), C, 0, r, r), block(Vec3::UnitX(), spring, 0, r, r) } };
		VecX                    mode;
		const StabilityEstimate e = stabilityLimit(op, mode, 1e-10, 50);
		const double            mEff = m / 2, expected = 4 * mEff / (C + std::sqrt(C * C + 4 * mEff * spring));
		EXPECT_TRUE(e.converged);
		EXPECT_NEAR(e.h, expected, 1e-9 * expected);
		EXPECT_LE(e.hSafe, e.h);
	}
	// against a wall: m* = m
	NetworkOperator op;
	op.scale = { sphereScale(m, r) };
	op.pairs = { { 0, -1, block(Vec3::UnitZ(), C, 0, r, 0), ViscousBlock() } };
	VecX mode;
	EXPECT_NEAR(stabilityLimit(op, mode, 1e-10, 50).h, 2 * m / C, 1e-9 * 2 * m / C);
}

// Random networks (with and without springs, tangential terms, walls): the limit lies in
// [hSafe, h] and h is within the tolerance of it.
TEST(NetworkSpectrum, RandomNetworksAreBracketed)
{
	std::mt19937 g(7);
	for (int trial = 0; trial < 12; ++trial) {
		const NetworkOperator op = randomNetwork(g, 12 + trial, trial % 2 == 1);
		VecX                  mode;
		const StabilityEstimate e = stabilityLimit(op, mode, 1e-6, 300);
		const double          truth = bisectedLimit(op);
		ASSERT_TRUE(e.converged) << trial;
		EXPECT_LE(e.hSafe, truth * (1 + 1e-9)) << trial;
		EXPECT_GE(e.h, truth * (1 - 1e-9)) << trial; // a Ritz vector can only err upwards
		EXPECT_NEAR(e.h / truth, 1, 1e-5) << trial;
	}
}

// Warm-started from the previous mode, a slightly changed network needs a product or two.
TEST(NetworkSpectrum, WarmStartConvergesAtOnce)
{
	std::mt19937    g(3);
	NetworkOperator op = randomNetwork(g, 40, false);
	VecX            mode;
	const StabilityEstimate cold = stabilityLimit(op, mode, 1e-3, 300);
	for (auto& p : op.pairs) p.damping.cn *= 1 + 1e-4 * vbtest::uniform(g, -1, 1);
	const StabilityEstimate warm = stabilityLimit(op, mode, 1e-3, 300);
	EXPECT_TRUE(warm.converged);
	EXPECT_LE(warm.iterations, 5);
	EXPECT_GT(cold.iterations, warm.iterations);
	EXPECT_NEAR(warm.h / cold.h, 1, 2e-3);
}

// Warm-started on a mode that is no longer the top one (here: the mode of a pair, beside a separate
// pair 3 % stiffer), the start's residual is small; the iteration must still find the stiffer mode
// within a few updates instead of reporting the lesser one as converged (a limit 3 % too high).
TEST(NetworkSpectrum, WarmStartOnALesserModeFindsTheTopOne)
{
	const double    m = 1.3e-6, r = 5e-4, C = 0.9;
	NetworkOperator op;
	op.scale = { sphereScale(m, r), sphereScale(m, r), sphereScale(m, r), sphereScale(m, r) };
	op.pairs = { { 0, 1, block(Vec3::UnitX(), C, 0, r, r), ViscousBlock() }, { 2, 3, block(Vec3::UnitX(), 1.03 * C, 0, r, r), ViscousBlock() } };
	const double truth = bisectedLimit(op);
	VecX         mode  = VecX::Zero(24);
	mode[0] = 1, mode[6] = -1; // the first pair's relative motion along its normal
	double h = 0;
	for (int update = 0; update < 3; ++update) h = stabilityLimit(op, mode, 1e-3, 30).h;
	EXPECT_NEAR(h / truth, 1, 1e-3);
}

// The maps a pair gives the time step: a dashpot-only bridge of Adams–Perchard at S_min.
TEST(NetworkSpectrum, PairMapsTakeTheBridgeAtItsStiffest)
{
	const double     r = 5e-4, rBar = r / 2, sMin = 1e-3 * rBar;
	BridgeInputs     in;
	in.viscosity = 1, in.rBar = rBar, in.radius1 = in.radius2 = r, in.sMin = sMin, in.mEff = 6.5e-7;
	ModelSelection s;
	s.normal = modelIndex<NormalSlot>("t", "adamsPerchard");
	const PairConstants k  = makePairConstants(s, {}, in, 0);
	const PairNow       at { Vec3::UnitX(), 0.3 * r, r, r, 0, 0, true };
	const PairMaps      m  = pairMaps(k, s, at, true);
	EXPECT_NEAR(m.damping.cn, 6 * kPi * rBar * rBar / sMin, 1e-9 * m.damping.cn); // at S_min, not at 0.3 r
	EXPECT_FALSE(m.stiffness.valid);                                           // no contact, no capillary
	EXPECT_FALSE(pairMaps(k, s, at, false).damping.valid);                     // implicit: the bridge leaves the step
}
