// A multigrid cycle for M + Δt D over aggregates of bodies whose coarse unknowns are the aggregates'
// rigid motions (physics.md P15b): the preconditioner whose cost grows linearly with the bodies.
//
// Why rigid motions: at high viscosity Δt D dominates M by 1e3–1e6, and D (nearly) vanishes on the
// rigid motions of any bridged cluster, so those are the error components a local smoother cannot
// remove; any rigid motion of a cluster is, on each aggregate, a rigid motion of that aggregate, so
// the coarse space holds them all.  Each level is built by Galerkin projection (A_c = Pᵀ A P, exact
// for the rigid modes); levels are added until the system is small enough for the sparse Cholesky
// factorisation (CholmodFactor).  The cycle is a symmetric V-cycle (a forward block Gauss–Seidel sweep before the
// coarse correction, a backward one after), hence a symmetric positive definite preconditioner.
// YADE-free.
#pragma once
#include "viscbridge/core/linalg/CholmodFactor.hpp"
#include "viscbridge/core/linalg/BlockRows.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

namespace viscbridge {

class AggregationMultigrid {
public:
	static constexpr int kCoarsestRows = 600; // factorised directly at or below this many block rows

	// The levels of A (pairBranch: per pair of A, centre of j − centre of i; free: per block row the
	// components that are unknowns, whose rows the coarse motions may move), coarsened until at most
	// coarsestRows block rows are left.  False if A is not positive definite.
	bool build(BlockMatrix6 A, std::vector<Vec3> pairBranch, const std::vector<std::array<bool, 6>>& free, int coarsestRows = kCoarsestRows)
	{
		levels_.clear();
		while (A.size() > coarsestRows) {
			Level L;
			if (!L.A.assign(A, pairBranch)) return false;
			std::vector<Vec3> position;
			L.aggregates = aggregate(L.A, L.aggregate, position);
			if (L.aggregates > A.size() * 3 / 4) break; // coarsening stalls (few couplings): factorise what is left
			L.transfer = rigidTransfers(position, levels_.empty() ? &free : nullptr);
			BlockMatrix6 coarse;
			pairBranch = galerkin(A, pairBranch, L, position, coarse);
			A          = std::move(coarse);
			levels_.push_back(std::move(L));
		}
		coarsest_.analyse(A.size(), A.pairs);
		return coarsest_.factorise(A);
	}

	// x ≈ A⁻¹ b by one V-cycle (b, x of length 6 × block rows; x may not alias b).
	void solve(const VecXd& b, VecXd& x) const { cycle(0, b, x); }

	int levels() const { return static_cast<int>(levels_.size()) + 1; }

	// The work of one cycle and of one build, in 6×6 block × 6-vector products (a block triple product
	// of the Galerkin projection is twelve of them), as CholmodFactor counts its own.
	double cycleWork() const
	{
		double w = coarsest_.solveWork();
		for (const Level& L : levels_) // two sweeps and a residual over rows and couplings; restriction and prolongation
			w += 3.0 * static_cast<double>(L.A.couplings() + L.A.size()) + 2.0 * L.A.size();
		return w;
	}
	double buildWork() const
	{
		double w = coarsest_.factorisationWork();
		for (const Level& L : levels_)
			w += 12.0 * static_cast<double>(L.A.couplings() / 2 + L.A.size()) + 6.0 * L.A.size();
		return w;
	}

	// 6×6 blocks kept besides the diagonals: the couplings of each level (one triangle), the transfers, and
	// the coarsest factor.
	size_t storedBlocks() const
	{
		size_t blocks = coarsest_.offDiagonalBlocks();
		for (const Level& L : levels_)
			blocks += L.A.couplings() / 2 + L.transfer.size();
		return blocks;
	}

private:
	struct Level {
		BlockRows         A;
		std::vector<int>  aggregate; // per row
		std::vector<Mat6> transfer;  // per row: its velocities from its aggregate's rigid motion
		int               aggregates = 0;
		mutable VecXd     residual, coarseRhs, coarseX;
	};

	void cycle(size_t l, const VecXd& b, VecXd& x) const
	{
		if (l == levels_.size()) return coarsest_.solve(b, x);
		const Level& L = levels_[l];
		x.setZero(b.size());
		L.A.sweep<true>(b, x);
		L.A.multiply(x, L.residual);
		L.residual = b - L.residual;
		L.coarseRhs.setZero(6 * L.aggregates);
		for (int i = 0; i < L.A.size(); ++i)
			L.coarseRhs.segment<6>(6 * L.aggregate[i]).noalias() += L.transfer[i].transpose() * L.residual.segment<6>(6 * i);
		cycle(l + 1, L.coarseRhs, L.coarseX);
		for (int i = 0; i < L.A.size(); ++i)
			x.segment<6>(6 * i).noalias() += L.transfer[i] * L.coarseX.segment<6>(6 * L.aggregate[i]);
		L.A.sweep<false>(b, x);
	}

	// Greedy aggregation over the couplings: a row whose neighbours are all free becomes a root with
	// its neighbours; a row left over joins a root's aggregate it touches; an isolated row stays alone.
	// position: each row's centre in its aggregate's frame, relative to the aggregate's centroid,
	// summed along the couplings' branches (periodic images are then seen as they are bridged).
	static int aggregate(const BlockRows& A, std::vector<int>& of, std::vector<Vec3>& position)
	{
		const int n = A.size();
		of.assign(n, -1);
		position.assign(n, Vec3::Zero());
		int count = 0;
		for (int i = 0; i < n; ++i) {
			bool alone = of[i] < 0;
			for (int e = A.start[i]; alone && e < A.start[i + 1]; ++e)
				alone = of[A.column[e]] < 0;
			if (!alone) continue;
			of[i] = count;
			for (int e = A.start[i]; e < A.start[i + 1]; ++e)
				of[A.column[e]] = count, position[A.column[e]] = A.branch[e];
			++count;
		}
		const std::vector<int> root = of;
		for (int i = 0; i < n; ++i) {
			if (of[i] >= 0) continue;
			for (int e = A.start[i]; e < A.start[i + 1] && of[i] < 0; ++e)
				if (root[A.column[e]] >= 0) of[i] = root[A.column[e]], position[i] = position[A.column[e]] - A.branch[e];
			if (of[i] < 0) of[i] = count++;
		}
		std::vector<Vec3> centroid(count, Vec3::Zero());
		std::vector<int>  members(count, 0);
		for (int i = 0; i < n; ++i)
			centroid[of[i]] += position[i], ++members[of[i]];
		for (int i = 0; i < n; ++i)
			position[i] -= centroid[of[i]] / members[of[i]];
		return count;
	}

	// T_i: the velocities (v, ω) of row i when its aggregate moves rigidly with (V, Ω) about its
	// centroid, v = V + Ω × r_i, ω = Ω; rows of prescribed components are not moved.
	static std::vector<Mat6> rigidTransfers(const std::vector<Vec3>& position, const std::vector<std::array<bool, 6>>* free)
	{
		std::vector<Mat6> T(position.size());
		for (size_t i = 0; i < position.size(); ++i) {
			const Vec3& r = position[i];
			T[i].setIdentity();
			T[i].topRightCorner<3, 3>() << 0, r.z(), -r.y(), -r.z(), 0, r.x(), r.y(), -r.x(), 0;
			for (int d = 0; free && d < 6; ++d)
				if (!(*free)[i][d]) T[i].row(d).setZero();
		}
		return T;
	}

	// A_c = Pᵀ A P over the aggregates, pairs sorted (duplicates summed), and the coarse pairs' branches
	// (centroid of b − centroid of a = branch_ij + r_i − r_j for any coupling i ∈ a, j ∈ b).  A
	// coarse component that nothing moves (a lone body's blocked rotation) gets a unit diagonal.
	static std::vector<Vec3> galerkin(const BlockMatrix6& A, const std::vector<Vec3>& pairBranch, const Level& L, const std::vector<Vec3>& position,
	                                  BlockMatrix6& coarse)
	{
		const auto& of = L.aggregate;
		const auto& T  = L.transfer;
		coarse.diagonal.assign(L.aggregates, Mat6::Zero());
		for (int i = 0; i < A.size(); ++i)
			coarse.diagonal[of[i]].noalias() += T[i].transpose() * A.diagonal[i] * T[i];
		struct Entry {
			std::pair<int, int> pair;
			Mat6                block;
			Vec3                branch;
		};
		std::vector<Entry> entries;
		for (size_t p = 0; p < A.pairs.size(); ++p) {
			const auto [i, j] = A.pairs[p];
			const int  a = of[i], b = of[j];
			const Mat6 B = T[i].transpose() * A.upper[p] * T[j];
			if (a == b) coarse.diagonal[a] += B + B.transpose();
			else {
				const Vec3 r = pairBranch[p] + position[i] - position[j];
				entries.push_back(a < b ? Entry { { a, b }, B, r } : Entry { { b, a }, B.transpose(), -r });
			}
		}
		std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) { return x.pair < y.pair; });
		std::vector<Vec3> branch;
		for (const Entry& e : entries) {
			if (!coarse.pairs.empty() && coarse.pairs.back() == e.pair) coarse.upper.back() += e.block;
			else {
				coarse.pairs.push_back(e.pair);
				coarse.upper.push_back(e.block);
				branch.push_back(e.branch);
			}
		}
		for (Mat6& D : coarse.diagonal)
			for (int d = 0; d < 6; ++d)
				if (D(d, d) == 0) D(d, d) = 1;
		return branch;
	}

	std::vector<Level> levels_;
	CholmodFactor      coarsest_;
};

} // namespace viscbridge
