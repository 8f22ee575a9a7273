// The implicit solver's factorisation by hand (core/linalg/BlockCholesky.hpp) against SuiteSparse's
// CHOLMOD (supernodal, on OpenBLAS; AMD or METIS as CHOLMOD chooses), on the same matrices M + Δt D:
// simple cubic (6 neighbours) and fcc (12 neighbours) lattices of bridged spheres, Δt C/m = 1e4,
// sliding damping C/100 (as Adams–Perchard + slip at S_min).  One thread (OMP_NUM_THREADS=1,
// OPENBLAS_NUM_THREADS=1).  Times: analysis, factorisation, one solve (the two sweeps), fastest of 3.
//
//   ./yadew sh bash bench/factor_libraries.sh        (installs libsuitesparse-dev into the Debian 13
//                                                   root if missing, builds this file, runs it)
#include "viscbridge/core/linalg/BlockCholesky.hpp"
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include <Eigen/CholmodSupport>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

using namespace viscbridge;

namespace {
double fastest(const std::function<void()>& f, int rounds = 3)
{
	double best = 1e300;
	for (int r = 0; r < rounds; ++r) {
		const auto t = std::chrono::steady_clock::now();
		f();
		best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
	}
	return best;
}

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

// side³ spheres of unit mass on a simple cubic (fcc = false) or fcc lattice of unit pitch between
// touching neighbours, every neighbour pair bridged.
ImplicitViscousSystem lattice(int side, bool fcc)
{
	std::vector<Vec3> x;
	for (int k = 0; k < side; ++k)
		for (int j = 0; j < side; ++j)
			for (int i = 0; i < side; ++i) {
				if (fcc) x.push_back(Vec3(i + 0.5 * ((j + k) % 2), j * std::sqrt(3.0) / 2 + (k % 2) * std::sqrt(3.0) / 6, k * std::sqrt(2.0 / 3.0)));
				else x.push_back(Vec3(i, j, k));
			}
	std::vector<SystemBody> bodies(x.size());
	for (auto& b : bodies) {
		b.mass    = 1;
		b.inertia = 0.1 * Mat3::Identity();
		b.vel     = Vec3(1, 0, 0);
		b.free.fill(true);
	}
	// neighbours at distance 1 (a cell list of unit cells)
	std::vector<SystemBridge> bridges;
	const int                 n = static_cast<int>(x.size());
	std::vector<std::vector<int>> cell;
	const int                 cs = side + 2;
	cell.resize(cs * cs * cs);
	auto key = [&](const Vec3& p) { return (int(p.z()) + 1) * cs * cs + (int(p.y()) + 1) * cs + int(p.x()) + 1; };
	for (int i = 0; i < n; ++i)
		cell[key(x[i])].push_back(i);
	for (int i = 0; i < n; ++i)
		for (int dz = -1; dz <= 1; ++dz)
			for (int dy = -1; dy <= 1; ++dy)
				for (int dx = -1; dx <= 1; ++dx) {
					const int c = key(x[i]) + dz * cs * cs + dy * cs + dx;
					if (c < 0 || c >= static_cast<int>(cell.size())) continue;
					for (const int j : cell[c]) {
						const Vec3 d = x[j] - x[i];
						if (j <= i || d.norm() > 1.01) continue;
						SystemBridge s { i, j, bridge(d.normalized(), 1e4), Vec3::Zero() };
						s.branch = d;
						bridges.push_back(s);
					}
				}
	return ImplicitViscousSystem(std::move(bodies), std::move(bridges), 1.0);
}

void compare(const std::string& name, int side, bool fcc)
{
	const ImplicitViscousSystem sys = lattice(side, fcc);
	std::vector<int>            rowOfBody;
	const BlockMatrix6          A = sys.blockMatrix(rowOfBody);
	const VecXd                 b = VecXd::Random(6 * A.size());
	VecXd                       x;
	BlockCholesky               block;
	const double ta = fastest([&] { block.analyse(A.size(), A.pairs); });
	const double tf = fastest([&] { block.factorise(A); });
	const double ts = fastest([&] { block.solve(b, x); });
	VecXd        Ax;
	A.multiply(x, Ax);
	std::printf("%-8s %7d bodies %7zu bridges | by hand: analyse %8.3f s factorise %8.3f s solve %8.4f s, L %9zu blocks (%5.1f per body), residual %.1e\n",
	            name.c_str(), A.size(), sys.bridges().size(), ta, tf, ts, block.offDiagonalBlocks(), double(block.offDiagonalBlocks()) / A.size(),
	            (Ax - b).norm() / b.norm());
	const Eigen::SparseMatrix<double> S = sys.assemble();
	Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
	const double ca = fastest([&] { llt.analyzePattern(S); });
	const double cf = fastest([&] { llt.factorize(S); });
	const double cs = fastest([&] { x = llt.solve(b); });
	const double nnzL = llt.cholmod().lnz; // entries of L (scalar), from CHOLMOD's statistics
	std::printf("%-8s %7d bodies %7zu bridges | CHOLMOD: analyse %8.3f s factorise %8.3f s solve %8.4f s, L %9.0f scalars (%5.1f 6×6 blocks per body), residual %.1e\n",
	            name.c_str(), A.size(), sys.bridges().size(), ca, cf, cs, nnzL, nnzL / 36 / A.size(), (S * x - b).norm() / b.norm());
	std::fflush(stdout);
}
} // namespace

int main(int argc, char** argv)
{
	const int largest = argc > 1 ? std::atoi(argv[1]) : 22;
	for (const int side : { 10, 16, 22, 30, 46 })
		if (side <= largest) compare("cubic", side, false);
	for (const int side : { 10, 16, 22, 30 })
		if (side <= largest) compare("fcc", side, true);
}
