// Backward Euler for the viscous bridge forces over the whole contact network (physics.md §4, P15):
//     (M + Δt D) v_{n+1/2} = M v_{n−1/2} + Δt F_other,
// D = Σ_bridges J_cᵀ C_c J_c (symmetric positive semi-definite for the dissipative models), solved
// matrix-free by preconditioned conjugate gradients.  YADE-free.
//
// Preconditioners: 6×6 block Jacobi (cheap, but with Δt C/m up to 1e6 at high viscosity CG needs
// hundreds of iterations), or a sparse Cholesky factorisation of the assembled matrix that is kept
// over several steps: contacts below S_min have constant coefficients, so a lagged factorisation
// is nearly exact and CG converges in a few iterations.
#pragma once
#include "PairKernel.hpp"
#include "ViscousBlock.hpp"
#include "Vector.hpp"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <vector>

namespace viscbridge {

using Mat3  = Eigen::Matrix<double, 3, 3>;
using Mat6  = Eigen::Matrix<double, 6, 6>;
using VecXd = Eigen::VectorXd;

// A body of the system: 6 velocity unknowns (v, ω), each free or prescribed.
struct SystemBody {
	double              mass = 0, inertia = 0; // sphere: scalar moment of inertia
	Vec3                vel = Vec3::Zero(), angVel = Vec3::Zero();
	Vec3                force = Vec3::Zero(), torque = Vec3::Zero(); // every other force, gravity included
	std::array<bool, 6> free {}; // false: the component keeps its current value (walls, fixed, blocked DOFs)
};

struct SystemBridge {
	int          body1, body2; // indices into the body list
	ViscousBlock block;
	Vec3         shiftVel = Vec3::Zero(); // periodic: body 2's image moves with this extra velocity
};

struct SolveReport {
	int    iterations = 0;
	double residual   = 0; // ‖r‖/‖b‖ of the free rows
	bool   converged  = false;
	bool   direct     = false; // the sparse Cholesky fallback was used
};

class ImplicitViscousSystem;

// z ≈ A⁻¹ r on the free rows (rows of prescribed unknowns are left 0).
class Preconditioner {
public:
	virtual ~Preconditioner()                                  = default;
	virtual void apply(const VecXd& r, VecXd& z) const = 0;
};

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
	void apply(const VecXd& x, VecXd& y, bool affine) const
	{
		y.resize(size());
		const long n = static_cast<long>(bodies_.size());
#pragma omp parallel for schedule(static)
		for (long i = 0; i < n; ++i) {
			const SystemBody& b = bodies_[i];
			Vec6              r;
			r << b.mass * x.segment<3>(6 * i), b.inertia * x.segment<3>(6 * i + 3);
			for (int k = start_[i]; k < start_[i + 1]; ++k) {
				const SystemBridge&    c = bridges_[adjacent_[k]];
				const BridgeResistance R = bridgeResistance(c.block, x.segment<3>(6 * c.body1), x.segment<3>(6 * c.body1 + 3), x.segment<3>(6 * c.body2),
				                                            x.segment<3>(6 * c.body2 + 3), affine ? c.shiftVel : Vec3::Zero());
				if (c.body1 == i) r += dt_ * (Vec6() << R.force1, R.torque1).finished();
				if (c.body2 == i) r += dt_ * (Vec6() << R.force2, R.torque2).finished();
			}
			y.segment<6>(6 * i) = r;
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

	// Solves for v_{n+1/2}; x holds the starting guess (prescribed entries are taken from the bodies)
	// and receives the solution.  Falls back to a sparse Cholesky factorisation when CG does not
	// reach `tolerance` within maxIterations (the report says so).
	SolveReport solve(VecXd& x, double tolerance, int maxIterations, const Preconditioner* pre = nullptr) const
	{
		const size_t n = size();
		const VecXd  current = currentVelocities();
		VecXd        prescribed = VecXd::Zero(n), mask = VecXd::Zero(n);
		for (size_t d = 0; d < n; ++d) {
			if (isFree(d)) mask[d] = 1;
			else prescribed[d] = current[d];
		}
		// Free unknowns only: x_f, with  A_ff x_f = b_f − (Δt D (prescribed + shift))_f.
		VecXd rhs, tmp;
		apply(prescribed, tmp, true); // M·prescribed vanishes on the free rows; Δt D(prescribed + shift) stays
		rhs = (rightHandSide() - tmp).cwiseProduct(mask);
		VecXd xf = x.cwiseProduct(mask);
		const double bnorm = rhs.norm();
		SolveReport  rep;
		if (bnorm == 0) {
			x = prescribed;
			rep.converged = true;
			return rep;
		}
		std::vector<Eigen::LDLT<Mat6>> jacobi;
		if (!pre) jacobi = blockJacobi();
		auto precondition = [&](const VecXd& r, VecXd& z) {
			if (pre) {
				pre->apply(r, z);
			} else {
				z.resize(n);
				for (size_t i = 0; i < bodies_.size(); ++i)
					z.segment<6>(6 * i) = jacobi[i].solve(r.segment<6>(6 * i));
			}
			z = z.cwiseProduct(mask);
		};
		VecXd r, z, p, Ap;
		apply(xf, Ap, false);
		r = rhs - Ap.cwiseProduct(mask);
		precondition(r, z);
		p         = z;
		double rz = r.dot(z);
		for (rep.iterations = 0; rep.iterations < maxIterations; ++rep.iterations) {
			rep.residual = r.norm() / bnorm;
			if (rep.residual <= tolerance) break;
			apply(p, Ap, false);
			Ap            = Ap.cwiseProduct(mask);
			const double alpha = rz / p.dot(Ap);
			xf += alpha * p;
			r -= alpha * Ap;
			precondition(r, z);
			const double rzNew = r.dot(z);
			p                  = z + (rzNew / rz) * p;
			rz                 = rzNew;
		}
		rep.residual  = r.norm() / bnorm;
		rep.converged = rep.residual <= tolerance;
		if (!rep.converged) {
			rep.direct = true;
			xf         = directSolve(rhs);
			apply(xf, Ap, false);
			rep.residual  = (rhs - Ap.cwiseProduct(mask)).norm() / bnorm;
			rep.converged = std::isfinite(rep.residual) && rep.residual <= std::max(tolerance, 1e-10);
		}
		x = xf + prescribed;
		return rep;
	}

	// Forces −D v (with the shift) on every body, for the solved velocities: what the bridges exert.
	std::vector<BridgeResistance> bridgeForces(const VecXd& x) const
	{
		std::vector<BridgeResistance> out(bridges_.size());
		for (size_t k = 0; k < bridges_.size(); ++k) {
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
		for (size_t i = 0; i < bodies_.size(); ++i) {
			blocks[i].setZero();
			blocks[i].topLeftCorner<3, 3>().diagonal().setConstant(bodies_[i].mass);
			blocks[i].bottomRightCorner<3, 3>().diagonal().setConstant(bodies_[i].inertia);
		}
		for (const auto& c : bridges_) {
			const ViscousBlock& b = c.block;
			const Mat3          nn = b.n * b.n.transpose(), P = Mat3::Identity() - nn;
			Mat3                N;
			N << 0, -b.n[2], b.n[1], b.n[2], 0, -b.n[0], -b.n[1], b.n[0], 0;
			const auto& m = b.resistance;
			for (int side = 0; side < 2; ++side) {
				const int    i     = side == 0 ? c.body1 : c.body2;
				const double sigma = side == 0 ? 1.0 : -1.0, a = side == 0 ? b.a1 : b.a2;
				Mat6         K;
				K.topLeftCorner<3, 3>()     = b.cn * nn + m.m11 * P;
				K.topRightCorner<3, 3>()    = -sigma * a * m.m12 * N;
				K.bottomLeftCorner<3, 3>()  = sigma * a * m.m21 * N;
				K.bottomRightCorner<3, 3>() = a * a * m.m22 * P;
				blocks[i] += dt_ * K;
			}
		}
		std::vector<Eigen::LDLT<Mat6>> out(bodies_.size());
		for (size_t i = 0; i < bodies_.size(); ++i) {
			for (int d = 0; d < 6; ++d)
				if (!bodies_[i].free[d]) {
					blocks[i].row(d).setZero();
					blocks[i].col(d).setZero();
					blocks[i](d, d) = 1;
				}
			out[i].compute(blocks[i]);
		}
		return out;
	}

	// M + Δt D on the free rows and columns, identity on the prescribed ones.  Each bridge's 12×12
	// block is read off its map with unit velocities.
	Eigen::SparseMatrix<double> assemble() const
	{
		const long n = static_cast<long>(size());
		VecXd      mask(n);
		for (long d = 0; d < n; ++d)
			mask[d] = isFree(d) ? 1 : 0;
		std::vector<Eigen::Triplet<double>> t;
		for (long d = 0; d < n; ++d)
			t.emplace_back(d, d, mask[d] != 0 ? (d % 6 < 3 ? bodies_[d / 6].mass : bodies_[d / 6].inertia) : 1.0);
		for (const auto& c : bridges_) {
			const int owners[2] = { c.body1, c.body2 };
			for (int j = 0; j < 12; ++j) {
				const long col = 6L * owners[j / 6] + j % 6;
				if (mask[col] == 0) continue;
				Vec6 e1 = Vec6::Zero(), e2 = Vec6::Zero();
				(j < 6 ? e1 : e2)[j % 6] = 1;
				const BridgeResistance R = bridgeResistance(c.block, e1.head<3>(), e1.tail<3>(), e2.head<3>(), e2.tail<3>(), Vec3::Zero());
				const Vec6 rows[2] = { (Vec6() << R.force1, R.torque1).finished(), (Vec6() << R.force2, R.torque2).finished() };
				// zeros are kept: the pattern depends only on which bodies share bridges, so that a
				// factorisation's symbolic analysis can be reused
				for (int side = 0; side < 2; ++side)
					for (int k = 0; k < 6; ++k) {
						const long row = 6L * owners[side] + k;
						if (mask[row] != 0) t.emplace_back(row, col, dt_ * rows[side][k]);
					}
			}
		}
		Eigen::SparseMatrix<double> A(n, n);
		A.setFromTriplets(t.begin(), t.end()); // duplicates (shared bodies) are summed
		return A;
	}

	const std::vector<SystemBody>&   bodies() const { return bodies_; }
	const std::vector<SystemBridge>& bridges() const { return bridges_; }

private:
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
};

// A sparse LDLᵀ factorisation of an earlier step's matrix, reused while the system keeps the same
// unknowns and bridges (the caller decides when to refresh it).
class LaggedCholesky : public Preconditioner {
public:
	// Factorises the system's matrix (the symbolic analysis is redone only when the pattern changed).
	bool refresh(const ImplicitViscousSystem& system, bool samePattern)
	{
		const Eigen::SparseMatrix<double> A = system.assemble();
		if (!samePattern || !analysed_) {
			ldlt_.analyzePattern(A);
			analysed_ = true;
		}
		ldlt_.factorize(A);
		size_ = A.rows();
		return ldlt_.info() == Eigen::Success;
	}
	bool matches(size_t size) const { return analysed_ && static_cast<size_t>(size_) == size && ldlt_.info() == Eigen::Success; }
	void apply(const VecXd& r, VecXd& z) const override { z = ldlt_.solve(r); }

private:
	Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
	bool                                               analysed_ = false;
	long                                               size_     = -1;
};

} // namespace viscbridge
