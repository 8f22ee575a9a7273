// A sparse Cholesky factorisation A = L Lᵀ of a symmetric positive definite matrix made of 6×6 blocks
// (one block row per body: its velocity and angular velocity), the implicit solver's preconditioner
// (physics.md §4).  Working on whole blocks instead of scalars lets Eigen's fixed-size 6×6 kernels
// do the arithmetic: the same fill, a fraction of the index work.  YADE-free.
//
//   analyse(n, pairs)  ordering (approximate minimum degree over the body graph) and the structure of L
//   factorise(A)       the numbers, for a matrix of the analysed pattern (left-looking, by columns)
//   solve(b, x)        x = A⁻¹ b by the two triangular solves
#pragma once
#include "Vector.hpp"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <utility>
#include <vector>

namespace viscbridge {

using Mat6  = Eigen::Matrix<double, 6, 6>;
using VecXd = Eigen::VectorXd;

// The block products of the factorisation and the solves, as plain loops over the column-major 6×6
// storage: YADE builds (and so this plugin must build) Eigen with EIGEN_DONT_VECTORIZE, and loops
// like these the compiler still vectorises (10 % fewer instructions than Eigen's scalar products
// in the factorisation, measured with callgrind).
namespace block {
	// s −= B y
	inline void subtractProduct(double* __restrict s, const double* __restrict B, const double* __restrict y)
	{
		for (int c = 0; c < 6; ++c)
			for (int r = 0; r < 6; ++r)
				s[r] -= B[6 * c + r] * y[c];
	}
	// s −= Bᵀ y
	inline void subtractTransposedProduct(double* __restrict s, const double* __restrict B, const double* __restrict y)
	{
		for (int c = 0; c < 6; ++c) {
			double d = 0;
			for (int r = 0; r < 6; ++r)
				d += B[6 * c + r] * y[r];
			s[c] -= d;
		}
	}
	// C −= A Bᵀ
	inline void subtractOuter(double* __restrict C, const double* __restrict A, const double* __restrict B)
	{
		for (int k = 0; k < 6; ++k)
			for (int c = 0; c < 6; ++c)
				for (int r = 0; r < 6; ++r)
					C[6 * c + r] -= A[6 * k + r] * B[6 * k + c];
	}
}

// A symmetric matrix of 6×6 blocks: the diagonal blocks and, for each pair (i, j) with i < j, the block
// in row i and column j (the one in row j and column i is its transpose).
struct BlockMatrix6 {
	std::vector<Mat6>                diagonal;
	std::vector<std::pair<int, int>> pairs;
	std::vector<Mat6>                upper;

	int size() const { return static_cast<int>(diagonal.size()); }

	// y = A x (x, y of length 6·size()).
	void multiply(const VecXd& x, VecXd& y) const
	{
		y.resize(6 * size());
		for (int i = 0; i < size(); ++i)
			y.segment<6>(6 * i) = diagonal[i] * x.segment<6>(6 * i);
		for (size_t p = 0; p < pairs.size(); ++p) {
			const auto [i, j] = pairs[p];
			y.segment<6>(6 * i) += upper[p] * x.segment<6>(6 * j);
			y.segment<6>(6 * j) += upper[p].transpose() * x.segment<6>(6 * i);
		}
	}
};

class BlockCholesky {
public:
	// The elimination order and the structure of L for n block rows coupled by `pairs` (i < j).
	void analyse(int n, const std::vector<std::pair<int, int>>& pairs)
	{
		order(n, pairs);
		std::vector<std::vector<int>> below(n); // A's blocks below the diagonal, by column (eliminated order)
		for (const auto& [i, j] : pairs) {
			const int a = position_[i], b = position_[j];
			below[std::min(a, b)].push_back(std::max(a, b));
		}
		columnStructure(below);
		rowStructure();
		placePairs(pairs);
		lower_.assign(rows_.size(), Mat6::Zero());
		inverseDiagonal_.assign(n, Mat6::Zero());
		where_.assign(n, -1);
		work_.resize(6 * n);
		analysed_ = true;
	}

	// The factor of A, whose pattern must be the analysed one (pairs in the same order).  False if A
	// is not positive definite.
	bool factorise(const BlockMatrix6& A)
	{
		if (!analysed_ || A.size() != static_cast<int>(order_.size()) || A.pairs.size() != pairTarget_.size()) return false;
		std::fill(lower_.begin(), lower_.end(), Mat6::Zero());
		for (size_t p = 0; p < pairTarget_.size(); ++p)
			lower_[pairTarget_[p]] = pairTransposed_[p] ? Mat6(A.upper[p].transpose()) : A.upper[p];
		for (int j = 0; j < static_cast<int>(order_.size()); ++j)
			if (!factoriseColumn(j, A.diagonal[order_[j]])) return (factorised_ = false);
		return (factorised_ = true);
	}

	// x = A⁻¹ b, with block row i of A at block blockOf[i] of b and x (x may not alias b; its other
	// blocks are left as they are).
	void solve(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const
	{
		const int n = static_cast<int>(order_.size());
		double*   y = work_.data();
		for (int j = 0; j < n; ++j) { // L y = b, each row pulling from the columns before it
			Vec6 s = b.segment<6>(6 * blockOf[order_[j]]);
			for (int e = rowStart_[j]; e < rowStart_[j + 1]; ++e)
				block::subtractProduct(s.data(), lower_[rowEntry_[e]].data(), y + 6 * rowColumn_[e]);
			Vec6 yj = Vec6::Zero();
			block::subtractProduct(yj.data(), inverseDiagonal_[j].data(), s.data()); // −L_jj⁻¹ s
			Eigen::Map<Vec6>(y + 6 * j) = -yj;
		}
		for (int j = n - 1; j >= 0; --j) { // Lᵀ x = y
			Vec6 s = Eigen::Map<const Vec6>(y + 6 * j);
			for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q)
				block::subtractTransposedProduct(s.data(), lower_[q].data(), y + 6 * rows_[q]);
			Vec6 xj = Vec6::Zero();
			block::subtractTransposedProduct(xj.data(), inverseDiagonal_[j].data(), s.data()); // −L_jj⁻ᵀ s
			xj = -xj;
			Eigen::Map<Vec6>(y + 6 * j)          = xj;
			x.segment<6>(6 * blockOf[order_[j]]) = xj;
		}
	}

	// x = A⁻¹ b (b, x of length 6n; x may not alias b).
	void solve(const VecXd& b, VecXd& x) const
	{
		if (identity_.size() != order_.size()) {
			identity_.resize(order_.size());
			for (size_t i = 0; i < identity_.size(); ++i)
				identity_[i] = static_cast<int>(i);
		}
		x.resize(6 * size());
		solve(b, x, identity_);
	}

	bool   factorised() const { return factorised_; }
	int    size() const { return static_cast<int>(order_.size()); }
	size_t offDiagonalBlocks() const { return rows_.size(); } // of L, fill included

private:
	// Approximate minimum degree on the body graph (Eigen's AMD), so that fill stays low.
	void order(int n, const std::vector<std::pair<int, int>>& pairs)
	{
		std::vector<Eigen::Triplet<int>> t;
		t.reserve(2 * pairs.size() + n);
		for (int i = 0; i < n; ++i)
			t.emplace_back(i, i, 1);
		for (const auto& [i, j] : pairs) {
			t.emplace_back(i, j, 1);
			t.emplace_back(j, i, 1);
		}
		Eigen::SparseMatrix<int> graph(n, n);
		graph.setFromTriplets(t.begin(), t.end());
		Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> eliminated; // indices()[k]: the row eliminated k-th
		Eigen::AMDOrdering<int>()(graph, eliminated);
		order_.assign(eliminated.indices().data(), eliminated.indices().data() + n);
		position_.assign(n, 0);
		for (int k = 0; k < n; ++k)
			position_[order_[k]] = k;
	}

	// Rows of each column of L: A's own, and those its elimination-tree children pass up.
	void columnStructure(std::vector<std::vector<int>>& below)
	{
		const int                     n = static_cast<int>(below.size());
		std::vector<std::vector<int>> passed(n);
		columnStart_.assign(n + 1, 0);
		rows_.clear();
		for (int j = 0; j < n; ++j) {
			std::vector<int>& s = below[j];
			s.insert(s.end(), passed[j].begin(), passed[j].end());
			std::sort(s.begin(), s.end());
			s.erase(std::unique(s.begin(), s.end()), s.end());
			rows_.insert(rows_.end(), s.begin(), s.end());
			columnStart_[j + 1] = static_cast<int>(rows_.size());
			if (!s.empty()) passed[s.front()].insert(passed[s.front()].end(), s.begin() + 1, s.end()); // to the parent
			std::vector<int>().swap(passed[j]);
			std::vector<int>().swap(s);
		}
	}

	// The blocks of each row of L (column, index into lower_), in column order.
	void rowStructure()
	{
		const int n = static_cast<int>(order_.size());
		rowStart_.assign(n + 1, 0);
		for (const int r : rows_)
			++rowStart_[r + 1];
		for (int i = 0; i < n; ++i)
			rowStart_[i + 1] += rowStart_[i];
		rowEntry_.resize(rows_.size());
		rowColumn_.resize(rows_.size());
		std::vector<int> fill(rowStart_.begin(), rowStart_.end() - 1);
		for (int k = 0; k < n; ++k)
			for (int q = columnStart_[k]; q < columnStart_[k + 1]; ++q) {
				rowEntry_[fill[rows_[q]]]    = q;
				rowColumn_[fill[rows_[q]]++] = k;
			}
	}

	// Where each of A's pairs lands in L (and whether as its transpose).
	void placePairs(const std::vector<std::pair<int, int>>& pairs)
	{
		pairTarget_.resize(pairs.size());
		pairTransposed_.resize(pairs.size());
		for (size_t p = 0; p < pairs.size(); ++p) {
			const int a = position_[pairs[p].first], b = position_[pairs[p].second];
			const int column = std::min(a, b), row = std::max(a, b);
			const auto first = rows_.begin() + columnStart_[column], last = rows_.begin() + columnStart_[column + 1];
			pairTarget_[p]     = static_cast<int>(std::lower_bound(first, last, row) - rows_.begin());
			pairTransposed_[p] = a < b; // block (i, j) sits above the diagonal in the eliminated order
		}
	}

	// Column j of L from A's column and the columns k < j that have a block in row j.
	bool factoriseColumn(int j, const Mat6& diagonal)
	{
		for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q)
			where_[rows_[q]] = q;
		Mat6 d = diagonal;
		for (int e = rowStart_[j]; e < rowStart_[j + 1]; ++e) {
			const int   k = rowColumn_[e], q0 = rowEntry_[e];
			const Mat6& ljk = lower_[q0];
			block::subtractOuter(d.data(), ljk.data(), ljk.data());
			for (int q = q0 + 1; q < columnStart_[k + 1]; ++q) // rows below j in column k are rows of column j
				block::subtractOuter(lower_[where_[rows_[q]]].data(), lower_[q].data(), ljk.data());
		}
		const Eigen::LLT<Mat6> llt(d);
		if (llt.info() != Eigen::Success) return false;
		inverseDiagonal_[j] = llt.matrixL().solve(Mat6::Identity());
		for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q) {
			lower_[q] = lower_[q] * inverseDiagonal_[j].transpose();
			where_[rows_[q]] = -1;
		}
		return true;
	}

	std::vector<int>   order_, position_;           // order_[k]: the block row eliminated k-th; position_ its inverse
	std::vector<int>   columnStart_, rows_;         // L below the diagonal, by column: rows ascending
	std::vector<Mat6>  lower_;                      // the blocks, same order as rows_
	std::vector<int>   rowStart_, rowEntry_, rowColumn_; // the same blocks by row
	std::vector<Mat6>  inverseDiagonal_;            // L_jj⁻¹
	std::vector<int>   pairTarget_;
	std::vector<char>  pairTransposed_;
	std::vector<int>   where_;                      // workspace: position of a row in the current column
	mutable VecXd      work_;
	mutable std::vector<int> identity_;            // blockOf for a plain solve
	bool               analysed_ = false, factorised_ = false;
};

} // namespace viscbridge
