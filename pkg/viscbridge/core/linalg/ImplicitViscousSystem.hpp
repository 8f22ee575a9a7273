// Backward Euler for the viscous bridge forces over the whole contact network (physics.md §4, P15):
//     (M + Δt D) v_{n+1/2} = M v_{n−1/2} + Δt F_other,
// D = Σ_bridges J_cᵀ C_c J_c (symmetric positive semi-definite for the dissipative models), solved
// matrix-free by preconditioned conjugate gradients.  YADE-free.
//
// Preconditioners: 6×6 block Jacobi (cheap, but with Δt C/m up to 1e6 at high viscosity CG needs
// hundreds of iterations), or a sparse Cholesky factorisation (CholmodFactor.hpp) of the
// assembled matrix that is kept over several steps: contacts below S_min have constant
// coefficients, so a lagged factorisation is nearly exact and CG converges in a few iterations.
#pragma once
#include "viscbridge/core/linalg/BlockMatrix6.hpp"
#include "viscbridge/core/linalg/BridgeDampingMatrix.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <vector>

namespace viscbridge {

using Mat3 = Eigen::Matrix<double, 3, 3>;

// A body of the system: 6 velocity unknowns (v, ω), each free or prescribed.
struct SystemBody {
	double              mass    = 0;
	Mat3                inertia = Mat3::Zero(); // rotational inertia in the global frame (a sphere: I·1; a clump: R diag(I) Rᵀ)
	Vec3                vel = Vec3::Zero(), angVel = Vec3::Zero();
	Vec3                force = Vec3::Zero(), torque = Vec3::Zero(); // every other force, gravity included
	std::array<bool, 6> free {}; // false: the component keeps its current value (walls, fixed, blocked DOFs)
};

struct SystemBridge {
	int          body1, body2; // indices into the body list
	ViscousBlock block;
	Vec3         shiftVel = Vec3::Zero(); // periodic: body 2's image moves with this extra velocity
	Vec3         branch   = Vec3::Zero(); // centre of body 2 (its image) − centre of body 1: the multigrid's rigid motions
};

struct SolveReport {
	int    iterations = 0;
	double residual   = 0; // ‖r‖/‖b‖ of the free rows
	bool   converged  = false;
	bool   direct     = false; // the sparse Cholesky fallback was used
	int    products   = 0;     // matrix-free products (M + Δt D) x
	double productSeconds = 0, preconditionerSeconds = 0; // wall time of the products and of the preconditioner
};

// Adds the wall time of its scope to a counter.
class ScopeTimer {
public:
	explicit ScopeTimer(double& total) : total_(total), start_(std::chrono::steady_clock::now()) { }
	~ScopeTimer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
	double&                               total_;
	std::chrono::steady_clock::time_point start_;
};

class ImplicitViscousSystem;

// z ≈ A⁻¹ r on the free rows (rows of prescribed unknowns are left 0).
class Preconditioner {
public:
	virtual ~Preconditioner()                                  = default;
	virtual void apply(const VecXd& r, VecXd& z) const = 0;
	// Z ≈ A⁻¹ R for several right-hand sides, column by column; a factor overrides it with one sweep
	// for all columns (on a large bed its sweeps are memory-bound: one pass over it serves them all).
	virtual void applyColumns(const MatXd& R, MatXd& Z) const
	{
		Z.resize(R.rows(), R.cols());
		VecXd z;
		for (long c = 0; c < R.cols(); ++c) {
			apply(R.col(c), z);
			Z.col(c) = z;
		}
	}
};

// Sums over the processes that share a system (MPI), and keeps the ghost rows of a search
// direction equal to their owners'; serially, nothing to do.
struct SerialReduction {
	double sum(double v) const { return v; }
	void   share(VecXd&) const { }
};

// Preconditioned conjugate gradients: x from its start value, with r = b − A x on entry; stops at
// ‖r‖/bnorm ≤ tolerance (or a non-finite residual) or after maxIterations (rep says which).  The
// residual is tested before the preconditioner is applied to it, so that a converged iteration does
// not pay for a preconditioner application it would not use (one of the four of a typical solve).
template <class Product, class Precondition, class Reduction>
void conjugateGradients(VecXd& x, VecXd& r, double bnorm, double tolerance, int maxIterations, const Product& product, const Precondition& precondition,
                        const Reduction& reduction, SolveReport& rep)
{
	auto converged = [&](const VecXd& residual) {
		rep.residual = std::sqrt(reduction.sum(residual.squaredNorm())) / bnorm;
		return rep.residual <= tolerance || !std::isfinite(rep.residual);
	};
	rep.iterations = 0;
	if (converged(r)) return;
	VecXd z, p, Ap;
	precondition(r, z);
	p = z;
	reduction.share(p);
	double rz = reduction.sum(r.dot(z));
	while (rep.iterations < maxIterations) {
		product(p, Ap);
		++rep.iterations;
		const double alpha = rz / reduction.sum(p.dot(Ap));
		x.noalias() += alpha * p;
		r.noalias() -= alpha * Ap;
		if (converged(r)) return;
		precondition(r, z);
		const double rzOld = rz;
		rz                 = reduction.sum(r.dot(z));
		p                  = z + (rz / rzOld) * p;
		reduction.share(p);
	}
}

class ImplicitViscousSystem {
public:
	ImplicitViscousSystem(std::vector<SystemBody> bodies, std::vector<SystemBridge> bridges, double dt)
	        : bodies_(std::move(bodies))
	        , bridges_(std::move(bridges))
	        , dt_(dt)
	{
		// Body → bridges adjacency, so that each body gathers its own rows (no write conflicts).
		start_.assign(bodies_.size() + 1, 0);
		for (const auto& c : bridges_) {
			++start_[c.body1 + 1];
			++start_[c.body2 + 1];
		}
		for (size_t i = 0; i < bodies_.size(); ++i)
			start_[i + 1] += start_[i];
		adjacent_.resize(start_.back());
		std::vector<int> fill(start_.begin(), start_.end() - 1);
		for (size_t k = 0; k < bridges_.size(); ++k) {
			adjacent_[fill[bridges_[k].body1]++] = static_cast<int>(k);
			adjacent_[fill[bridges_[k].body2]++] = static_cast<int>(k);
		}
		const long m = static_cast<long>(bridges_.size());
		anchored_.resize(m);
		loaded_.resize(m);
#pragma omp parallel for schedule(static)
		for (long k = 0; k < m; ++k) {
			anchored_[k] = isAnchored(bridges_[k].block);
			loaded_[k]   = !bridges_[k].shiftVel.isZero(0) || !allFree(bodies_[bridges_[k].body1]) || !allFree(bodies_[bridges_[k].body2]);
		}
	}

	size_t size() const { return 6 * bodies_.size(); }
	bool   isFree(size_t dof) const { return bodies_[dof / 6].free[dof % 6]; }

	// The current velocities (v_{n−1/2}) as one vector.
	VecXd currentVelocities() const
	{
		VecXd x(size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			x.segment<6>(6 * i) << bodies_[i].vel, bodies_[i].angVel;
		return x;
	}

	// y = M x + Δt D x, with the periodic shift velocity when `affine` (a full solution vector).
	// Each bridge is evaluated once; each body then gathers its own bridges' rows (no write conflicts).
	void apply(const VecXd& x, VecXd& y, bool affine) const
	{
		y.resize(size());
		resistance_.resize(bridges_.size());
		const long m = static_cast<long>(bridges_.size()), n = static_cast<long>(bodies_.size());
#pragma omp parallel
		{
#pragma omp for schedule(static)
			for (long k = 0; k < m; ++k) {
				const SystemBridge& c     = bridges_[k];
				const Vec3          shift = affine ? c.shiftVel : Vec3::Zero();
				const Vec3 v1 = x.segment<3>(6 * c.body1), w1 = x.segment<3>(6 * c.body1 + 3), v2 = x.segment<3>(6 * c.body2), w2 = x.segment<3>(6 * c.body2 + 3);
				resistance_[k] = anchored_[k] ? bridgeResistance<true>(c.block, v1, w1, v2, w2, shift) : bridgeResistance<false>(c.block, v1, w1, v2, w2, shift);
			}
#pragma omp for schedule(static)
			for (long i = 0; i < n; ++i) {
				const SystemBody& b = bodies_[i];
				Vec3              f, t;
				resultantOn(i, resistance_, f, t);
				y.segment<3>(6 * i)     = b.mass * x.segment<3>(6 * i) + dt_ * f;
				y.segment<3>(6 * i + 3) = b.inertia * x.segment<3>(6 * i + 3) + dt_ * t;
			}
		}
	}

	// The resistance D v of its bridges on body i (R: per bridge, from bridgeForces), summed in the
	// order of its bridges, so that any number of threads gives the same sum.
	void resultantOn(long i, const std::vector<BridgeResistance>& R, Vec3& force, Vec3& torque) const
	{
		force.setZero();
		torque.setZero();
		for (int k = start_[i]; k < start_[i + 1]; ++k) {
			const int               e     = adjacent_[k];
			const bool              first = bridges_[e].body1 == i;
			force += first ? R[e].force1 : R[e].force2;
			torque += first ? R[e].torque1 : R[e].torque2;
		}
	}

	// The right-hand side M v_{n−1/2} + Δt F_other (free rows).
	VecXd rightHandSide() const
	{
		VecXd b(size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			b.segment<6>(6 * i) << bodies_[i].mass * bodies_[i].vel + dt_ * bodies_[i].force,
			        bodies_[i].inertia * bodies_[i].angVel + dt_ * bodies_[i].torque;
		return b;
	}

	// The system on the free unknowns x_f:  A_ff x_f = b_f − (Δt D (prescribed + shift))_f.  `others`
	// marks unknowns that are neither free nor prescribed here (1: under MPI, the ghosts' rows,
	// solved by their owners).
	struct FreeProblem {
		VecXd mask, prescribed, rhs;
	};
	// 1 on the free unknowns, 0 on the prescribed ones.
	VecXd freeMask() const
	{
		VecXd mask(size());
		for (size_t d = 0; d < size(); ++d)
			mask[d] = isFree(d) ? 1 : 0;
		return mask;
	}
	FreeProblem freeProblem(const VecXd& others) const
	{
		const size_t n       = size();
		const VecXd  current = currentVelocities();
		FreeProblem  f { freeMask(), VecXd::Zero(n), VecXd() };
		for (size_t d = 0; d < n; ++d)
			if (!isFree(d) && others[d] == 0) f.prescribed[d] = current[d];
		f.rhs = (rightHandSide() - prescribedLoad(f.prescribed) - inertialLoad(f.prescribed)).cwiseProduct(f.mask);
		return f;
	}

	// Δt D (prescribed + shift): the load of the prescribed velocities (walls, fixed bodies, blocked
	// components) and of the periodic shift, from the only bridges that carry one.
	VecXd prescribedLoad(const VecXd& prescribed) const
	{
		VecXd y = VecXd::Zero(size());
		for (size_t k = 0; k < bridges_.size(); ++k) {
			const SystemBridge& c = bridges_[k];
			if (!loaded_[k]) continue;
			const BridgeResistance R = bridgeResistance(c.block, prescribed.segment<3>(6 * c.body1), prescribed.segment<3>(6 * c.body1 + 3),
			                                            prescribed.segment<3>(6 * c.body2), prescribed.segment<3>(6 * c.body2 + 3), c.shiftVel);
			y.segment<3>(6 * c.body1) += dt_ * R.force1;
			y.segment<3>(6 * c.body1 + 3) += dt_ * R.torque1;
			y.segment<3>(6 * c.body2) += dt_ * R.force2;
			y.segment<3>(6 * c.body2 + 3) += dt_ * R.torque2;
		}
		return y;
	}

	// M (prescribed): a full inertia tensor couples a blocked rotation to the free ones (a sphere's
	// or a diagonal tensor does not, and this is zero there).
	VecXd inertialLoad(const VecXd& prescribed) const
	{
		VecXd y(size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			y.segment<6>(6 * i) << bodies_[i].mass * prescribed.segment<3>(6 * i), bodies_[i].inertia * prescribed.segment<3>(6 * i + 3);
		return y;
	}

	// M u on the free rows, zero elsewhere whatever u holds there (a fixed body's entry may be
	// undefined: what it would be per unit of its zero mass).
	VecXd freeLoad(const VecXd& u, const VecXd& mask) const
	{
		const VecXd free = (mask.array() > 0).select(u, 0.0); // before M: a body's inertia mixes its components
		return inertialLoad(free).cwiseProduct(mask);
	}

	// A_ff v (rows outside `mask` zero), timed and counted in rep.
	auto maskedProduct(const VecXd& mask, SolveReport& rep) const
	{
		return [this, &mask, &rep](const VecXd& v, VecXd& Av) {
			const ScopeTimer timer(rep.productSeconds);
			apply(v, Av, false);
			Av.array() *= mask.array();
			++rep.products;
		};
	}

	// z = P⁻¹ r on the rows of `mask`: the given preconditioner, else 6×6 block Jacobi.
	auto preconditioning(const Preconditioner* pre, const VecXd& mask, SolveReport& rep) const
	{
		std::vector<Eigen::LDLT<Mat6>> jacobi;
		if (!pre) jacobi = blockJacobi();
		return [this, pre, &mask, &rep, jacobi = std::move(jacobi)](const VecXd& r, VecXd& z) {
			const ScopeTimer timer(rep.preconditionerSeconds);
			if (pre) {
				pre->apply(r, z);
			} else {
				z.resize(r.size());
				for (size_t i = 0; i < bodies_.size(); ++i)
					z.segment<6>(6 * i) = jacobi[i].solve(r.segment<6>(6 * i));
			}
			z.array() *= mask.array();
		};
	}

	// Solves for v_{n+1/2}; x holds the starting guess (prescribed entries are taken from the bodies)
	// and receives the solution.  Falls back to a sparse Cholesky factorisation when CG does not
	// reach `tolerance` within maxIterations (the report says so).
	SolveReport solve(VecXd& x, double tolerance, int maxIterations, const Preconditioner* pre = nullptr) const
	{
		const FreeProblem f  = freeProblem(VecXd::Zero(size()));
		VecXd             xf = x.cwiseProduct(f.mask);
		SolveReport       rep;
		const double      bnorm = f.rhs.norm();
		if (bnorm == 0) {
			x             = f.prescribed;
			rep.converged = true;
			return rep;
		}
		const auto product      = maskedProduct(f.mask, rep);
		const auto precondition = preconditioning(pre, f.mask, rep);
		VecXd      r;
		product(xf, r);
		r = f.rhs - r;
		conjugateGradients(xf, r, bnorm, tolerance, maxIterations, product, precondition, SerialReduction(), rep);
		rep.converged = rep.residual <= tolerance;
		if (!rep.converged) {
			rep.direct = true;
			xf         = directSolve(f.rhs);
			VecXd Ax;
			product(xf, Ax);
			rep.residual  = (f.rhs - Ax).norm() / bnorm;
			rep.converged = std::isfinite(rep.residual) && rep.residual <= std::max(tolerance, 1e-10);
		}
		x = xf + f.prescribed;
		return rep;
	}

	// y ≈ (M + Δt D)⁻¹ M u on the free rows, with the prescribed components and the periodic shift
	// at zero: how this step's matrix filters a velocity perturbation u (physics.md A1a).  `factor`:
	// pre is a Cholesky factor of this matrix or of a recent one (lagged), and its one application
	// stands for the solve, as an estimate allows; else CG to `tolerance` from y's value, stopping
	// at maxIterations with whatever it reached (an estimate needs no fallback).
	void filter(const VecXd& u, VecXd& y, double tolerance, int maxIterations, const Preconditioner* pre, bool factor) const
	{
		const VecXd mask = freeMask();
		const VecXd b    = freeLoad(u, mask);
		if (factor && pre) {
			pre->apply(b, y);
			y.array() *= mask.array();
			return;
		}
		const double bnorm = b.norm();
		y                  = y.size() == b.size() ? VecXd(y.cwiseProduct(mask)) : VecXd::Zero(b.size());
		if (bnorm == 0) return;
		SolveReport rep;
		const auto  product = maskedProduct(mask, rep);
		VecXd       r;
		product(y, r);
		r = b - r;
		conjugateGradients(y, r, bnorm, tolerance, maxIterations, product, preconditioning(pre, mask, rep), SerialReduction(), rep);
	}

	// The same for the columns of U at once, each as filter() would; with a factor, one application
	// for all of them.
	void filterColumns(const MatXd& U, MatXd& Y, double tolerance, int maxIterations, const Preconditioner* pre, bool factor) const
	{
		if (factor && pre) {
			const VecXd mask = freeMask();
			MatXd       B(U.rows(), U.cols());
			for (long c = 0; c < U.cols(); ++c)
				B.col(c) = freeLoad(U.col(c), mask);
			pre->applyColumns(B, Y);
			Y.array().colwise() *= mask.array();
			return;
		}
		Y.resize(U.rows(), U.cols());
		VecXd y;
		for (long c = 0; c < U.cols(); ++c) {
			filter(U.col(c), y, tolerance, maxIterations, pre, factor);
			Y.col(c) = y;
		}
	}

	// Forces −D v (with the shift) on every body, for the solved velocities: what the bridges exert.
	std::vector<BridgeResistance> bridgeForces(const VecXd& x) const
	{
		std::vector<BridgeResistance> out(bridges_.size());
		const long                    m = static_cast<long>(bridges_.size());
#pragma omp parallel for schedule(static)
		for (long k = 0; k < m; ++k) {
			const SystemBridge& c = bridges_[k];
			out[k] = bridgeResistance(c.block, x.segment<3>(6 * c.body1), x.segment<3>(6 * c.body1 + 3), x.segment<3>(6 * c.body2),
			                          x.segment<3>(6 * c.body2 + 3), c.shiftVel);
		}
		return out;
	}

	// Diagonal 6×6 blocks of M + Δt D (free rows and columns; identity on prescribed ones).
	std::vector<Eigen::LDLT<Mat6>> blockJacobi() const
	{
		std::vector<Mat6> blocks(bodies_.size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			blocks[i] = massBlock(i);
		for (const auto& c : bridges_) {
			const BridgeDampingMatrix D = bridgeDampingMatrix(c.block);
			blocks[c.body1] += dt_ * D.block[0][0];
			blocks[c.body2] += dt_ * D.block[1][1];
		}
		std::vector<Eigen::LDLT<Mat6>> out(bodies_.size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			out[i].compute(masked(blocks[i], i, i));
		return out;
	}

	// M + Δt D as 6×6 blocks over the bodies with a free component (rowOfBody: their block rows, −1
	// for the others), prescribed rows and columns replaced by the identity's; pairs sorted, so that
	// the same bridges give the same matrix whatever their order.  pairBranch (if given): per pair,
	// centre of its second body − centre of its first (a bridge's branch).
	BlockMatrix6 blockMatrix(std::vector<int>& rowOfBody, std::vector<Vec3>* pairBranch = nullptr) const
	{
		rowOfBody.assign(bodies_.size(), -1);
		int rows = 0;
		for (size_t i = 0; i < bodies_.size(); ++i)
			if (std::any_of(bodies_[i].free.begin(), bodies_[i].free.end(), [](bool f) { return f; })) rowOfBody[i] = rows++;
		BlockMatrix6 A;
		A.diagonal.resize(rows);
		for (size_t i = 0; i < bodies_.size(); ++i)
			if (rowOfBody[i] >= 0) A.diagonal[rowOfBody[i]] = massBlock(i);
		std::vector<std::pair<int, int>> pairs;
		std::vector<Mat6>                upper;
		std::vector<Vec3>                branch;
		for (const auto& c : bridges_) {
			const int i = rowOfBody[c.body1], j = rowOfBody[c.body2];
			if (i < 0 && j < 0) continue;
			const BridgeDampingMatrix D = bridgeDampingMatrix(c.block);
			if (i >= 0) A.diagonal[i] += dt_ * D.block[0][0];
			if (j >= 0) A.diagonal[j] += dt_ * D.block[1][1];
			if (i < 0 || j < 0) continue;
			pairs.emplace_back(std::min(i, j), std::max(i, j));
			branch.push_back(i < j ? c.branch : Vec3(-c.branch));
			upper.push_back(dt_ * (i < j ? masked(D.block[0][1], c.body1, c.body2) : masked(D.block[1][0], c.body2, c.body1)));
		}
		for (size_t i = 0; i < bodies_.size(); ++i)
			if (rowOfBody[i] >= 0) A.diagonal[rowOfBody[i]] = masked(A.diagonal[rowOfBody[i]], i, i);
		std::vector<int> sorted(pairs.size());
		std::iota(sorted.begin(), sorted.end(), 0);
		std::sort(sorted.begin(), sorted.end(), [&](int a, int b) { return pairs[a] < pairs[b]; });
		if (pairBranch) pairBranch->clear();
		for (const int p : sorted) {
			if (!A.pairs.empty() && A.pairs.back() == pairs[p]) A.upper.back() += upper[p]; // two bridges between the same bodies
			else {
				A.pairs.push_back(pairs[p]);
				A.upper.push_back(upper[p]);
				if (pairBranch) pairBranch->push_back(branch[p]);
			}
		}
		return A;
	}

	// M + Δt D on the free rows and columns, identity on the prescribed ones, as one scalar sparse
	// matrix (for the direct fallback).
	Eigen::SparseMatrix<double> assemble() const
	{
		std::vector<int>                    rowOfBody;
		const BlockMatrix6                  A = blockMatrix(rowOfBody);
		std::vector<Eigen::Triplet<double>> t;
		auto add = [&](int bi, int bj, const Mat6& B) {
			for (int k = 0; k < 6; ++k)
				for (int l = 0; l < 6; ++l)
					if (B(k, l) != 0 || (bi == bj && k == l)) t.emplace_back(6 * bi + k, 6 * bj + l, B(k, l));
		};
		for (size_t i = 0; i < bodies_.size(); ++i) {
			if (rowOfBody[i] >= 0) add(static_cast<int>(i), static_cast<int>(i), A.diagonal[rowOfBody[i]]);
			else add(static_cast<int>(i), static_cast<int>(i), Mat6::Identity());
		}
		std::vector<int> bodyOfRow(A.size());
		for (size_t i = 0; i < bodies_.size(); ++i)
			if (rowOfBody[i] >= 0) bodyOfRow[rowOfBody[i]] = static_cast<int>(i);
		for (size_t p = 0; p < A.pairs.size(); ++p) {
			add(bodyOfRow[A.pairs[p].first], bodyOfRow[A.pairs[p].second], A.upper[p]);
			add(bodyOfRow[A.pairs[p].second], bodyOfRow[A.pairs[p].first], A.upper[p].transpose());
		}
		Eigen::SparseMatrix<double> S(size(), size());
		S.setFromTriplets(t.begin(), t.end());
		return S;
	}

	const std::vector<SystemBody>&   bodies() const { return bodies_; }
	const std::vector<SystemBridge>& bridges() const { return bridges_; }

private:
	Mat6 massBlock(size_t i) const
	{
		Mat6 m = Mat6::Zero();
		m.diagonal().head<3>().setConstant(bodies_[i].mass);
		m.bottomRightCorner<3, 3>() = bodies_[i].inertia;
		return m;
	}

	// B with the rows of body i's and the columns of body j's prescribed components zeroed, and on a
	// diagonal block (i == j) a unit diagonal there.
	Mat6 masked(Mat6 B, size_t i, size_t j) const
	{
		for (int d = 0; d < 6; ++d) {
			if (!bodies_[i].free[d]) B.row(d).setZero();
			if (!bodies_[j].free[d]) B.col(d).setZero();
			if (i == j && !bodies_[i].free[d]) B(d, d) = 1;
		}
		return B;
	}

	// The loud fallback: the assembled system, factorised.
	VecXd directSolve(const VecXd& rhs) const
	{
		Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(assemble());
		if (ldlt.info() != Eigen::Success) return VecXd::Constant(rhs.size(), std::nan(""));
		return ldlt.solve(rhs);
	}

	std::vector<SystemBody>   bodies_;
	std::vector<SystemBridge> bridges_;
	double                    dt_;
	std::vector<int>          start_, adjacent_;
	static bool allFree(const SystemBody& b) { return std::all_of(b.free.begin(), b.free.end(), [](bool f) { return f; }); }

	std::vector<char>                     anchored_;   // per bridge: a wall side's anchor terms are needed
	std::vector<char>                     loaded_;     // per bridge: it touches a prescribed component or is periodic-shifted
	mutable std::vector<BridgeResistance> resistance_; // workspace of apply()
};

} // namespace viscbridge
