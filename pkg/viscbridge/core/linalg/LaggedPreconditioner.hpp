// Preconditioners computed from an earlier step's matrix M + Δt D and kept over several steps (the
// implicit solver decides when to refresh them, physics.md §4): the sparse Cholesky factor, exact
// when fresh, whose fill grows faster than the bodies; and the aggregation multigrid (P15b), whose
// cost grows linearly.  Both work on the block rows of the bodies with a free component.  YADE-free.
#pragma once
#include "viscbridge/core/linalg/AggregationMultigrid.hpp"
#include "viscbridge/core/linalg/CholmodFactor.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include <array>
#include <vector>

namespace viscbridge {

class LaggedPreconditioner : public Preconditioner {
public:
	// Recomputes it from the system's matrix (samePattern: the same bodies, bridges and free
	// components as at the last refresh, so an analysis may be kept).  False if the matrix is not
	// positive definite.
	virtual bool refresh(const ImplicitViscousSystem& system, bool samePattern) = 0;
	bool         matches(size_t size) const { return ready_ && size_ == size; }
	// A refresh's cost in CG iterations of a system of `bridges` bridges: the refresh and the assembly
	// against one iteration (one application and a product), counted in block × vector products from
	// the structure, so that the decision is the same on every run.  Per bridge, the assembly costs
	// about 25 and a product 5 of them (wall time on the settling bed, docs/performance.md §4).
	double refreshCost(size_t bridges) const
	{
		const double b = static_cast<double>(bridges);
		return (refreshWork() + 25 * b) / (applicationWork() + 5 * b);
	}
	virtual size_t storedBlocks() const = 0; // 6×6 blocks below the diagonal it keeps (memory)
	virtual int    levels() const { return 1; }
	virtual const char* factorKind() const { return ""; } // the Cholesky factor's: "supernodal" or "simplicial"

	// z ≈ A⁻¹ r: r's blocks of the rows' bodies gathered, solved on the rows, scattered back.
	void apply(const VecXd& r, VecXd& z) const override
	{
		onRows(r, z, rows_, solution_, [this](const VecXd& b, VecXd& x) { solveRows(b, x); });
	}

protected:
	// The system's block matrix, and which body each block row is.
	BlockMatrix6 blockRows(const ImplicitViscousSystem& system, std::vector<Vec3>* pairBranch = nullptr)
	{
		std::vector<int>   rowOfBody;
		const BlockMatrix6 A = system.blockMatrix(rowOfBody, pairBranch);
		size_                = system.size();
		bodyOfRow_.assign(A.size(), 0);
		prescribedBodies_.clear();
		for (size_t i = 0; i < rowOfBody.size(); ++i) {
			if (rowOfBody[i] >= 0) bodyOfRow_[rowOfBody[i]] = static_cast<int>(i);
			else prescribedBodies_.push_back(static_cast<int>(i));
		}
		return A;
	}
	virtual double refreshWork() const                              = 0;
	virtual double applicationWork() const                          = 0;
	virtual void   solveRows(const VecXd& b, VecXd& x) const = 0; // x ≈ A⁻¹ b on the block rows
	// r's blocks of the rows' bodies gathered (a column per right-hand side), solved on the rows by
	// solve(rows, solution), scattered back; zero on the bodies without a free component.
	template <class M, class Solve> void onRows(const M& r, M& z, M& rows, M& solution, Solve solve) const
	{
		z.resize(r.rows(), r.cols());
		for (const int i : prescribedBodies_)
			z.template middleRows<6>(6 * i).setZero();
		rows.resize(6 * bodyOfRow_.size(), r.cols());
		for (size_t i = 0; i < bodyOfRow_.size(); ++i)
			rows.template middleRows<6>(6 * i) = r.template middleRows<6>(6 * bodyOfRow_[i]);
		solve(rows, solution);
		for (size_t i = 0; i < bodyOfRow_.size(); ++i)
			z.template middleRows<6>(6 * bodyOfRow_[i]) = solution.template middleRows<6>(6 * i);
	}

	std::vector<int> bodyOfRow_, prescribedBodies_; // the system's body of each block row; bodies without a free component
	size_t           size_  = 0;
	bool             ready_ = false;

private:
	mutable VecXd rows_, solution_; // workspace of an application
};

class LaggedCholesky : public LaggedPreconditioner {
public:
	bool refresh(const ImplicitViscousSystem& system, bool samePattern) override
	{
		analyse(system, samePattern);
		return factorise();
	}
	// A refresh in two halves, so that the factor's size is known before its memory is taken: the
	// system's matrix assembled and its pattern analysed (the analysis kept if samePattern) ...
	void analyse(const ImplicitViscousSystem& system, bool samePattern)
	{
		assembled_ = blockRows(system);
		if (!samePattern || !factor_.factorised() || factor_.size() != assembled_.size()) factor_.analyse(assembled_.size(), assembled_.pairs);
	}
	size_t factorBytes() const { return factor_.factorBytes(); } // of the analysed factor
	// ... then the numbers; false if the matrix is not positive definite.
	bool factorise()
	{
		ready_     = factor_.factorise(assembled_);
		assembled_ = BlockMatrix6();
		return ready_;
	}
	size_t      storedBlocks() const override { return factor_.offDiagonalBlocks(); }
	const char* factorKind() const override { return factor_.supernodal() ? "supernodal" : "simplicial"; }

private:
	double refreshWork() const override { return factor_.factorisationWork(); }
	double applicationWork() const override { return factor_.solveWork(); }
	void   solveRows(const VecXd& b, VecXd& x) const override { factor_.solve(b, x); }
	// one sweep of the factor for all columns
	void applyColumns(const MatXd& R, MatXd& Z) const override
	{
		MatXd rows, solution;
		onRows(R, Z, rows, solution, [this](const MatXd& b, MatXd& x) { factor_.solve(b, x); });
	}

	CholmodFactor factor_;
	BlockMatrix6  assembled_; // between analyse() and factorise()
};

class LaggedMultigrid : public LaggedPreconditioner {
public:
	explicit LaggedMultigrid(int coarsestRows = AggregationMultigrid::kCoarsestRows) : coarsestRows_(coarsestRows) { }
	bool refresh(const ImplicitViscousSystem& system, bool) override
	{
		std::vector<Vec3>               branch;
		BlockMatrix6                    A = blockRows(system, &branch);
		std::vector<std::array<bool, 6>> free(A.size());
		for (int i = 0; i < A.size(); ++i)
			free[i] = system.bodies()[bodyOfRow_[i]].free;
		return ready_ = cycle_.build(std::move(A), std::move(branch), free, coarsestRows_);
	}
	size_t storedBlocks() const override { return cycle_.storedBlocks(); }
	int    levels() const override { return cycle_.levels(); }

private:
	double refreshWork() const override { return cycle_.buildWork(); }
	double applicationWork() const override { return cycle_.cycleWork(); }
	void   solveRows(const VecXd& b, VecXd& x) const override { cycle_.solve(b, x); }

	int                  coarsestRows_;
	AggregationMultigrid cycle_;
};

} // namespace viscbridge
