// A sparse Cholesky factorisation A = L Lᵀ of a symmetric positive definite matrix of 6×6 blocks by
// SuiteSparse's CHOLMOD (through Eigen's CholmodSupport): supernodal where the factor is dense
// enough, so the factorisation and the sweeps run as dense BLAS kernels on groups of columns, and
// simplicial (plain loops, no BLAS call per column group) on a sparse factor, where a supernodal
// sweep is mostly BLAS call overhead (docs/performance.md §4: 300-sphere bed).  The choice is CHOLMOD's
// own rule, flops per factor entry against `supernodal_switch`, with the switch moved from its
// default 40 to kSupernodalSwitch.  The fill-reducing order is CHOLMOD's (AMD, or METIS where that
// fills less).  It replaced a hand-written block factorisation that it beats 9–66× in factorisation
// and 5–8× in the sweeps from 10³ to 10⁴ bodies (docs/performance.md §3).  YADE-free.
//
//   analyse(n, pairs)  the order and the structure of L, for n block rows coupled by `pairs` (i < j)
//   factorise(A)       the numbers, for a matrix of the analysed pattern
//   solve(b, x)        x = A⁻¹ b (b a vector, or a matrix of several right-hand sides)
//
// Every coupling is stored as a full 6×6 block (zeros included), so that the scalar pattern, and
// with it the analysis, depends on the block pattern only.
#pragma once
#include "viscbridge/core/linalg/BlockMatrix6.hpp"
#include "viscbridge/core/util/BlasThreads.hpp"
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace viscbridge {

class CholmodFactor {
public:
	void analyse(int n, const std::vector<std::pair<int, int>>& pairs)
	{
		below_.assign(n, {});
		for (size_t p = 0; p < pairs.size(); ++p)
			below_[pairs[p].first].push_back({ pairs[p].second, static_cast<int>(p) });
		for (auto& column : below_)
			std::sort(column.begin(), column.end());
		pairCount_  = pairs.size();
		factorised_ = false;
		if (n == 0) { // every body prescribed: nothing to factorise (CHOLMOD does not take an empty matrix)
			analysed_ = true;
			return;
		}
		fillLower(nullptr);
		cholmod_common& c    = llt_.cholmod();
		c.supernodal         = CHOLMOD_AUTO;
		c.supernodal_switch  = kSupernodalSwitch;
		c.final_asis         = 0; // a simplicial factor LLᵀ too, not LDLᵀ: an indefinite A is refused
		c.final_ll           = 1;
		c.final_super        = 1;
		llt_.analyzePattern(lower_);
		analysed_ = llt_.info() == Eigen::Success;
		blasThreads_ = analysed_ && factorBytes() >= kThreadedBlasBytes ? maxThreads() : 1;
	}

	// False if A is not positive definite (or not of the analysed pattern).
	bool factorise(const BlockMatrix6& A)
	{
		if (!analysed_ || A.size() != size() || A.pairs.size() != pairCount_) return factorised_ = false;
		if (size() == 0) return factorised_ = true;
		fillLower(&A);
		setBlasThreads(blasThreads_);
		llt_.factorize(lower_);
		return factorised_ = llt_.info() == Eigen::Success;
	}

	void solve(const VecXd& b, VecXd& x) const { solveDense(b, x); }
	// X = A⁻¹ B, one sweep over the factor for all of B's columns (CHOLMOD solves a dense block).
	void solve(const MatXd& B, MatXd& X) const { solveDense(B, X); }

	// The threads the BLAS runs this factor's calls on: all of OpenMP's for a factor of at least
	// kThreadedBlasBytes, whose supernodes give BLAS threads work, else one.
	int  blasThreadsUsed() const { return blasThreads_; }
	bool analysed() const { return analysed_; }
	bool factorised() const { return factorised_; }
	bool supernodal() const { return llt_.supernodal(); } // else simplicial (kSupernodalSwitch)
	int  size() const { return static_cast<int>(below_.size()); }
	// 6×6 blocks' worth of L below its diagonal blocks (fill included), from CHOLMOD's count of L's entries.
	size_t offDiagonalBlocks() const { return static_cast<size_t>(std::max(0.0, (lnz() - 21.0 * size()) / 36.0)); }
	// Bytes L will take once factorised (its numbers and CHOLMOD's integer pattern), known from the
	// analysis: a supernodal factor stores each supernode's columns dense (xsize numbers, ssize row
	// indices), a simplicial one its lnz entries with a row index each.
	size_t factorBytes() const
	{
		if (size() == 0 || !analysed_) return 0;
		const cholmod_factor& L = *llt_.factor();
		const double entries = L.is_super ? static_cast<double>(L.xsize) : lnz();
		const double indices = L.is_super ? static_cast<double>(L.ssize) : lnz();
		return static_cast<size_t>(entries * sizeof(double) + indices * sizeof(int));
	}
	// The work of one factorisation and of one solve in 6×6 block × 6-vector products (72 flops), from
	// CHOLMOD's flop count and L's entries, at the supernodal factor's speed: what the implicit solver
	// weighs to decide when a refresh pays.
	double factorisationWork() const
	{
		return size() == 0 ? 0.0 : const_cast<CholmodLLT&>(llt_).cholmod().fl / 72.0 * (supernodal() ? 1.0 : kSimplicialFactorisationTime);
	}
	double solveWork() const { return 4.0 * lnz() / 72.0 * (supernodal() ? 1.0 : kSimplicialSweepTime); }
	// A simplicial factor's time against a supernodal one's of the same flops, measured on the
	// 300-sphere settling bed (docs/performance.md §4): its factorisation 1.5× slower (no BLAS-3), its
	// sweeps 0.65× (no BLAS call per supernode).
	static constexpr double kSimplicialFactorisationTime = 1.5, kSimplicialSweepTime = 0.65;

private:
	// CHOLMOD's factor, with the kind CHOLMOD chose for it readable
	class CholmodLLT : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
	public:
		bool                  supernodal() const { return m_cholmodFactor && m_cholmodFactor->is_super; }
		const cholmod_factor* factor() const { return m_cholmodFactor; }
	};
	// Flops per factor entry below which the factor is simplicial.  Measured (docs/performance.md §4):
	// the 300-sphere settling bed (up to ~45) is 12 % faster simplicial (sweeps 1.5× faster, refresh
	// 1.5× slower); the wetted 1000-sphere random bed (~300) is 3× slower simplicial (refresh 4.5×).
	static constexpr double kSupernodalSwitch = 100;
	// Factor size from which OpenBLAS's threads pay for the cores they take from OpenMP's loops while
	// they spin after a call (core/util/BlasThreads.hpp).  Measured on two cores (docs/performance.md
	// §2): at 200 MB and 1.3 GB of factor the implicit step on two threads took 0.53× and 0.93× of one
	// thread's with OpenBLAS on two, 0.98× and 1.10× with it on one (and the factorisation alone was
	// 9 % slower on two); at 9.5 GB two BLAS threads factorise 1.33× and sweep 1.09× faster.
	static constexpr double kThreadedBlasBytes = 4e9;
	static int              maxThreads()
	{
#ifdef _OPENMP
		return omp_get_max_threads();
#else
		return 1;
#endif
	}

	template <class Dense>
	void solveDense(const Dense& B, Dense& X) const
	{
		if (size() == 0) {
			X.resize(0, B.cols());
			return;
		}
		setBlasThreads(blasThreads_);
		X = llt_.solve(B);
	}

	double lnz() const { return size() == 0 ? 0.0 : const_cast<CholmodLLT&>(llt_).cholmod().lnz; }

	// The lower triangle, column by column: the diagonal block's rows from the column down, then the
	// blocks below it (Aᵀ of the pair's upper block).  A = nullptr: the pattern, with zeros.
	void fillLower(const BlockMatrix6* A)
	{
		const int n = size();
		lower_.resize(6 * n, 6 * n);
		lower_.reserve(21 * n + 36 * static_cast<long>(pairCount_));
		for (int J = 0; J < n; ++J)
			for (int c = 0; c < 6; ++c) {
				const int col = 6 * J + c;
				lower_.startVec(col);
				for (int r = c; r < 6; ++r)
					lower_.insertBack(6 * J + r, col) = A ? A->diagonal[J](r, c) : 0.0;
				for (const auto& [I, p] : below_[J])
					for (int r = 0; r < 6; ++r)
						lower_.insertBack(6 * I + r, col) = A ? A->upper[p](c, r) : 0.0;
			}
		lower_.finalize();
	}

	std::vector<std::vector<std::pair<int, int>>> below_; // per block column: (block row below, pair index), by row
	size_t                                       pairCount_ = 0;
	Eigen::SparseMatrix<double>                  lower_;
	CholmodLLT                                   llt_;
	bool                                         analysed_ = false, factorised_ = false;
	int                                          blasThreads_ = 1;
};

} // namespace viscbridge
