// The implicit solver's linear algebra without YADE (physics.md §4, P15): one bridge's damping
// matrix against its resistance map, the block Cholesky factorisation against a dense one, and the
// assembled system against its matrix-free product and its solution.
#include "test_support.hpp"
#include "viscbridge/core/linalg/CholmodFactor.hpp"
#include "viscbridge/core/linalg/BridgeDampingMatrix.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include "viscbridge/core/linalg/LaggedPreconditioner.hpp"
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <array>
#include <gtest/gtest.h>
#include <limits>
#include <random>

using namespace viscbridge;
using namespace vbtest;

namespace {
using Mat12 = Eigen::Matrix<double, 12, 12>;

// A bridge with stiff normal damping and a symmetric positive definite tangential resistance, as
// the dissipative models give (Cⁿ/C_T ≈ 200 at S_min).
ViscousBlock randomBridge(std::mt19937& g, bool wallOnSide1 = false)
{
	ViscousBlock b;
	b.valid  = true;
	b.n      = randomUnit(g);
	b.cn     = 200 * uniform(g, 0.5, 2);
	const double m11 = uniform(g, 0.5, 2), m22 = uniform(g, 0.5, 2), m12 = uniform(g, -0.5, 0.5);
	b.resistance = { m11, m12, m12, m22 };
	b.a1     = wallOnSide1 ? 0 : uniform(g, 0.5, 1.5);
	b.a2     = uniform(g, 0.5, 1.5);
	if (wallOnSide1) b.r1 = randomVec(g, 2.0);
	return b;
}

// The 12×12 matrix of the resistance map, column by column from unit velocities.
Mat12 byUnitVelocities(const ViscousBlock& b)
{
	Mat12 D;
	for (int j = 0; j < 12; ++j) {
		Eigen::Matrix<double, 12, 1> q = Eigen::Matrix<double, 12, 1>::Zero();
		q[j]                           = 1;
		const BridgeResistance R       = bridgeResistance(b, q.segment<3>(0), q.segment<3>(3), q.segment<3>(6), q.segment<3>(9), Vec3::Zero());
		D.col(j) << R.force1, R.torque1, R.force2, R.torque2;
	}
	return D;
}

Mat12 assembled(const BridgeDampingMatrix& D)
{
	Mat12 m;
	m << D.block[0][0], D.block[0][1], D.block[1][0], D.block[1][1];
	return m;
}

// A random symmetric positive definite block matrix over n bodies coupled along a random graph.
BlockMatrix6 randomBlockMatrix(std::mt19937& g, int n, int couplings)
{
	BlockMatrix6 A;
	A.diagonal.assign(n, Mat6::Zero());
	for (int c = 0; c < couplings; ++c) {
		int i = static_cast<int>(uniform(g, 0, n)), j = static_cast<int>(uniform(g, 0, n));
		if (i == j || std::find(A.pairs.begin(), A.pairs.end(), std::make_pair(std::min(i, j), std::max(i, j))) != A.pairs.end()) continue;
		// a 12×12 positive semi-definite coupling GᵀG spread over the two bodies
		const Eigen::Matrix<double, 12, 12> G = Eigen::Matrix<double, 12, 12>::Random(), K = G.transpose() * G;
		const auto [lo, hi] = std::minmax(i, j);
		A.diagonal[lo] += K.topLeftCorner<6, 6>();
		A.diagonal[hi] += K.bottomRightCorner<6, 6>();
		A.pairs.emplace_back(lo, hi);
		A.upper.push_back(K.topRightCorner<6, 6>());
	}
	for (auto& d : A.diagonal)
		d += 0.1 * Mat6::Identity(); // the mass: positive definite
	return A;
}

// n bodies coupled as a chain (each to the next) or as a complete graph (each to every other), by
// −1 blocks on a diagonal that keeps the matrix positive definite.
BlockMatrix6 chainOrCompleteGraph(int n, bool complete)
{
	BlockMatrix6 A;
	A.diagonal.assign(n, (complete ? 2.0 * n : 4.0) * Mat6::Identity());
	for (int i = 0; i < n; ++i)
		for (int j = i + 1; j < (complete ? n : std::min(i + 2, n)); ++j) {
			A.pairs.emplace_back(i, j);
			A.upper.push_back(-Mat6::Identity());
		}
	return A;
}

Eigen::MatrixXd dense(const BlockMatrix6& A)
{
	Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 * A.size(), 6 * A.size());
	for (int i = 0; i < A.size(); ++i)
		M.block<6, 6>(6 * i, 6 * i) = A.diagonal[i];
	for (size_t p = 0; p < A.pairs.size(); ++p) {
		M.block<6, 6>(6 * A.pairs[p].first, 6 * A.pairs[p].second) = A.upper[p];
		M.block<6, 6>(6 * A.pairs[p].second, 6 * A.pairs[p].first) = A.upper[p].transpose();
	}
	return M;
}
} // namespace

// The assembled blocks are the resistance map itself (same forces for any velocities), for two
// spheres (the reduced form of sphereBridgeDampingMatrix) and for a moving wall whose anchor is off
// its centre (the general form).
TEST(ImplicitLinearAlgebra, BridgeMatrixIsTheResistanceMap)
{
	std::mt19937 g(11);
	for (int trial = 0; trial < 20; ++trial)
		for (bool wall : { false, true }) {
			ViscousBlock b = randomBridge(g, wall);
			b.resistance.m21 += 0.3; // not symmetric: the blocks must still follow the map term by term
			const Mat12 expected = byUnitVelocities(b), got = assembled(bridgeDampingMatrix(b));
			EXPECT_LE((got - expected).norm(), 1e-13 * expected.norm()) << "wall " << wall;
			EXPECT_EQ(isAnchored(b), wall);
			if (wall) continue;
			// two spheres: the map without the anchor terms is the same map
			const Vec3 v1 = randomVec(g, 1), w1 = randomVec(g, 1), v2 = randomVec(g, 1), w2 = randomVec(g, 1), shift = randomVec(g, 0.1);
			const BridgeResistance full = bridgeResistance<true>(b, v1, w1, v2, w2, shift), lean = bridgeResistance<false>(b, v1, w1, v2, w2, shift);
			EXPECT_LE((full.force1 - lean.force1).norm() + (full.torque1 - lean.torque1).norm() + (full.torque2 - lean.torque2).norm(), 1e-13 * full.force1.norm());
		}
}

// A dissipative bridge's matrix is symmetric positive semi-definite, with the rigid translation in
// its null space (no force without relative motion).
TEST(ImplicitLinearAlgebra, DissipativeBridgeMatrixIsSymmetricSemiDefinite)
{
	std::mt19937 g(12);
	for (int trial = 0; trial < 20; ++trial) {
		const Mat12 D = assembled(bridgeDampingMatrix(randomBridge(g)));
		EXPECT_LE((D - D.transpose()).norm(), 1e-13 * D.norm());
		const Eigen::SelfAdjointEigenSolver<Mat12> eig(D);
		EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * D.norm());
		Eigen::Matrix<double, 12, 1> translation;
		translation << randomVec(g, 1.0), Vec3::Zero(), Vec3::Zero(), Vec3::Zero();
		translation.segment<3>(6) = translation.head<3>();
		EXPECT_LE((D * translation).norm(), 1e-13 * D.norm());
	}
}

// The factorisation solves the system as exactly as a dense Cholesky does.
TEST(ImplicitLinearAlgebra, CholmodFactorSolvesLikeADenseFactorisation)
{
	std::mt19937 g(13);
	for (int n : { 1, 2, 7, 40, 120 }) {
		const BlockMatrix6 A = randomBlockMatrix(g, n, 3 * n);
		CholmodFactor      chol;
		chol.analyse(A.size(), A.pairs);
		ASSERT_TRUE(chol.factorise(A)) << n;
		const VecXd b = VecXd::Random(6 * n);
		VecXd       x, Ax;
		chol.solve(b, x);
		A.multiply(x, Ax);
		EXPECT_LE((Ax - b).norm(), 1e-11 * b.norm()) << n;
		const VecXd reference = dense(A).llt().solve(b);
		EXPECT_LE((x - reference).norm(), 1e-9 * reference.norm()) << n;
	}
}

// The same pattern with new numbers is refactorised without a new analysis, and a coupling block
// whose entries happen to be zero at the analysis (an axis-aligned bridge) may fill in later.
TEST(ImplicitLinearAlgebra, CholmodFactorRefactorisesTheAnalysedPattern)
{
	std::mt19937 g(14);
	BlockMatrix6 A = randomBlockMatrix(g, 30, 80);
	const Mat6   kept = A.upper[3];
	A.upper[3].setZero();
	CholmodFactor chol;
	chol.analyse(A.size(), A.pairs);
	ASSERT_TRUE(chol.factorise(A));
	for (auto& u : A.upper)
		u *= 0.5;
	A.upper[3] = 0.5 * kept;
	ASSERT_TRUE(chol.factorise(A));
	const VecXd b = VecXd::Random(6 * A.size());
	VecXd       x, Ax;
	chol.solve(b, x);
	A.multiply(x, Ax);
	EXPECT_LE((Ax - b).norm(), 1e-11 * b.norm());
}

// A sparse factor (a chain) is simplicial, a dense one (every body coupled to every other)
// supernodal; each solves exactly and refuses a matrix that is not positive definite (a simplicial
// LDLᵀ would factorise it).
TEST(ImplicitLinearAlgebra, CholmodFactorChoosesItsKindByDensity)
{
	for (const bool complete : { false, true }) {
		const int    n = 40;
		BlockMatrix6 A = chainOrCompleteGraph(n, complete);
		CholmodFactor chol;
		chol.analyse(n, A.pairs);
		ASSERT_TRUE(chol.factorise(A)) << complete;
		EXPECT_EQ(chol.supernodal(), complete);
		const VecXd b = VecXd::Random(6 * n);
		VecXd       x, Ax;
		chol.solve(b, x);
		A.multiply(x, Ax);
		EXPECT_LE((Ax - b).norm(), 1e-11 * b.norm()) << complete;
		A.diagonal[n / 2](3, 3) = -1;
		EXPECT_FALSE(chol.factorise(A)) << complete;
	}
}

// A chain of bodies has no fill (each eliminated body couples only its two neighbours), and a
// matrix that is not positive definite is refused instead of factorised.
TEST(ImplicitLinearAlgebra, CholmodFactorFillAndRefusal)
{
	BlockMatrix6 chain;
	const int    n = 50;
	chain.diagonal.assign(n, 4 * Mat6::Identity());
	for (int i = 0; i + 1 < n; ++i) {
		chain.pairs.emplace_back(i, i + 1);
		chain.upper.push_back(-Mat6::Identity());
	}
	CholmodFactor chol;
	chol.analyse(n, chain.pairs);
	ASSERT_TRUE(chol.factorise(chain));
	EXPECT_EQ(chol.offDiagonalBlocks(), static_cast<size_t>(n - 1));
	EXPECT_GT(chol.factorisationWork(), 0);
	ASSERT_FALSE(chol.supernodal()); // a chain's factor is sparse: its sweeps are timed as simplicial ones
	EXPECT_NEAR(chol.solveWork(), CholmodFactor::kSimplicialSweepTime * 4.0 * (21 * n + 36 * (n - 1)) / 72, 1e-9);
	chain.diagonal[n / 2](3, 3) = -1;
	EXPECT_FALSE(chol.factorise(chain));
	EXPECT_FALSE(chol.factorised());
	// no free body at all (a floor of fixed spheres bridged among themselves): nothing to factorise
	CholmodFactor none;
	none.analyse(0, {});
	EXPECT_TRUE(none.factorise(BlockMatrix6 {}));
	VecXd x;
	none.solve(VecXd(), x);
	EXPECT_EQ(x.size(), 0);
}

namespace {
// A small network: a cluster of spheres with random bridges, one wall (prescribed), one sphere
// with its z translation blocked, and one clump-like body with a full inertia tensor and its y
// rotation blocked (its tensor couples the blocked rotation to the free ones).
ImplicitViscousSystem randomSystem(std::mt19937& g, int spheres, double dt)
{
	std::vector<SystemBody> bodies(spheres + 1);
	for (int i = 0; i < spheres; ++i) {
		bodies[i].mass    = uniform(g, 0.5, 2);
		bodies[i].inertia = 0.1 * bodies[i].mass * Mat3::Identity();
		bodies[i].vel     = randomVec(g, 1.0);
		bodies[i].angVel  = randomVec(g, 1.0);
		bodies[i].force   = randomVec(g, 1.0);
		bodies[i].torque  = randomVec(g, 0.1);
		bodies[i].free.fill(true);
	}
	bodies[1].free[2]    = false; // a blocked DOF keeps its velocity
	const Mat3 turn      = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
	bodies[2].inertia    = turn * Vec3(0.05, 0.2, 0.3).asDiagonal() * turn.transpose();
	bodies[2].free[4]    = false;
	bodies[spheres].vel  = Vec3(0.3, 0, 0); // the wall, moving
	std::vector<SystemBridge> bridges;
	for (int i = 0; i < spheres; ++i)
		for (int j = i + 1; j < spheres; ++j)
			if (uniform(g, 0, 1) < 3.0 / spheres) bridges.push_back({ i, j, randomBridge(g), Vec3::Zero() });
	for (int i = 0; i < spheres; i += 4) {
		ViscousBlock w = randomBridge(g, true);
		bridges.push_back({ spheres, i, w, Vec3::Zero() });
	}
	return ImplicitViscousSystem(std::move(bodies), std::move(bridges), dt);
}

// CG on `system` from its current velocities, preconditioned by the factor of `factorised`; it must
// converge without the direct fallback.
SolveReport solvedByCG(const ImplicitViscousSystem& factorised, const ImplicitViscousSystem& system, double tolerance, int maxIterations, VecXd& x)
{
	LaggedCholesky pre;
	EXPECT_TRUE(pre.refresh(factorised, false));
	x                     = system.currentVelocities();
	const SolveReport rep = system.solve(x, tolerance, maxIterations, &pre);
	EXPECT_TRUE(rep.converged);
	EXPECT_FALSE(rep.direct);
	return rep;
}
} // namespace

// The factor's memory is known from the analysis alone, before it is taken (what the solver's
// preconditioner='auto' weighs): a chain's simplicial factor holds its 21n + 36(n−1) entries with a row
// index each; a complete graph's supernodal factor at least the dense lower triangle.  Factorising
// does not change it.
TEST(ImplicitLinearAlgebra, CholmodFactorKnowsItsSizeBeforeFactorising)
{
	for (const bool complete : { false, true }) {
		const int          n = 40;
		const BlockMatrix6 A = chainOrCompleteGraph(n, complete);
		CholmodFactor chol;
		EXPECT_EQ(chol.factorBytes(), 0u);
		chol.analyse(n, A.pairs);
		const size_t analysed = chol.factorBytes();
		if (complete) EXPECT_GE(analysed, sizeof(double) * (6 * n) * (6 * n + 1) / 2);
		else EXPECT_EQ(analysed, (sizeof(double) + sizeof(int)) * (21 * n + 36 * (n - 1)));
		ASSERT_TRUE(chol.factorise(A));
		EXPECT_EQ(chol.factorBytes(), analysed) << complete;
	}
}

// A small factor's calls run OpenBLAS on one thread, whatever the process set before: its pool's
// workers, spinning after each call, would take the cores of YADE's OpenMP loops (BlasThreads.hpp).
TEST(ImplicitLinearAlgebra, SmallFactorRunsBlasOnOneThread)
{
	if (!setBlasThreads(2)) GTEST_SKIP() << "the BLAS of this process is not OpenBLAS";
	ASSERT_EQ(blasThreads(), 2);
	const int          n = 40;
	const BlockMatrix6 A = chainOrCompleteGraph(n, true);
	CholmodFactor      chol;
	chol.analyse(n, A.pairs);
	EXPECT_EQ(chol.blasThreadsUsed(), 1);
	ASSERT_TRUE(chol.factorise(A));
	EXPECT_EQ(blasThreads(), 1);
	setBlasThreads(2);
	VecXd x;
	chol.solve(VecXd::Ones(6 * n), x);
	EXPECT_EQ(blasThreads(), 1);
}

// The assembled block matrix is the matrix-free product on the free rows and columns.
TEST(ImplicitLinearAlgebra, AssembledMatrixIsTheMatrixFreeProduct)
{
	std::mt19937                g(16);
	const ImplicitViscousSystem sys = randomSystem(g, 24, 0.05);
	std::vector<int>            rowOfBody;
	const BlockMatrix6          A = sys.blockMatrix(rowOfBody);
	VecXd                       x = VecXd::Random(sys.size()), y, xr = VecXd::Zero(6 * A.size()), yr;
	for (size_t d = 0; d < sys.size(); ++d)
		if (!sys.isFree(d)) x[d] = 0;
	sys.apply(x, y, false);
	for (size_t i = 0; i < rowOfBody.size(); ++i)
		if (rowOfBody[i] >= 0) xr.segment<6>(6 * rowOfBody[i]) = x.segment<6>(6 * i);
	A.multiply(xr, yr);
	for (size_t d = 0; d < sys.size(); ++d) {
		if (!sys.isFree(d)) continue;
		EXPECT_NEAR(yr[6 * rowOfBody[d / 6] + d % 6], y[d], 1e-12 * y.norm()) << "unknown " << d;
	}
}

// With a fresh factorisation CG converges at once; the solution satisfies (M + Δt D) v = M v₀ + Δt F
// on the free rows and keeps the prescribed components.
TEST(ImplicitLinearAlgebra, SolveWithAFreshFactorSatisfiesTheSystem)
{
	std::mt19937                g(17);
	const ImplicitViscousSystem sys = randomSystem(g, 24, 0.05);
	VecXd             x;
	const SolveReport rep = solvedByCG(sys, sys, 1e-12, 50, x);
	EXPECT_LE(rep.iterations, 2);
	VecXd Ax;
	sys.apply(x, Ax, true);
	const VecXd b = sys.rightHandSide(), v0 = sys.currentVelocities();
	for (size_t d = 0; d < sys.size(); ++d) {
		if (sys.isFree(d)) EXPECT_NEAR(Ax[d], b[d], 1e-9 * b.norm()) << "row " << d;
		else EXPECT_EQ(x[d], v0[d]) << "prescribed " << d;
	}
}

// An aged factor (a different step's matrix) still preconditions: CG converges, in more iterations.
TEST(ImplicitLinearAlgebra, AnAgedFactorStillConverges)
{
	std::mt19937                g(18);
	const ImplicitViscousSystem older = randomSystem(g, 24, 0.05);
	std::mt19937                g2(18);
	ImplicitViscousSystem       newer = randomSystem(g2, 24, 0.08); // same pattern, other numbers
	VecXd             x;
	const SolveReport rep = solvedByCG(older, newer, 1e-10, 200, x);
	EXPECT_GT(rep.iterations, 2);
}

// The step-error filter (physics.md A1a) is (M + Δt D)⁻¹ M on the free rows, with the prescribed
// components and the wall's motion at zero — by one application of a fresh factor as by CG — and,
// D being dissipative, it never amplifies a perturbation in the kinetic-energy norm.
TEST(ImplicitLinearAlgebra, StepErrorFilterIsTheDampedInverse)
{
	std::mt19937                g(19);
	const ImplicitViscousSystem sys = randomSystem(g, 24, 0.05);
	LaggedCholesky              pre;
	ASSERT_TRUE(pre.refresh(sys, false));
	VecXd u = VecXd::Random(sys.size()), mask(sys.size());
	for (size_t d = 0; d < sys.size(); ++d)
		mask[d] = sys.isFree(d) ? 1 : 0;
	u = u.cwiseProduct(mask); // as the solver's: a change of velocity, none on a blocked component
	for (const bool factor : { true, false }) {
		VecXd y, Ay;
		sys.filter(u, y, 1e-12, 500, factor ? &pre : nullptr, factor);
		sys.apply(y, Ay, false);
		const VecXd Mu = sys.inertialLoad(u);
		for (size_t d = 0; d < sys.size(); ++d) {
			if (sys.isFree(d)) EXPECT_NEAR(Ay[d], Mu[d], 1e-9 * Mu.norm()) << factor << " row " << d;
			else EXPECT_EQ(y[d], 0) << factor << " prescribed " << d;
		}
		EXPECT_LT(y.dot(sys.inertialLoad(y)), 0.99 * u.dot(sys.inertialLoad(u))) << factor; // the bridges damp it
	}
}

// A perturbation per unit mass is undefined on a wall's or fixed body's rows (its mass is zero):
// whatever they hold, the filter reads the free rows only.  NaN there once made every CG check of
// the estimate "converge" at once (a NaN residual), so that a lagging factor was never corrected in
// a scene with walls.
TEST(ImplicitLinearAlgebra, StepErrorFilterIgnoresThePrescribedRows)
{
	std::mt19937                g(29);
	const ImplicitViscousSystem sys = randomSystem(g, 24, 0.05);
	LaggedCholesky              pre;
	ASSERT_TRUE(pre.refresh(sys, false));
	VecXd clean = VecXd::Random(sys.size()), undefined(sys.size());
	long  prescribed = 0;
	for (size_t d = 0; d < sys.size(); ++d) {
		if (!sys.isFree(d)) clean[d] = 0, ++prescribed;
		undefined[d] = sys.isFree(d) ? clean[d] : (d % 2 ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN());
	}
	ASSERT_GT(prescribed, 0);
	for (const bool factor : { true, false }) {
		VecXd expected, y;
		sys.filter(clean, expected, 1e-12, 500, &pre, factor);
		sys.filter(undefined, y, 1e-12, 500, &pre, factor);
		ASSERT_TRUE(y.allFinite()) << factor;
		EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm()) << factor;
		MatXd Y;
		sys.filterColumns(undefined.replicate(1, 2), Y, 1e-12, 500, &pre, factor);
		EXPECT_LT((Y.col(1) - expected).norm(), 1e-12 * expected.norm()) << factor;
	}
}

// Several perturbations filtered at once (the step error and the offsets, physics.md A1a/A1b) are
// each filtered as alone: one application of the factor for all columns, or CG column by column.
TEST(ImplicitLinearAlgebra, FilteringColumnsAtOnceIsFilteringEach)
{
	std::mt19937                g(23);
	const ImplicitViscousSystem sys = randomSystem(g, 30, 0.05);
	LaggedCholesky              pre;
	ASSERT_TRUE(pre.refresh(sys, false));
	MatXd U = MatXd::Random(sys.size(), 3);
	for (const bool factor : { true, false }) {
		MatXd Y;
		sys.filterColumns(U, Y, 1e-12, 500, factor ? &pre : nullptr, factor);
		ASSERT_EQ(Y.cols(), 3);
		for (long c = 0; c < U.cols(); ++c) {
			VecXd y;
			sys.filter(U.col(c), y, 1e-12, 500, factor ? &pre : nullptr, factor);
			EXPECT_LT((Y.col(c) - y).norm(), 1e-9 * y.norm()) << factor << " column " << c;
			EXPECT_GT(y.norm(), 0);
		}
	}
}
