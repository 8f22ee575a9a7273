// A symmetric matrix of 6×6 blocks stored by rows (both triangles), with the branch vector of each
// coupling (centre of body j − centre of body i): the form the multigrid's smoother sweeps and its
// aggregation reads (AggregationMultigrid.hpp, physics.md P15b).  YADE-free.
#pragma once
#include "viscbridge/core/linalg/BlockMatrix6.hpp"
#include "viscbridge/core/linalg/Types.hpp"
#include <Eigen/Cholesky>
#include <numeric>
#include <vector>

namespace viscbridge {

struct BlockRows {
	std::vector<int>  start;            // row i's couplings: start[i] … start[i+1]
	std::vector<int>  column;           // per coupling: the other row
	std::vector<Mat6> block;            // A_ij
	std::vector<Vec3> branch;           // centre of j − centre of i
	std::vector<Mat6> diagonal;         // A_ii
	std::vector<Mat6> inverseDiagonal;  // A_ii⁻¹

	// From A and the branch of each of its pairs (i < j: centre of j − centre of i).  False if a
	// diagonal block is not positive definite.
	bool assign(const BlockMatrix6& A, const std::vector<Vec3>& pairBranch)
	{
		const int n = A.size();
		start.assign(n + 1, 0);
		for (const auto& [i, j] : A.pairs)
			++start[i + 1], ++start[j + 1];
		std::partial_sum(start.begin(), start.end(), start.begin());
		column.resize(start[n]);
		block.resize(start[n]);
		branch.resize(start[n]);
		std::vector<int> fill(start.begin(), start.end() - 1);
		for (size_t p = 0; p < A.pairs.size(); ++p) {
			const auto [i, j] = A.pairs[p];
			put(fill[i]++, j, A.upper[p], pairBranch[p]);
			put(fill[j]++, i, A.upper[p].transpose(), -pairBranch[p]);
		}
		diagonal = A.diagonal;
		inverseDiagonal.resize(n);
		for (int i = 0; i < n; ++i) {
			const Eigen::LLT<Mat6> llt(A.diagonal[i]);
			if (llt.info() != Eigen::Success) return false;
			inverseDiagonal[i] = llt.solve(Mat6::Identity());
		}
		return true;
	}

	int size() const { return static_cast<int>(inverseDiagonal.size()); }

	// Row i of (A − diag A) x.
	Vec6 offDiagonalRow(int i, const VecXd& x) const
	{
		Vec6 s = Vec6::Zero();
		for (int e = start[i]; e < start[i + 1]; ++e)
			s.noalias() += block[e] * x.segment<6>(6 * column[e]);
		return s;
	}

	// y = A x.
	void multiply(const VecXd& x, VecXd& y) const
	{
		y.resize(x.size());
		for (int i = 0; i < size(); ++i)
			y.segment<6>(6 * i) = diagonal[i] * x.segment<6>(6 * i) + offDiagonalRow(i, x);
	}

	// One block Gauss–Seidel sweep for A x = b over the rows in increasing (Forward) or decreasing
	// order: each row's block solved with the newest values of the others.  A forward sweep followed by
	// a backward one is a symmetric smoother (the multigrid cycle stays a valid CG preconditioner).
	template <bool Forward> void sweep(const VecXd& b, VecXd& x) const
	{
		const int n = size();
		for (int k = 0; k < n; ++k) {
			const int i          = Forward ? k : n - 1 - k;
			x.segment<6>(6 * i) = inverseDiagonal[i] * (b.segment<6>(6 * i) - offDiagonalRow(i, x));
		}
	}

	// Off-diagonal blocks (both triangles): the cost of a sweep, in block × vector products.
	size_t couplings() const { return column.size(); }

private:
	void put(int e, int other, const Mat6& B, const Vec3& r)
	{
		column[e] = other;
		block[e]  = B;
		branch[e] = r;
	}
};

} // namespace viscbridge
