// A sparse Cholesky factorisation A = L Lᵀ of a symmetric positive definite matrix made of 6×6 blocks
// (one block row per body: its velocity and angular velocity), the implicit solver's preconditioner
// (physics.md §4).  Working on whole blocks instead of scalars lets Eigen's fixed-size 6×6 kernels
// do the arithmetic: the same fill, a fraction of the index work.  YADE-free.
//
//   analyse(n, pairs)  ordering (approximate minimum degree over the body graph) and the structure of L
//   factorise(A)       the numbers, for a matrix of the analysed pattern (left-looking, by columns)
//   solve(b, x)        x = A⁻¹ b by the two triangular solves
//
// Large systems (≥ kSplitBodies block rows) are first bisected: two halves that share no coupling and
// the rows that separate them, eliminated last.  The halves' columns of L then depend on their own
// half only, so two threads factorise and solve them side by side; the arithmetic is the same on any
// number of threads (the order does not depend on it), so are the results.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <queue>
#include <utility>
#include <vector>

namespace viscbridge {

using Mat6  = Eigen::Matrix<double, 6, 6>;
using VecXd = Eigen::VectorXd;

// The block products of the factorisation and the solves, on the column-major 6×6 storage.  YADE
// builds (and so this plugin must build) Eigen with EIGEN_DONT_VECTORIZE, so they are written with
// GCC's vector extensions: a 6-row column is three pairs of doubles (SSE2, any x86-64) or, where the
// caller is compiled for AVX2 + FMA (`Wide`), four and two.  Each product accumulates on its own and
// is subtracted once, so that the blocks of a row do not wait for each other.
namespace block {
#if defined(__GNUC__)
#define VISCBRIDGE_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define VISCBRIDGE_ALWAYS_INLINE inline
#endif
	typedef double Lanes4 __attribute__((vector_size(32)));
	typedef double Lanes2 __attribute__((vector_size(16)));
	// (By reference: a 32-byte vector passed by value outside AVX code would change the ABI.)
	template <class Lanes> VISCBRIDGE_ALWAYS_INLINE void load(Lanes& v, const double* p) { __builtin_memcpy(&v, p, sizeof v); }
	// p = v (assign) or p −= v
	template <bool assign, class Lanes> VISCBRIDGE_ALWAYS_INLINE void storeTo(double* p, const Lanes& v)
	{
		Lanes out = v;
		if constexpr (!assign) {
			load(out, p);
			out -= v;
		}
		__builtin_memcpy(p, &out, sizeof out);
	}
	// acc = (first) or += the Lanes-wide part of a column starting at `column`, times y_c
	template <class Lanes, bool first> VISCBRIDGE_ALWAYS_INLINE void accumulate(Lanes& acc, const double* column, double yc)
	{
		Lanes v;
		load(v, column);
		if constexpr (first) acc = v * yc;
		else acc += v * yc;
	}

	// s = B y (assign) or s −= B y
	template <bool Wide, bool assign> VISCBRIDGE_ALWAYS_INLINE void productTo(double* __restrict s, const double* __restrict B, const double* __restrict y)
	{
		if constexpr (Wide) {
			Lanes4 a;
			Lanes2 b;
			accumulate<Lanes4, true>(a, B, y[0]);
			accumulate<Lanes2, true>(b, B + 4, y[0]);
			for (int c = 1; c < 6; ++c) {
				accumulate<Lanes4, false>(a, B + 6 * c, y[c]);
				accumulate<Lanes2, false>(b, B + 6 * c + 4, y[c]);
			}
			storeTo<assign>(s, a);
			storeTo<assign>(s + 4, b);
		} else {
			Lanes2 a[3];
			for (int h = 0; h < 3; ++h)
				accumulate<Lanes2, true>(a[h], B + 2 * h, y[0]);
			for (int c = 1; c < 6; ++c)
				for (int h = 0; h < 3; ++h)
					accumulate<Lanes2, false>(a[h], B + 6 * c + 2 * h, y[c]);
			for (int h = 0; h < 3; ++h)
				storeTo<assign>(s + 2 * h, a[h]);
		}
	}
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void subtractProduct(double* __restrict s, const double* B, const double* y) { productTo<Wide, false>(s, B, y); }
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void product(double* __restrict s, const double* B, const double* y) { productTo<Wide, true>(s, B, y); }
	// C = A Bᵀ (assign) or C −= A Bᵀ, column by column: C's column c takes A times B's row c.
	template <bool Wide, bool assign> VISCBRIDGE_ALWAYS_INLINE void outerTo(double* __restrict C, const double* __restrict A, const double* __restrict B)
	{
		for (int c = 0; c < 6; ++c) {
			const double row[6] = { B[c], B[6 + c], B[12 + c], B[18 + c], B[24 + c], B[30 + c] };
			productTo<Wide, assign>(C + 6 * c, A, row);
		}
	}
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void subtractOuter(double* __restrict C, const double* A, const double* B) { outerTo<Wide, false>(C, A, B); }
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void outer(double* __restrict C, const double* A, const double* B) { outerTo<Wide, true>(C, A, B); }
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
		separatorStructure();
		placePairs(pairs);
		countUpdates();
		lower_.assign(rows_.size(), Mat6::Zero());
		transposed_.assign(rows_.size(), Mat6::Zero());
		inverseDiagonal_.assign(n, Mat6::Zero());
		inverseDiagonalTransposed_.assign(n, Mat6::Zero());
		for (auto& w : where_)
			w.assign(n, -1);
		work_.resize(6 * n);
		analysed_ = true;
	}

	// The factor of A, whose pattern must be the analysed one (pairs in the same order).  False if A
	// is not positive definite.
	bool factorise(const BlockMatrix6& A)
	{
		if (!analysed_ || A.size() != static_cast<int>(order_.size()) || A.pairs.size() != pairTarget_.size()) return false;
		return (factorised_ = wideLanes() ? factoriseWide(A) : factoriseAnyCpu(A));
	}

	// x = A⁻¹ b, with block row i of A at block blockOf[i] of b and x (x may not alias b; its other
	// blocks are left as they are).
	void solve(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const
	{
		if (wideLanes()) return solveWide(b, x, blockOf);
		solveAnyCpu(b, x, blockOf);
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

	// The work of one factorisation and of one solve, in 6×6 block × 6-vector products (a block update
	// is six of them): what the implicit solver weighs to decide when a refresh pays.
	double factorisationWork() const { return 6.0 * static_cast<double>(updates_ + rows_.size()); }
	double solveWork() const { return 2.0 * static_cast<double>(order_.size() + rows_.size()); }

	bool   factorised() const { return factorised_; }
	int    size() const { return static_cast<int>(order_.size()); }
	size_t offDiagonalBlocks() const { return rows_.size(); } // of L, fill included
	// Rows of the two halves that are factorised side by side (0 and 0: not bisected).
	std::array<int, 2> halves() const { return { parts_[1] - parts_[0], parts_[2] - parts_[1] }; }

	static constexpr int kSplitBodies = 1000; // below this, one thread and plain AMD order

private:
	// The two sweeps, each half's rows and columns side by side, then the separator's.  The sweeps and
	// the factorisation are compiled twice: for any x86-64 (SSE2) and for AVX2 + FMA (`Wide`, chosen at
	// run time; half the instructions).  FMA rounds once where SSE2 rounds twice, so the two builds
	// differ in the last bits; on one machine the results do not depend on the thread count.
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void sweeps(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const
	{
#pragma omp parallel for schedule(static, 1) if (parts_[1] > 0)
		for (int half = 0; half < 2; ++half) {
			forward<Wide>(parts_[half], parts_[half + 1], b, blockOf);
			separatorPull<Wide>(half);
		}
		forward<Wide>(parts_[2], parts_[3], b, blockOf);
		backward<Wide>(parts_[2], parts_[3], x, blockOf);
#pragma omp parallel for schedule(static, 1) if (parts_[1] > 0)
		for (int half = 0; half < 2; ++half)
			backward<Wide>(parts_[half], parts_[half + 1], x, blockOf);
	}
	void solveAnyCpu(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const { sweeps<false>(b, x, blockOf); }
	bool factoriseAnyCpu(const BlockMatrix6& A) { return factoriseAll<false>(A); }
#if defined(__GNUC__) && defined(__x86_64__)
	__attribute__((target("avx2,fma"))) void solveWide(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const { sweeps<true>(b, x, blockOf); }
	__attribute__((target("avx2,fma"))) bool factoriseWide(const BlockMatrix6& A) { return factoriseAll<true>(A); }
	static bool wideLanes()
	{
		static const bool wide = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
		return wide;
	}
#else
	void        solveWide(const VecXd& b, VecXd& x, const std::vector<int>& blockOf) const { solveAnyCpu(b, x, blockOf); }
	bool        factoriseWide(const BlockMatrix6& A) { return factoriseAnyCpu(A); }
	static bool wideLanes() { return false; }
#endif
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE bool factoriseAll(const BlockMatrix6& A)
	{
		std::fill(lower_.begin(), lower_.end(), Mat6::Zero());
		for (size_t p = 0; p < pairTarget_.size(); ++p)
			lower_[pairTarget_[p]] = pairTransposed_[p] ? Mat6(A.upper[p].transpose()) : A.upper[p];
		std::array<char, 2> ok { 1, 1 };
#pragma omp parallel for schedule(static, 1) if (parts_[1] > 0)
		for (int half = 0; half < 2; ++half)
			for (int j = parts_[half]; j < parts_[half + 1] && ok[half]; ++j)
				ok[half] = factoriseColumn<Wide>(j, A.diagonal[order_[j]], where_[half]);
		for (int j = parts_[2]; j < parts_[3] && ok[0]; ++j)
			ok[0] = factoriseColumn<Wide>(j, A.diagonal[order_[j]], where_[0]);
		if (!ok[0] || !ok[1]) return false;
		for (size_t q = 0; q < lower_.size(); ++q)
			transposed_[q] = lower_[q].transpose();
		for (size_t j = 0; j < inverseDiagonal_.size(); ++j)
			inverseDiagonalTransposed_[j] = inverseDiagonal_[j].transpose();
		return true;
	}

	// L y = b for the rows [first, last) of the eliminated order, each row pulling from the columns
	// before it: a half's rows from their own half; the separator's rows from the separator's
	// columns, the halves' columns having been pulled already by separatorPull.
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void forward(int first, int last, const VecXd& b, const std::vector<int>& blockOf) const
	{
		double* y = work_.data();
		for (int j = first; j < last; ++j) {
			double s[6];
			for (int r = 0; r < 6; ++r)
				s[r] = b[6 * blockOf[order_[j]] + r];
			int e = rowStart_[j];
			if (j >= parts_[2] && parts_[1] > 0) { // a separator row of a bisected system: the halves' part
				const int row = j - parts_[2];
				for (int r = 0; r < 6; ++r)
					s[r] += separatorPartial_[0][6 * row + r] + separatorPartial_[1][6 * row + r];
				e = separatorEntries_[row][2];
			}
			for (; e < rowStart_[j + 1]; ++e)
				block::subtractProduct<Wide>(s, lower_[rowEntry_[e]].data(), y + 6 * rowColumn_[e]);
			block::product<Wide>(y + 6 * j, inverseDiagonal_[j].data(), s); // L_jj⁻¹ s
		}
	}

	// −Σ L_jk y_k over one half's columns k, for every separator row j: the separator's part of the
	// forward sweep that needs only that half, so that the thread of the half does it (it holds about
	// 40 % of the blocks of L on a bisected lattice).  Serial and parallel runs sum it the same way.
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void separatorPull(int half) const
	{
		if (parts_[1] == 0) return; // not bisected
		const double* y       = work_.data();
		double*       partial = separatorPartial_[half].data();
		for (int row = 0; row < parts_[3] - parts_[2]; ++row) {
			double s[6] = { 0, 0, 0, 0, 0, 0 };
			for (int e = separatorEntries_[row][half]; e < separatorEntries_[row][half + 1]; ++e)
				block::subtractProduct<Wide>(s, lower_[rowEntry_[e]].data(), y + 6 * rowColumn_[e]);
			for (int r = 0; r < 6; ++r)
				partial[6 * row + r] = s[r];
		}
	}

	// Lᵀ x = y for the columns [first, last), last first, each pulling from the rows below it (with
	// the transposed blocks, so that both sweeps use the same kernel).
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE void backward(int first, int last, VecXd& x, const std::vector<int>& blockOf) const
	{
		double* y = work_.data();
		for (int j = last - 1; j >= first; --j) {
			double s[6];
			for (int r = 0; r < 6; ++r)
				s[r] = y[6 * j + r];
			for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q)
				block::subtractProduct<Wide>(s, transposed_[q].data(), y + 6 * rows_[q]);
			double* yj = y + 6 * j;
			block::product<Wide>(yj, inverseDiagonalTransposed_[j].data(), s); // L_jj⁻ᵀ s
			for (int r = 0; r < 6; ++r)
				x[6 * blockOf[order_[j]] + r] = yj[r];
		}
	}

	// The elimination order: each part (the two halves, then the separator) in approximate minimum
	// degree order (Eigen's AMD) of its own couplings, so that fill stays low.
	void order(int n, const std::vector<std::pair<int, int>>& pairs)
	{
		std::vector<std::vector<int>> adjacent(n);
		for (const auto& [i, j] : pairs) {
			adjacent[i].push_back(j);
			adjacent[j].push_back(i);
		}
		const std::vector<int> part = n >= kSplitBodies ? bisection(adjacent) : std::vector<int>(n, 2);
		order_.clear();
		for (int p = 0; p < 3; ++p) {
			parts_[p] = static_cast<int>(order_.size());
			std::vector<int> members;
			for (int i = 0; i < n; ++i)
				if (part[i] == p) members.push_back(i);
			const std::vector<int> ordered = minimumDegree(members, adjacent);
			order_.insert(order_.end(), ordered.begin(), ordered.end());
		}
		parts_[3] = n;
		position_.assign(n, 0);
		for (int k = 0; k < n; ++k)
			position_[order_[k]] = k;
	}

	// `members` (rows of one part) in AMD order of the couplings among them.
	static std::vector<int> minimumDegree(const std::vector<int>& members, const std::vector<std::vector<int>>& adjacent)
	{
		const int        m = static_cast<int>(members.size());
		std::vector<int> local(adjacent.size(), -1);
		for (int k = 0; k < m; ++k)
			local[members[k]] = k;
		std::vector<Eigen::Triplet<int>> t;
		for (int k = 0; k < m; ++k) {
			t.emplace_back(k, k, 1);
			for (const int j : adjacent[members[k]])
				if (local[j] >= 0) t.emplace_back(k, local[j], 1);
		}
		Eigen::SparseMatrix<int> graph(m, m);
		graph.setFromTriplets(t.begin(), t.end());
		Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> eliminated; // indices()[k]: the row eliminated k-th
		Eigen::AMDOrdering<int>()(graph, eliminated);
		std::vector<int> out(m);
		for (int k = 0; k < m; ++k)
			out[k] = members[eliminated.indices()[k]];
		return out;
	}

	// Two halves without a coupling between them (part 0 and 1) and their separator (part 2): the
	// breadth-first levels of each connected component from a far node, stacked, cut at the level
	// that holds the middle row — a level touches only its neighbouring levels.
	static std::vector<int> bisection(const std::vector<std::vector<int>>& adjacent)
	{
		const int        n = static_cast<int>(adjacent.size());
		std::vector<int> level(n, -1), sequence;
		sequence.reserve(n);
		for (int start = 0, levels = 0; start < n; ++start) {
			if (level[start] >= 0) continue;
			const size_t first = sequence.size();
			breadthFirst(start, adjacent, level, levels, sequence);
			const int far = sequence.back(); // on the last level: start again from there
			for (size_t k = first; k < sequence.size(); ++k)
				level[sequence[k]] = -1;
			sequence.resize(first);
			breadthFirst(far, adjacent, level, levels, sequence);
			levels = level[sequence.back()] + 1;
		}
		std::vector<int> part(n);
		const int        cut = level[sequence[n / 2]];
		for (int i = 0; i < n; ++i)
			part[i] = level[i] < cut ? 0 : level[i] > cut ? 1 : 2;
		return part;
	}

	// Appends the component of `start` to `sequence` in visiting order, its levels from `offset` on.
	static void breadthFirst(int start, const std::vector<std::vector<int>>& adjacent, std::vector<int>& level, int offset, std::vector<int>& sequence)
	{
		const size_t first = sequence.size();
		level[start]       = offset;
		sequence.push_back(start);
		for (size_t k = first; k < sequence.size(); ++k)
			for (const int j : adjacent[sequence[k]])
				if (level[j] < 0) {
					level[j] = level[sequence[k]] + 1;
					sequence.push_back(j);
				}
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

	// Where each separator row's blocks in half 0's, half 1's and the separator's columns begin (a
	// row's blocks are in column order, and the parts are eliminated one after the other).
	void separatorStructure()
	{
		const int rows = parts_[1] > 0 ? parts_[3] - parts_[2] : 0; // only a bisected system has halves
		separatorEntries_.resize(rows);
		for (int j = parts_[2]; j < parts_[2] + rows; ++j) {
			const auto first = rowColumn_.begin() + rowStart_[j], last = rowColumn_.begin() + rowStart_[j + 1];
			auto&      split = separatorEntries_[j - parts_[2]];
			for (int part = 0; part < 3; ++part)
				split[part] = static_cast<int>(std::lower_bound(first, last, parts_[part]) - rowColumn_.begin());
		}
		for (auto& p : separatorPartial_)
			p.setZero(6 * rows);
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
	template <bool Wide> VISCBRIDGE_ALWAYS_INLINE bool factoriseColumn(int j, const Mat6& diagonal, std::vector<int>& where)
	{
		for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q)
			where[rows_[q]] = q;
		Mat6 d = diagonal;
		for (int e = rowStart_[j]; e < rowStart_[j + 1]; ++e) {
			const int   k = rowColumn_[e], q0 = rowEntry_[e];
			const Mat6& ljk = lower_[q0];
			block::subtractOuter<Wide>(d.data(), ljk.data(), ljk.data());
			for (int q = q0 + 1; q < columnStart_[k + 1]; ++q) // rows below j in column k are rows of column j
				block::subtractOuter<Wide>(lower_[where[rows_[q]]].data(), lower_[q].data(), ljk.data());
		}
		const Eigen::LLT<Mat6> llt(d);
		if (llt.info() != Eigen::Success) return false;
		invertLower(llt.matrixLLT(), inverseDiagonal_[j]);
		for (int q = columnStart_[j]; q < columnStart_[j + 1]; ++q) {
			const Mat6 a = lower_[q]; // L_qj = A_qj L_jj⁻ᵀ
			block::outer<Wide>(lower_[q].data(), a.data(), inverseDiagonal_[j].data());
			where[rows_[q]] = -1;
		}
		return true;
	}

	// The block updates C −= A Bᵀ of a factorisation: per block (j, k) of L, one on the diagonal block
	// of j and one per block below j in column k (factoriseColumn).
	void countUpdates()
	{
		updates_ = 0;
		for (size_t e = 0; e < rowEntry_.size(); ++e)
			updates_ += static_cast<size_t>(columnStart_[rowColumn_[e] + 1] - rowEntry_[e]);
	}

	// X = L⁻¹ for the lower triangle L of `l`, by columns (Eigen's triangular solve takes its general,
	// blocked path for a 6×6 and cost a fifth of the factorisation).
	static void invertLower(const Mat6& l, Mat6& X)
	{
		X.setZero();
		for (int c = 0; c < 6; ++c) {
			X(c, c) = 1 / l(c, c);
			for (int r = c + 1; r < 6; ++r) {
				double s = 0;
				for (int k = c; k < r; ++k)
					s += l(r, k) * X(k, c);
				X(r, c) = -s / l(r, r);
			}
		}
	}

	std::vector<int>   order_, position_;           // order_[k]: the block row eliminated k-th; position_ its inverse
	std::vector<int>   columnStart_, rows_;         // L below the diagonal, by column: rows ascending
	std::vector<Mat6>  lower_;                      // the blocks, same order as rows_
	std::vector<int>   rowStart_, rowEntry_, rowColumn_; // the same blocks by row
	std::vector<Mat6>  transposed_;                 // the same blocks transposed, for the backward sweep
	std::vector<Mat6>  inverseDiagonal_, inverseDiagonalTransposed_; // L_jj⁻¹ and L_jj⁻ᵀ
	std::vector<int>   pairTarget_;
	std::vector<char>  pairTransposed_;
	std::array<int, 4> parts_ { 0, 0, 0, 0 };       // eliminated order: half 0 [parts_[0], parts_[1]), half 1, separator [parts_[2], parts_[3])
	std::array<std::vector<int>, 2> where_;         // workspace per half: position of a row in the current column
	std::vector<std::array<int, 3>> separatorEntries_; // per separator row: its first block in half 0's, half 1's, the separator's columns
	mutable std::array<VecXd, 2>    separatorPartial_; // per half: −Σ L_jk y_k of the separator rows over its columns (forward sweep)
	mutable VecXd      work_;
	mutable std::vector<int> identity_;            // blockOf for a plain solve
	size_t             updates_  = 0; // block updates of one factorisation
	bool               analysed_ = false, factorised_ = false;
};

} // namespace viscbridge
