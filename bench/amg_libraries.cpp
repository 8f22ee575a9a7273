// The preconditioners Debian ships against our own, on the implicit solver's system A = M + Δt D
// (issue 26): hypre's BoomerAMG (nodal systems AMG, with and without the rigid-body modes as
// interpolation vectors) and PETSc's GAMG (smoothed aggregation with the rigid-body near-null
// space), against the CHOLMOD factor (core/linalg/CholmodFactor.hpp) and our aggregation multigrid
// (core/linalg/AggregationMultigrid.hpp), each preconditioning conjugate gradients on the same
// matrices to ‖b − A x‖/‖b‖ ≤ 1e-6 from x = 0, with b = A x_true for a random x_true.
//
// Beds (unit masses, inertia 0.1, Δt c/m = 1e4, tangential and rolling resistances c/100,
// a1 = a2 = 0.5, every component free): a simple cubic lattice (6 neighbours) and a "random" bed —
// fcc sites jittered by up to 0.1 pitch, 15 % removed, bridges between centres closer than 1.05.
// One process, one thread (MPI initialised as a singleton; OMP_NUM_THREADS=OPENBLAS_NUM_THREADS=1).
//
//   ./yadew sh sh bench/amg_libraries.sh [LARGEST_BODIES [cubic|random]]
//
// Each library solves with its own CG and its own matrix-vector product (hypre ParCSR, PETSc AIJ
// with inodes); ours use Eigen's CSR product with the project's conjugateGradients.  At the largest
// size (~10⁵) only the CHOLMOD factor, our multigrid and, per library, its first settings (the
// library's defaults given the system's structure) and those that were fastest (setup + solve) and
// that took the fewest iterations at the size below are run, to keep the bench's time bounded.
#include "viscbridge/core/linalg/AggregationMultigrid.hpp"
#include "viscbridge/core/linalg/CholmodFactor.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include "viscbridge/core/util/AvailableMemory.hpp"
#include <HYPRE.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_utilities.h>
#include <petscksp.h>
#include <Eigen/QR>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <malloc.h>
#include <random>
#include <string>
#include <vector>

using namespace viscbridge;

namespace {
using CsrMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr double kTolerance     = 1e-6;
constexpr int    kMaxIterations = 1000;
constexpr double kRepeatBelow   = 20;   // s: a setup + solve longer than this is not repeated

// Bytes a CHOLMOD factor may take: 12 GB (this 24 GB machine), less if less than twice that is available.
double factorLimit()
{
	static const double limit = std::min(12e9, 0.5 * static_cast<double>(availableMemoryBytes()));
	return limit;
}

double since(std::chrono::steady_clock::time_point t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); }

// Bytes the process holds on its heap (small blocks and mmap'ed large ones): the growth over a
// setup is what the preconditioner keeps, whichever library allocated it (all go through malloc).
double heapBytes()
{
	const struct mallinfo2 m = mallinfo2();
	return static_cast<double>(m.uordblks + m.hblkhd);
}

// ------------------------------------------------------------------------------------------------
// The beds
// ------------------------------------------------------------------------------------------------

ViscousBlock bridge(const Vec3& n, double c)
{
	ViscousBlock b;
	b.valid      = true;
	b.n          = n;
	b.cn         = c;
	b.resistance = { c / 100, c / 100, c / 100, c / 100 };
	b.a1 = b.a2 = 0.5;
	return b;
}

struct Bed {
	std::string                      name;
	std::vector<Vec3>                position;
	std::vector<std::pair<int, int>> pairs; // bridged bodies, i < j
};

// Unit masses, all six components free; Δt c/m = 1e4 with Δt = 1.
ImplicitViscousSystem systemOf(const Bed& bed)
{
	std::vector<SystemBody> bodies(bed.position.size());
	for (auto& b : bodies) {
		b.mass    = 1;
		b.inertia = 0.1 * Mat3::Identity();
		b.free.fill(true);
	}
	std::vector<SystemBridge> bridges;
	for (const auto& [i, j] : bed.pairs) {
		const Vec3   d = bed.position[j] - bed.position[i];
		SystemBridge s { i, j, bridge(d.normalized(), 1e4), Vec3::Zero() };
		s.branch = d;
		bridges.push_back(s);
	}
	return ImplicitViscousSystem(std::move(bodies), std::move(bridges), 1.0);
}

// side³ bodies at unit pitch, each bridged to its 6 neighbours.
Bed cubicLattice(int side)
{
	Bed  bed { "cubic", {}, {} };
	auto index = [&](int i, int j, int k) { return (k * side + j) * side + i; };
	for (int k = 0; k < side; ++k)
		for (int j = 0; j < side; ++j)
			for (int i = 0; i < side; ++i) {
				bed.position.emplace_back(i, j, k);
				if (i + 1 < side) bed.pairs.emplace_back(index(i, j, k), index(i + 1, j, k));
				if (j + 1 < side) bed.pairs.emplace_back(index(i, j, k), index(i, j + 1, k));
				if (k + 1 < side) bed.pairs.emplace_back(index(i, j, k), index(i, j, k + 1));
			}
	return bed;
}

// Pairs of points closer than `range`, by a grid of cells of that size (each pair once, i < j).
std::vector<std::pair<int, int>> closePairs(const std::vector<Vec3>& x, double range)
{
	Vec3 lo = x[0], hi = x[0];
	for (const Vec3& p : x)
		lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
	const Eigen::Vector3i cells = ((hi - lo) / range).cast<int>() + Eigen::Vector3i::Ones();
	auto cellOf = [&](const Vec3& p) { return Eigen::Vector3i(((p - lo) / range).cast<int>()); };
	auto key    = [&](const Eigen::Vector3i& c) { return (c.z() * cells.y() + c.y()) * cells.x() + c.x(); };
	std::vector<std::vector<int>> grid(static_cast<size_t>(cells.prod()));
	for (size_t i = 0; i < x.size(); ++i)
		grid[key(cellOf(x[i]))].push_back(static_cast<int>(i));
	std::vector<std::pair<int, int>> pairs;
	for (size_t i = 0; i < x.size(); ++i) {
		const Eigen::Vector3i c = cellOf(x[i]);
		for (int dz = -1; dz <= 1; ++dz)
			for (int dy = -1; dy <= 1; ++dy)
				for (int dx = -1; dx <= 1; ++dx) {
					const Eigen::Vector3i n = c + Eigen::Vector3i(dx, dy, dz);
					if ((n.array() < 0).any() || (n.array() >= cells.array()).any()) continue;
					for (const int j : grid[key(n)])
						if (j > static_cast<int>(i) && (x[j] - x[i]).norm() < range) pairs.emplace_back(static_cast<int>(i), j);
				}
	}
	std::sort(pairs.begin(), pairs.end());
	return pairs;
}

// fcc sites of unit nearest-neighbour distance in nx × ny × nz cubic cells, each moved by up to 0.1
// in a random direction and 15 % of them removed (fixed seed), bridged below 1.05: the coordination
// varies from body to body as in a settled bed.
Bed randomBed(int nx, int ny, int nz)
{
	const double                          a = std::sqrt(2.0); // cube edge for unit nearest-neighbour distance
	const std::array<Vec3, 4>             basis { Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5) };
	std::mt19937_64                       g(2026);
	std::uniform_real_distribution<double> u(-1, 1);
	Bed                                   bed { "random", {}, {} };
	for (int k = 0; k < nz; ++k)
		for (int j = 0; j < ny; ++j)
			for (int i = 0; i < nx; ++i)
				for (const Vec3& b : basis) {
					Vec3 jitter;
					do jitter = Vec3(u(g), u(g), u(g));
					while (jitter.squaredNorm() > 1);
					const bool removed = (u(g) + 1) / 2 < 0.15;
					if (!removed) bed.position.push_back(a * (Vec3(i, j, k) + b) + 0.1 * jitter);
				}
	bed.pairs = closePairs(bed.position, 1.05);
	return bed;
}

// ------------------------------------------------------------------------------------------------
// The problem every method solves
// ------------------------------------------------------------------------------------------------

struct Problem {
	std::string       bed;
	int               bodies = 0;
	size_t            bridges = 0;
	CsrMatrix         A;        // assembled M + Δt D, both triangles
	BlockMatrix6      blocks;   // the same by 6×6 blocks (CHOLMOD factor, our multigrid)
	std::vector<Vec3> branch;   // per block pair: centre of j − centre of i (our multigrid)
	VecXd             b, xTrue; // b = A xTrue
	MatXd             rigid;    // 6 rigid motions of the whole bed about its centroid: 3 translations, 3 rotations
};

// Column k < 3: v = e_k, ω = 0; column 3 + k: v = e_k × (x − centroid), ω = e_k.
MatXd rigidModes(const std::vector<Vec3>& x)
{
	Vec3 centroid = Vec3::Zero();
	for (const Vec3& p : x)
		centroid += p / static_cast<double>(x.size());
	MatXd R = MatXd::Zero(6 * x.size(), 6);
	for (size_t i = 0; i < x.size(); ++i)
		for (int k = 0; k < 3; ++k) {
			const Vec3 e = Vec3::Unit(k);
			R.block<3, 1>(6 * i, k)         = e;
			R.block<3, 1>(6 * i, 3 + k)     = e.cross(x[i] - centroid);
			R.block<3, 1>(6 * i + 3, 3 + k) = e;
		}
	return R;
}

Problem problemOf(const Bed& bed)
{
	const ImplicitViscousSystem sys = systemOf(bed);
	Problem                     p;
	p.bed     = bed.name;
	p.bodies  = static_cast<int>(bed.position.size());
	p.bridges = bed.pairs.size();
	p.A       = sys.assemble();
	p.A.makeCompressed();
	std::vector<int> rowOfBody; // every body has free components: row i is body i
	p.blocks = sys.blockMatrix(rowOfBody, &p.branch);
	std::mt19937_64                        g(7);
	std::uniform_real_distribution<double> u(-1, 1);
	p.xTrue = VecXd::NullaryExpr(p.A.rows(), [&] { return u(g); });
	p.b     = p.A * p.xTrue;
	p.rigid = rigidModes(bed.position);
	return p;
}

// ------------------------------------------------------------------------------------------------
// One measurement
// ------------------------------------------------------------------------------------------------

struct Result {
	explicit Result(std::string name = "") : method(std::move(name)) { }
	std::string method;
	double      setup = 0, solve = 0, apply = 0; // s: setup, the whole CG solve, one application of the preconditioner
	int         iterations = 0;
	double      memory     = 0; // bytes kept by the preconditioner (heap growth over its setup)
	double      residual   = 0; // true ‖b − A x‖/‖b‖
	bool        converged  = false;
	bool        skipped    = false; // not run (memory): the note says why
	int         rounds     = 0;
	std::string note;
};

double trueResidual(const Problem& p, const VecXd& x) { return (p.b - p.A * x).norm() / p.b.norm(); }

// The fastest setup and the fastest solve of up to two runs (one if the first took over kRepeatBelow).
Result fastestOf(const std::function<Result()>& run)
{
	Result best = run();
	best.rounds = 1;
	if (!best.skipped && best.setup + best.solve < kRepeatBelow) {
		const Result again = run();
		best.setup         = std::min(best.setup, again.setup);
		best.solve         = std::min(best.solve, again.solve);
		best.apply         = std::min(best.apply, again.apply);
		best.rounds        = 2;
	}
	return best;
}

void printHeader()
{
	std::printf("| bed | bodies | bridges (per body) | method | setup s | iterations | solve s | ms/iteration | ms/application | memory MB | residual | notes |\n");
	std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
	std::fflush(stdout);
}

void print(const Problem& p, const Result& r)
{
	if (r.skipped) {
		std::printf("| %s | %d | %zu (%.2f) | %s | – | – | – | – | – | – | – | %s |\n", p.bed.c_str(), p.bodies, p.bridges, 2.0 * p.bridges / p.bodies,
		            r.method.c_str(), r.note.c_str());
		std::fflush(stdout);
		return;
	}
	std::printf("| %s | %d | %zu (%.2f) | %s | %.3f | %d%s | %.3f | %.2f | %.2f | %.0f | %.1e | %s%s |\n", p.bed.c_str(), p.bodies, p.bridges,
	            2.0 * p.bridges / p.bodies, r.method.c_str(), r.setup, r.iterations, r.converged ? "" : " (not converged)", r.solve,
	            r.iterations ? 1e3 * r.solve / r.iterations : 0.0, 1e3 * r.apply, r.memory / 1e6, r.residual, r.note.c_str(),
	            r.rounds == 1 ? (r.note.empty() ? "1 run" : "; 1 run") : "");
	std::fflush(stdout);
}

double fastestApplication(const std::function<void()>& apply)
{
	double best = 1e300;
	for (int k = 0; k < 3; ++k) {
		const auto t = std::chrono::steady_clock::now();
		apply();
		best = std::min(best, since(t));
	}
	return best;
}

// ------------------------------------------------------------------------------------------------
// Ours: the project's CG (ImplicitViscousSystem.hpp) with the CHOLMOD factor or the multigrid
// ------------------------------------------------------------------------------------------------

// CG from x = 0 preconditioned by `precondition`, the product by Eigen's CSR matrix.
template <class Precondition> Result projectCG(const Problem& p, const Precondition& precondition, Result r)
{
	VecXd       x = VecXd::Zero(p.b.size()), residual = p.b;
	SolveReport rep;
	const auto  t = std::chrono::steady_clock::now();
	conjugateGradients(
	        x, residual, p.b.norm(), kTolerance, kMaxIterations, [&](const VecXd& v, VecXd& Av) { Av.noalias() = p.A * v; }, precondition,
	        SerialReduction(), rep);
	r.solve      = since(t);
	r.iterations = rep.iterations;
	r.residual   = trueResidual(p, x);
	r.converged  = rep.residual <= kTolerance;
	return r;
}

Result cholmodRun(const Problem& p)
{
	Result        r { "CHOLMOD factor (CholmodFactor: supernodal/simplicial by CHOLMOD, AMD/METIS)" };
	const double  heap = heapBytes();
	CholmodFactor factor;
	auto          t = std::chrono::steady_clock::now();
	factor.analyse(p.blocks.size(), p.blocks.pairs);
	const double analyse = since(t);
	char         note[200];
	if (factor.factorBytes() > factorLimit()) { // not made: report the analysis only
		std::snprintf(note, sizeof note, "SKIPPED: factor would take %.1f GB, limit %.1f GB (analysis %.2f s)", factor.factorBytes() / 1e9,
		              factorLimit() / 1e9, analyse);
		r.note    = note;
		r.skipped = true;
		return r;
	}
	t = std::chrono::steady_clock::now();
	factor.factorise(p.blocks);
	r.setup  = since(t) + analyse;
	r.memory = heapBytes() - heap;
	VecXd z;
	r.apply = fastestApplication([&] { factor.solve(p.b, z); });
	std::snprintf(note, sizeof note, "analyse %.2f s; L %.2f GB, %.0f blocks/body, %s", analyse, factor.factorBytes() / 1e9,
	              static_cast<double>(factor.offDiagonalBlocks()) / p.blocks.size(), factor.supernodal() ? "supernodal" : "simplicial");
	r.note = note;
	return projectCG(p, [&](const VecXd& res, VecXd& z) { factor.solve(res, z); }, r);
}

Result multigridRun(const Problem& p)
{
	Result                           r { "ours: AggregationMultigrid (rigid aggregates, block GS, CHOLMOD ≤ 600 rows)" };
	BlockMatrix6                     A = p.blocks; // build() takes its own copy
	std::vector<Vec3>                branch = p.branch;
	std::vector<std::array<bool, 6>> free(p.bodies);
	for (auto& f : free)
		f.fill(true);
	const double         heap = heapBytes();
	AggregationMultigrid mg;
	const auto           t = std::chrono::steady_clock::now();
	if (!mg.build(std::move(A), std::move(branch), free)) r.note = "BUILD FAILED; ";
	r.setup  = since(t);
	r.memory = heapBytes() - heap;
	VecXd z;
	r.apply = fastestApplication([&] { mg.solve(p.b, z); });
	char note[80];
	std::snprintf(note, sizeof note, "%d levels, %.1f blocks/body", mg.levels(), static_cast<double>(mg.storedBlocks()) / p.blocks.size());
	r.note += note;
	return projectCG(p, [&](const VecXd& res, VecXd& z) { mg.solve(res, z); }, r);
}

// ------------------------------------------------------------------------------------------------
// hypre: BoomerAMG preconditioning hypre's PCG, through the IJ interface (ParCSR), one process
// ------------------------------------------------------------------------------------------------

struct HypreSettings {
	std::string name;
	double      strongThreshold = 0.25;
	int         nodal           = 1; // HYPRE_BoomerAMGSetNodal: 1 coarsens on the Frobenius norms of the 6×6 blocks
	int         interpVectors   = 0; // 0; 3: v = e_k × x, ω = 0 (the rotations less their per-function constant ω = e_k); 6: the full rigid modes
	int         variant         = 1; // HYPRE_BoomerAMGSetInterpVecVariant: 1 (GM1; see hypreSettings() for 2 and 3)
	int         aggLevels       = 0; // HYPRE_BoomerAMGSetAggNumLevels: levels of aggressive coarsening
};

void hypreCheck(HYPRE_Int err, const char* what)
{
	if (!err) return;
	char text[256] = "";
	HYPRE_DescribeError(err, text);
	std::fprintf(stderr, "hypre: %s: %s\n", what, text);
	HYPRE_ClearAllErrors();
}

// An IJ vector over the rows 0 … n−1 of this one process.
HYPRE_IJVector hypreVector(const VecXd& v)
{
	const HYPRE_BigInt n = static_cast<HYPRE_BigInt>(v.size());
	HYPRE_IJVector     ij;
	HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n - 1, &ij);
	HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR);
	HYPRE_IJVectorInitialize(ij);
	std::vector<HYPRE_BigInt> rows(n);
	std::iota(rows.begin(), rows.end(), 0);
	HYPRE_IJVectorSetValues(ij, static_cast<HYPRE_Int>(n), rows.data(), v.data());
	HYPRE_IJVectorAssemble(ij);
	return ij;
}

HYPRE_ParVector parVector(HYPRE_IJVector ij)
{
	void* object;
	HYPRE_IJVectorGetObject(ij, &object);
	return static_cast<HYPRE_ParVector>(object);
}

VecXd valuesOf(HYPRE_IJVector ij, long n)
{
	VecXd                     v(n);
	std::vector<HYPRE_BigInt> rows(n);
	std::iota(rows.begin(), rows.end(), 0);
	HYPRE_IJVectorGetValues(ij, static_cast<HYPRE_Int>(n), rows.data(), v.data());
	return v;
}

// The matrix, row by row from the CSR arrays, in one call.
HYPRE_IJMatrix hypreMatrix(const CsrMatrix& A)
{
	const HYPRE_BigInt n = static_cast<HYPRE_BigInt>(A.rows());
	HYPRE_IJMatrix     ij;
	HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, n - 1, 0, n - 1, &ij);
	HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR);
	std::vector<HYPRE_Int>    sizes(n);
	std::vector<HYPRE_BigInt> rows(n), columns(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
	for (HYPRE_BigInt i = 0; i < n; ++i)
		sizes[i] = A.outerIndexPtr()[i + 1] - A.outerIndexPtr()[i], rows[i] = i;
	HYPRE_IJMatrixSetRowSizes(ij, sizes.data());
	HYPRE_IJMatrixInitialize(ij);
	HYPRE_IJMatrixSetValues(ij, static_cast<HYPRE_Int>(n), sizes.data(), rows.data(), columns.data(), A.valuePtr());
	HYPRE_IJMatrixAssemble(ij);
	return ij;
}

// PCG's own call of the preconditioner's setup is skipped: BoomerAMGSetup is called (and timed) before.
HYPRE_Int setupDoneAlready(HYPRE_Solver, HYPRE_Matrix, HYPRE_Vector, HYPRE_Vector) { return 0; }

struct HypreData { // the matrix, the right-hand side and the rigid modes, made once per problem
	HYPRE_IJMatrix              A;
	HYPRE_IJVector              b, x, z;
	std::vector<HYPRE_IJVector> modes;             // the 6 columns of Problem::rigid
	std::vector<HYPRE_IJVector> rotationsLessSpin; // its rotations with ω = 0: what per-function interpolation misses
	explicit HypreData(const Problem& p) : A(hypreMatrix(p.A)), b(hypreVector(p.b)), x(hypreVector(VecXd::Zero(p.b.size()))), z(hypreVector(VecXd::Zero(p.b.size())))
	{
		for (int k = 0; k < 6; ++k)
			modes.push_back(hypreVector(p.rigid.col(k)));
		for (int k = 3; k < 6; ++k) {
			VecXd v = p.rigid.col(k);
			for (long i = 3; i < v.size(); i += 6)
				v.segment<3>(i).setZero();
			rotationsLessSpin.push_back(hypreVector(v));
		}
	}
	~HypreData()
	{
		HYPRE_IJMatrixDestroy(A);
		for (HYPRE_IJVector v : { b, x, z })
			HYPRE_IJVectorDestroy(v);
		for (HYPRE_IJVector v : modes)
			HYPRE_IJVectorDestroy(v);
		for (HYPRE_IJVector v : rotationsLessSpin)
			HYPRE_IJVectorDestroy(v);
	}
	HYPRE_ParCSRMatrix matrix() const
	{
		void* object;
		HYPRE_IJMatrixGetObject(A, &object);
		return static_cast<HYPRE_ParCSRMatrix>(object);
	}
};

HYPRE_Solver boomerAMG(const HypreSettings& s, std::vector<HYPRE_ParVector>& vectors, const HypreData& d)
{
	HYPRE_Solver amg;
	HYPRE_BoomerAMGCreate(&amg);
	HYPRE_BoomerAMGSetPrintLevel(amg, 0);
	HYPRE_BoomerAMGSetMaxIter(amg, 1); // one V-cycle per application, as a preconditioner
	HYPRE_BoomerAMGSetTol(amg, 0.0);
	HYPRE_BoomerAMGSetNumFunctions(amg, 6); // (v, ω) interleaved per body: the default dof → function map
	HYPRE_BoomerAMGSetNodal(amg, s.nodal);
	HYPRE_BoomerAMGSetStrongThreshold(amg, s.strongThreshold);
	HYPRE_BoomerAMGSetAggNumLevels(amg, s.aggLevels);
	if (s.interpVectors > 0) {
		vectors.clear();
		for (int k = 0; k < s.interpVectors; ++k)
			vectors.push_back(parVector(s.interpVectors == 3 ? d.rotationsLessSpin[k] : d.modes[k]));
		HYPRE_BoomerAMGSetInterpVectors(amg, s.interpVectors, vectors.data()); // kept by us: hypre frees only its coarse copies
		HYPRE_BoomerAMGSetInterpVecVariant(amg, s.variant);
	}
	return amg;
}

Result hypreRun(const Problem& p, const HypreData& d, const HypreSettings& s)
{
	Result                       r { "hypre BoomerAMG: " + s.name };
	const HYPRE_ParCSRMatrix     A = d.matrix();
	const HYPRE_ParVector        b = parVector(d.b), x = parVector(d.x), z = parVector(d.z);
	std::vector<HYPRE_ParVector> vectors;
	const double                 heap = heapBytes();
	HYPRE_Solver                 amg  = boomerAMG(s, vectors, d);
	auto                         t    = std::chrono::steady_clock::now();
	hypreCheck(HYPRE_BoomerAMGSetup(amg, A, b, x), "BoomerAMGSetup");
	r.setup  = since(t);
	r.memory = heapBytes() - heap;
	r.apply  = fastestApplication([&] {
                HYPRE_ParVectorSetConstantValues(z, 0.0);
                HYPRE_BoomerAMGSolve(amg, A, b, z);
        });
	HYPRE_Solver pcg;
	HYPRE_ParCSRPCGCreate(MPI_COMM_WORLD, &pcg);
	HYPRE_PCGSetTol(pcg, kTolerance);
	HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
	HYPRE_PCGSetTwoNorm(pcg, 1); // stop on ‖r‖/‖b‖ as the others, not on the preconditioned norm
	HYPRE_PCGSetMaxIter(pcg, kMaxIterations);
	HYPRE_PCGSetPrintLevel(pcg, 0);
	HYPRE_PCGSetPrecond(pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve), setupDoneAlready, amg);
	HYPRE_ParCSRPCGSetup(pcg, A, b, x);
	HYPRE_ParVectorSetConstantValues(x, 0.0);
	t = std::chrono::steady_clock::now();
	const HYPRE_Int err = HYPRE_ParCSRPCGSolve(pcg, A, b, x);
	r.solve             = since(t);
	if (err) HYPRE_ClearAllErrors(); // not converged: reported below
	HYPRE_Int iterations = 0;
	HYPRE_PCGGetNumIterations(pcg, &iterations);
	HYPRE_Real relative = 1;
	HYPRE_PCGGetFinalRelativeResidualNorm(pcg, &relative);
	r.iterations = iterations;
	r.converged  = relative <= kTolerance; // hypre's recursive residual, as CG's test everywhere here
	r.residual   = trueResidual(p, valuesOf(d.x, p.b.size()));
	HYPRE_ParCSRPCGDestroy(pcg);
	HYPRE_BoomerAMGDestroy(amg);
	return r;
}

// ------------------------------------------------------------------------------------------------
// PETSc: KSPCG with PCGAMG, AIJ of block size 6 with the rigid modes as near-null space
// ------------------------------------------------------------------------------------------------

struct PetscSettings {
	std::string name;
	double      threshold = -2; // PCGAMGSetThreshold; < -1: PETSc's default
	const char* smoother  = nullptr; // -mg_levels_pc_type (nullptr: the default, Chebyshev/Jacobi)
	bool        nearNull  = true;    // else GAMG's default: per-component constants of the 6×6 blocks
	int         aggressive = -1;     // PCGAMGSetAggressiveLevels (−1: the default, 1)
};

#define PETSC_OK(call) PetscCallAbort(PETSC_COMM_SELF, call)

Vec petscVector(const VecXd& v)
{
	Vec x;
	PETSC_OK(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(v.size()), &x));
	PetscScalar* a;
	PETSC_OK(VecGetArray(x, &a));
	std::copy(v.data(), v.data() + v.size(), a);
	PETSC_OK(VecRestoreArray(x, &a));
	return x;
}

struct PetscData {
	Mat          A;
	Vec          b, x, z;
	MatNullSpace rigid; // the 6 rigid modes, orthonormalised (MatNullSpaceCreate wants an orthonormal basis)
	explicit PetscData(const Problem& p)
	{
		const PetscInt n = static_cast<PetscInt>(p.A.rows());
		PETSC_OK(MatCreate(PETSC_COMM_SELF, &A));
		PETSC_OK(MatSetSizes(A, n, n, n, n));
		PETSC_OK(MatSetType(A, MATSEQAIJ));
		PETSC_OK(MatSetBlockSize(A, 6));
		PETSC_OK(MatSeqAIJSetPreallocationCSR(A, p.A.outerIndexPtr(), p.A.innerIndexPtr(), p.A.valuePtr()));
		PETSC_OK(MatSetOption(A, MAT_SPD, PETSC_TRUE));
		b = petscVector(p.b);
		x = petscVector(VecXd::Zero(n));
		z = petscVector(VecXd::Zero(n));
		const MatXd      Q = Eigen::HouseholderQR<MatXd>(p.rigid).householderQ() * MatXd::Identity(p.rigid.rows(), 6);
		std::vector<Vec> modes;
		for (int k = 0; k < 6; ++k)
			modes.push_back(petscVector(Q.col(k)));
		PETSC_OK(MatNullSpaceCreate(PETSC_COMM_SELF, PETSC_FALSE, 6, modes.data(), &rigid));
		for (Vec& v : modes)
			PETSC_OK(VecDestroy(&v));
	}
	~PetscData()
	{
		PETSC_OK(MatNullSpaceDestroy(&rigid));
		PETSC_OK(MatDestroy(&A));
		PETSC_OK(VecDestroy(&b));
		PETSC_OK(VecDestroy(&x));
		PETSC_OK(VecDestroy(&z));
	}
};

VecXd valuesOf(Vec x, long n)
{
	const PetscScalar* a;
	PETSC_OK(VecGetArrayRead(x, &a));
	VecXd v = Eigen::Map<const VecXd>(a, n);
	PETSC_OK(VecRestoreArrayRead(x, &a));
	return v;
}

Result petscRun(const Problem& p, const PetscData& d, const PetscSettings& s)
{
	Result r { "PETSc GAMG: " + s.name };
	PETSC_OK(MatSetNearNullSpace(d.A, s.nearNull ? d.rigid : nullptr));
	PETSC_OK(PetscOptionsClear(nullptr));
	if (s.smoother) PETSC_OK(PetscOptionsSetValue(nullptr, "-mg_levels_pc_type", s.smoother));
	const double heap = heapBytes();
	KSP          ksp;
	PC           pc;
	PETSC_OK(KSPCreate(PETSC_COMM_SELF, &ksp));
	PETSC_OK(KSPSetOperators(ksp, d.A, d.A));
	PETSC_OK(KSPSetType(ksp, KSPCG));
	PETSC_OK(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED)); // stop on ‖r‖/‖b‖ as the others
	PETSC_OK(KSPSetTolerances(ksp, kTolerance, 0.0, 1e10, kMaxIterations));
	PETSC_OK(KSPGetPC(ksp, &pc));
	PETSC_OK(PCSetType(pc, PCGAMG));
	if (s.threshold >= -1) {
		PetscReal th = s.threshold;
		PETSC_OK(PCGAMGSetThreshold(pc, &th, 1));
	}
	if (s.aggressive >= 0) PETSC_OK(PCGAMGSetAggressiveLevels(pc, s.aggressive));
	PETSC_OK(KSPSetFromOptions(ksp));
	auto t = std::chrono::steady_clock::now();
	PETSC_OK(PCSetUp(pc));
	r.setup  = since(t);
	r.memory = heapBytes() - heap;
	PETSC_OK(KSPSetUp(ksp));
	r.apply = fastestApplication([&] { PETSC_OK(PCApply(pc, d.b, d.z)); });
	PETSC_OK(VecSet(d.x, 0.0));
	t = std::chrono::steady_clock::now();
	PETSC_OK(KSPSolve(ksp, d.b, d.x));
	r.solve = since(t);
	PetscInt           iterations;
	KSPConvergedReason reason;
	PETSC_OK(KSPGetIterationNumber(ksp, &iterations));
	PETSC_OK(KSPGetConvergedReason(ksp, &reason));
	r.iterations = static_cast<int>(iterations);
	r.converged  = reason > 0;
	r.residual   = trueResidual(p, valuesOf(d.x, p.b.size()));
	PetscInt  levels;
	PetscReal gridComplexity, operatorComplexity;
	PETSC_OK(PCMGGetLevels(pc, &levels));
	PETSC_OK(PCMGGetGridComplexity(pc, &gridComplexity, &operatorComplexity));
	char note[120];
	std::snprintf(note, sizeof note, "%d levels, operator complexity %.2f", static_cast<int>(levels), static_cast<double>(operatorComplexity));
	r.note = note;
	PETSC_OK(KSPDestroy(&ksp));
	return r;
}

// ------------------------------------------------------------------------------------------------
// The settings tried, and the run over the sizes
// ------------------------------------------------------------------------------------------------

// The interpolation vectors go with GM variant 1 only: variant 2 (hypre's preferred one) modifies
// the new dofs' rows with weights θ[m] for the m < num_functions original functions, and without
// user weights (no public setter) θ is a 3-entry array (2-D/3-D elasticity: 2 or 3 functions), so
// with our 6 functions it reads past it — valgrind: uninitialised stack values from setup on,
// results that change with the memory layout (0, 21, 34 or 59 iterations for one setting).
// Also tried and left out: the LN variant 3 (a segmentation fault in setup), the full rotations
// (ω = e_k) as vectors under variant 2, nodal norm 4 (as norm 1), classical interpolation with
// Falgout coarsening (3× the cost per cycle, no fewer iterations).
std::vector<HypreSettings> hypreSettings()
{
	return {
		{ "nodal, θ 0.25 (defaults otherwise)", 0.25 },
		{ "nodal, θ 0.5", 0.5 },
		{ "unknown-based (nodal 0), θ 0.5", 0.5, 0 },
		{ "nodal, θ 0.25, aggressive coarsening on 1 level", 0.25, 1, 0, 1, 1 },
		{ "nodal, θ 0.25, rotations (v = e×x, ω = 0) as interp vectors, GM1", 0.25, 1, 3, 1 },
		{ "nodal, θ 0.5, rotations (v = e×x, ω = 0) as interp vectors, GM1", 0.5, 1, 3, 1 },
		{ "nodal, θ 0.5, 6 rigid modes as interp vectors, GM1", 0.5, 1, 6, 1 },
	};
}

std::vector<PetscSettings> petscSettings()
{
	return {
		{ "rigid near-null space, default threshold (−1: no filtering)" },
		{ "rigid near-null space, threshold 0", 0.0 },
		{ "rigid near-null space, threshold 0.01", 0.01 },
		{ "rigid near-null space, threshold 0.05", 0.05 },
		{ "rigid near-null space, threshold 0.01, no aggressive coarsening", 0.01, nullptr, true, 0 },
		{ "rigid near-null space, threshold 0.01, SOR smoother", 0.01, "sor" },
		{ "no near-null space (block constants), default threshold", -2, nullptr, false },
	};
}

// Per library (method name prefix), the converged settings that were fastest (setup + solve) and
// those that took the fewest iterations.
std::vector<std::string> bestOf(const std::vector<Result>& results, const std::string& prefix)
{
	const Result* fastest = nullptr;
	const Result* fewest  = nullptr;
	for (const Result& r : results) {
		if (!r.converged || r.method.rfind(prefix, 0) != 0) continue;
		if (!fastest || r.setup + r.solve < fastest->setup + fastest->solve) fastest = &r;
		if (!fewest || r.iterations < fewest->iterations) fewest = &r;
	}
	std::vector<std::string> names;
	if (fastest) names.push_back(fastest->method);
	if (fewest && fewest != fastest) names.push_back(fewest->method);
	return names;
}

// All methods on one bed; with `only` non-empty, the libraries run only the settings named there.
std::vector<Result> measure(const Problem& p, const std::vector<std::string>& only)
{
	auto chosen = [&](const std::string& method) { return only.empty() || std::find(only.begin(), only.end(), method) != only.end(); };
	std::vector<Result> results;
	auto                record = [&](const Result& r) { print(p, r), results.push_back(r); };
	record(fastestOf([&] { return cholmodRun(p); }));
	record(fastestOf([&] { return multigridRun(p); }));
	{
		const HypreData d(p);
		for (const HypreSettings& s : hypreSettings())
			if (chosen("hypre BoomerAMG: " + s.name)) record(fastestOf([&] { return hypreRun(p, d, s); }));
	}
	{
		const PetscData d(p);
		for (const PetscSettings& s : petscSettings())
			if (chosen("PETSc GAMG: " + s.name)) record(fastestOf([&] { return petscRun(p, d, s); }));
	}
	return results;
}

void runBed(const std::vector<std::function<Bed()>>& sizes, int largestBodies)
{
	std::vector<Result> previous;
	for (size_t k = 0; k < sizes.size(); ++k) {
		const Bed bed = sizes[k]();
		if (bed.position.size() > largestBodies * 1.1) break;
		const Problem            p = problemOf(bed);
		std::vector<std::string> only;
		if (k > 0 && p.bodies > 50000) { // the largest beds: per library its first settings, and the fastest and the fewest-iteration ones of the size below
			only = { "hypre BoomerAMG: " + hypreSettings().front().name, "PETSc GAMG: " + petscSettings().front().name };
			for (const char* library : { "hypre", "PETSc" })
				for (const std::string& name : bestOf(previous, library))
					only.push_back(name);
		}
		previous = measure(p, only);
	}
}
} // namespace

int main(int argc, char** argv)
{
	PetscCall(PetscInitializeNoArguments()); // initialises MPI (a singleton: no mpirun needed)
	HYPRE_Initialize();
	const int         largest = argc > 1 ? std::atoi(argv[1]) : 100000;
	const std::string beds    = argc > 2 ? argv[2] : "both";
	std::printf("hypre %s, PETSc %d.%d.%d, CHOLMOD %d.%d.%d; CG to ‖b − A x‖/‖b‖ ≤ %.0e from x = 0, b = A x_true (x_true uniform in [−1, 1], "
	            "fixed seed); times: fastest of 2 runs (1 if over %.0f s); memory: heap growth over the setup; CHOLMOD factors over %.1f GB not made\n\n",
	            HYPRE_RELEASE_VERSION, PETSC_VERSION_MAJOR, PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR, CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION,
	            CHOLMOD_SUBSUB_VERSION, kTolerance, kRepeatBelow, factorLimit() / 1e9);
	printHeader();
	if (beds != "random") runBed({ [] { return cubicLattice(10); }, [] { return cubicLattice(22); }, [] { return cubicLattice(46); } }, largest);
	if (beds != "cubic") runBed({ [] { return randomBed(6, 7, 7); }, [] { return randomBed(14, 14, 15); }, [] { return randomBed(30, 31, 32); } }, largest);
	HYPRE_Finalize();
	PetscCall(PetscFinalize());
	return 0;
}
