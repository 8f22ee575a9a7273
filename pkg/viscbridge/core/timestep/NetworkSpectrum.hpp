// The stability limit of the explicit scheme on a whole contact network (physics.md §7, P16–P18).
//
// YADE's leapfrog evaluates the viscous forces with the half-step velocities, so the linearised
// update of the bed is stable iff Δt < h*, the smallest h with λ_max(h²K̃ + 2hD̃) = 4 (P18), where
// K̃ = M^-1/2 K M^-1/2 and D̃ = M^-1/2 D M^-1/2 are the network's stiffness and damping in
// mass-scaled coordinates.  The operator is applied matrix-free, pair by pair (PairMaps.hpp), never
// assembled; its top eigenpair is found by LOBPCG (block size 1), warm-started from the previous
// mode, with h re-solved from the Ritz vector's quotients at every iteration: on a common
// eigenvector y, h²(yᵀK̃y) + 2h(yᵀD̃y) = 4 is P13 in mass-scaled form, h = networkLimit(d, k).
//
// What the estimate guarantees: a Ritz quotient is a lower bound of λ_max, so the h it gives is an
// upper bound of h* (unsafe side); with the residual r, λ_max ≤ θ + ‖r‖ once the iteration has found
// the top eigenvector, and since λ(th) ≤ t λ(h) for t ≤ 1, h/(1 + ‖r‖/θ) is then below h*.  The
// caller brackets it further with P14, which is rigorous: h* ∈ [max(hSafe, hP14), hRitz].
#pragma once
#include "viscbridge/core/timestep/TimeStepBounds.hpp"
#include "viscbridge/core/linalg/ViscousBlock.hpp"
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace viscbridge {

using VecX = Eigen::VectorXd;

// One pair of the network: compact body indices (−1 for a side without degrees of freedom, such as
// a wall) and its damping and stiffness maps.
struct NetworkPair {
	int          body1, body2;
	ViscousBlock damping, stiffness;
};

// D̃ and K̃ of a network: per body, the scale 1/√m (×3) and 1/√I (×3) that makes the coordinates
// mass-scaled (0 for a blocked component), and its pairs.  `key` names each body the same way whatever
// the numbering of this operator (a body id), so that the start vector does not depend on it.
class NetworkOperator {
public:
	std::vector<Vec6>        scale;
	std::vector<NetworkPair> pairs;
	std::vector<long>        key; // per body, a name independent of the numbering (its id); empty: the index

	std::size_t size() const { return 6 * scale.size(); }

	// Dy = D̃ y and Ky = K̃ y in one pass over the pairs.
	void apply(const VecX& y, VecX& Dy, VecX& Ky) const
	{
		Dy.setZero(size());
		Ky.setZero(size());
		for (const NetworkPair& p : pairs) {
			Vec6 v1 = Vec6::Zero(), v2 = Vec6::Zero();
			if (p.body1 >= 0) v1 = scale[p.body1].cwiseProduct(y.segment<6>(6 * p.body1));
			if (p.body2 >= 0) v2 = scale[p.body2].cwiseProduct(y.segment<6>(6 * p.body2));
			accumulate(p.damping, p, v1, v2, Dy);
			accumulate(p.stiffness, p, v1, v2, Ky);
		}
	}

	// The diagonals of D̃ and K̃ (each a Rayleigh quotient of a unit vector, so a lower bound of the
	// top eigenvalue), in closed form from each pair's side blocks: translations cn n_k² + m11(1 − n_k²),
	// rotations a² m22 (1 − n_k²), mass-scaled.
	void diagonal(VecX& D, VecX& K) const
	{
		D.setZero(size());
		K.setZero(size());
		for (const NetworkPair& p : pairs)
			for (int side = 0; side < 2; ++side) {
				const int body = side == 0 ? p.body1 : p.body2;
				if (body < 0) continue;
				addDiagonal(p.damping, side == 0 ? p.damping.a1 : p.damping.a2, body, D);
				addDiagonal(p.stiffness, side == 0 ? p.stiffness.a1 : p.stiffness.a2, body, K);
			}
	}

private:
	void addDiagonal(const ViscousBlock& b, double arm, int body, VecX& out) const
	{
		if (!b.valid) return;
		for (int k = 0; k < 3; ++k) {
			const double nk2 = b.n[k] * b.n[k], s = scale[body][k], sr = scale[body][k + 3];
			out[6 * body + k] += s * s * (b.cn * nk2 + b.resistance.m11 * (1 - nk2));
			out[6 * body + k + 3] += sr * sr * arm * arm * b.resistance.m22 * (1 - nk2);
		}
	}
	void accumulate(const ViscousBlock& b, const NetworkPair& p, const Vec6& v1, const Vec6& v2, VecX& out) const
	{
		if (!b.valid) return;
		const BridgeResistance R = bridgeResistance(b, v1.head<3>(), v1.tail<3>(), v2.head<3>(), v2.tail<3>(), Vec3::Zero());
		if (p.body1 >= 0) out.segment<6>(6 * p.body1) += scale[p.body1].cwiseProduct((Vec6() << R.force1, R.torque1).finished());
		if (p.body2 >= 0) out.segment<6>(6 * p.body2) += scale[p.body2].cwiseProduct((Vec6() << R.force2, R.torque2).finished());
	}
};

struct StabilityEstimate {
	double h      = std::numeric_limits<double>::infinity(); // from the Ritz vector: an upper bound of h*
	double hSafe  = std::numeric_limits<double>::infinity(); // h/(1 + ‖r‖/θ), below h* once converged
	double d      = 0, k = 0;                                // the mode's quotients yᵀD̃y, yᵀK̃y [1/s, 1/s²]
	double residual = 0;                                     // ‖r‖/θ of the last iteration
	int    iterations = 0;                                   // operator products spent
	bool   converged  = false;
};

// Where the iteration's vectors live.  Locally, the whole network: products are the operator's,
// reductions are plain.  A network split over processes (yade.mpy) provides another space with the
// same members: `apply` refreshes the entries other processes own before the product and leaves
// only this one's rows, `owns` tells its own degrees of freedom, `dot`, `sum`, `max` reduce over the processes, `largest` ranks entries over
// all of them, so that every process takes the same decisions and the result does not depend on the
// split (up to rounding).
struct LocalNetwork {
	const NetworkOperator& op;
	std::size_t            size() const { return op.size(); }
	bool                   owns(std::size_t) const { return true; }
	void                   apply(const VecX& y, VecX& Dy, VecX& Ky) const { op.apply(y, Dy, Ky); }
	void                   diagonal(VecX& D, VecX& K) const { op.diagonal(D, K); }
	double                 dot(const VecX& a, const VecX& b) const { return a.dot(b); }
	double                 sum(double v) const { return v; }
	double                 max(double v) const { return v; }
	// (value, key) of the `count` largest of these entries of all processes, largest first
	std::vector<std::pair<double, long>> largest(const std::vector<std::pair<double, long>>& mine, std::size_t) const { return mine; }
};

namespace detail {
	// A key per degree of freedom: the body's key and the component.
	inline long dofKey(const NetworkOperator& op, std::size_t i)
	{
		const std::size_t body = i / 6;
		return 6 * (op.key.empty() ? static_cast<long>(body) : op.key[body]) + static_cast<long>(i % 6);
	}
	// A pseudo-random number in [−1, 1] for a key (SplitMix64): the same for a degree of freedom however
	// the network is numbered or split.
	inline double noise(long key)
	{
		unsigned long long z = static_cast<unsigned long long>(key) + 0x9E3779B97F4A7C15ULL;
		z                    = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
		z                    = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
		z ^= z >> 31;
		return 2.0 * static_cast<double>(z >> 11) / static_cast<double>(1ULL << 53) - 1.0;
	}

	// A vector together with its two images.
	struct Imaged {
		VecX x, Dx, Kx;
	};
	template <class Space> void orthogonalise(const Space& s, Imaged& w, const Imaged& against)
	{
		const double c = s.dot(against.x, w.x);
		w.x -= c * against.x, w.Dx -= c * against.Dx, w.Kx -= c * against.Kx;
	}
	template <class Space> bool normalise(const Space& s, Imaged& w)
	{
		const double n = std::sqrt(s.dot(w.x, w.x));
		if (!(n > 1e-12)) return false;
		w.x /= n, w.Dx /= n, w.Kx /= n;
		return true;
	}

	// A value with the key that names it; ranked largest first, ties by key, so that every process
	// (and any numbering) picks the same.
	using Entry = std::pair<double, long>;
	inline bool before(const Entry& a, const Entry& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); }

	// The degrees of freedom with the largest diagonal entries of h²K̃ + 2hD̃: where the stiffest
	// local modes sit (ties broken by key, so that the choice does not depend on the numbering).
	template <class Space>
	std::vector<std::size_t> largestEntries(const Space& s, const VecX& D, const VecX& K, double h, std::size_t count)
	{
		std::vector<Entry>       e;
		std::vector<std::size_t> at;
		for (long i = 0; i < D.size(); ++i)
			if (D[i] > 0 || K[i] > 0) e.push_back({ h * h * K[i] + 2 * h * D[i], dofKey(s.op, i) });
		const std::size_t k = std::min(count, e.size());
		std::partial_sort(e.begin(), e.begin() + k, e.end(), before);
		e.resize(k);
		std::vector<Entry> all = s.largest(e, count);
		std::sort(all.begin(), all.end(), before);
		if (all.size() > count) all.resize(count);
		std::vector<std::size_t> out;
		for (long i = 0; i < D.size(); ++i)
			for (const Entry& a : all)
				if (a.second == dofKey(s.op, i) && (D[i] > 0 || K[i] > 0)) out.push_back(static_cast<std::size_t>(i));
		return out;
	}

	// A pair's relative motion along its normal, y = (s₁∘n, −s₂∘n) in mass-scaled coordinates, is a
	// Rayleigh quotient of the whole operator at least cₙσ (σ = Σ_k n_k²(s₁k² + s₂k²), the inverse reduced
	// mass along n; other bridges only add): so h* ≤ the pair's own limit (P12/P13).  The stiffest pair
	// over the network (over all processes, ties by key) and its vector, a witness against a lesser mode.
	template <class Space> double stiffestPair(const Space& s, VecX& witness)
	{
		const NetworkOperator& op = s.op;
		auto sigmaOf = [&](const NetworkPair& p) {
			double sigma = 0;
			for (int k = 0; k < 3; ++k)
				for (int b : { p.body1, p.body2 })
					if (b >= 0) sigma += p.damping.n[k] * p.damping.n[k] * op.scale[b][k] * op.scale[b][k];
			return sigma;
		};
		auto keyOf = [&](const NetworkPair& p) {
			auto k = [&](int b) { return b < 0 ? -1L : (op.key.empty() ? static_cast<long>(b) : op.key[b]); };
			return (k(p.body1) + 1) * (1L << 26) + k(p.body2) + 1; // exact in a double up to 6.7e7 bodies
		};
		Entry best { 0.0, 0 };
		for (const NetworkPair& p : op.pairs) {
			const double sigma = sigmaOf(p);
			const Entry  e { 1 / networkLimit(p.damping.valid ? p.damping.cn * sigma : 0, p.stiffness.valid ? p.stiffness.cn * sigma : 0), keyOf(p) };
			if (before(e, best)) best = e;
		}
		std::vector<Entry> all = s.largest(best.first > 0 ? std::vector<Entry> { best } : std::vector<Entry> {}, 1);
		witness.setZero(s.size());
		if (all.empty()) return std::numeric_limits<double>::infinity();
		best = *std::min_element(all.begin(), all.end(), before);
		for (const NetworkPair& p : op.pairs)
			if (keyOf(p) == best.second)
				for (int side = 0; side < 2; ++side) {
					const int b = side == 0 ? p.body1 : p.body2;
					if (b >= 0) witness.segment<3>(6 * b) = (side == 0 ? 1.0 : -1.0) * op.scale[b].head<3>().cwiseProduct(p.damping.n);
				}
		return 1 / best.first;
	}

	// The start: the previous mode, plus unit vectors where the diagonal is largest, plus a little of a
	// fixed pseudo-random vector.  A network of separate clusters has an eigenvector in each, with zero
	// residual: started on one, the iteration would stay there although another cluster's mode is
	// stiffer.  With every candidate in the start it moves to the top one.
	template <class Space> VecX startVector(const Space& s, const VecX& previous, bool warm, const std::vector<std::size_t>& candidates)
	{
		const std::size_t n = s.size();
		VecX              x = warm ? VecX(previous) : VecX(VecX::Zero(n));
		if (warm) {
			// an eigenvector's sign is arbitrary (rounding picks it); fixing it against the noise makes
			// the start, hence the step, the same however the network is split over processes
			VecX e(n);
			for (std::size_t i = 0; i < n; ++i) e[i] = noise(dofKey(s.op, i));
			x /= std::copysign(std::sqrt(s.dot(x, x)), s.dot(x, e));
		}
		// beside a previous mode, a tenth of its weight: enough to grow if stiffer, little to clean if not
		std::vector<std::size_t> mine; // a process adds its own degrees of freedom only
		for (std::size_t i : candidates)
			if (s.owns(i)) mine.push_back(i);
		const double candidateWeight = (warm ? 0.1 : 1.0) / std::sqrt(std::max(s.sum(static_cast<double>(mine.size())), 1.0));
		for (std::size_t i : mine) x[i] += candidateWeight;
		std::size_t owned = 0;
		for (std::size_t i = 0; i < n; ++i) owned += s.owns(i) ? 1 : 0;
		const double dofs   = s.sum(static_cast<double>(owned));
		const double weight = s.dot(x, x) > 0 ? 1e-3 / std::sqrt(dofs) : 1.0;
		for (std::size_t i = 0; i < n; ++i) x[i] += weight * noise(dofKey(s.op, i));
		return x / std::sqrt(s.dot(x, x));
	}
}

// h* by a dense eigen-solution and bisection on λ_max(h²K̃ + 2hD̃) = 4: O(n³), for small networks
// and for checking the iteration.
inline double denseStabilityLimit(const NetworkOperator& op)
{
	const long n = static_cast<long>(op.size());
	if (n == 0 || op.pairs.empty()) return std::numeric_limits<double>::infinity();
	Eigen::MatrixXd D(n, n), K(n, n);
	VecX            e = VecX::Zero(n), Dy, Ky;
	for (long j = 0; j < n; ++j) {
		e[j] = 1;
		op.apply(e, Dy, Ky);
		D.col(j) = Dy, K.col(j) = Ky;
		e[j]     = 0;
	}
	D = 0.5 * (D + D.transpose()), K = 0.5 * (K + K.transpose());
	auto lambda = [&](double h) { return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h * h * K + 2 * h * D, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff(); };
	double hi = 1;
	while (lambda(hi) < 4) hi *= 2;
	double lo = hi;
	while (lambda(lo) >= 4) lo /= 2;
	for (int i = 0; i < 60; ++i) {
		const double mid = std::sqrt(lo * hi);
		(lambda(mid) < 4 ? lo : hi) = mid;
	}
	return std::sqrt(lo * hi);
}

// LOBPCG from `start` (see stabilityLimit).
template <class Space> StabilityEstimate lobpcg(const Space& s, const VecX& start, double tolerance, int maxIterations, VecX& mode)
{
	StabilityEstimate est;
	const std::size_t n = s.size();
	detail::Imaged    x, w, p;
	x.x = start;
	s.apply(x.x, x.Dx, x.Kx);
	++est.iterations;
	bool haveP = false;
	for (;;) {
		est.d = s.dot(x.x, x.Dx), est.k = s.dot(x.x, x.Kx);
		est.h = networkLimit(est.d, est.k);
		if (!std::isfinite(est.h)) break; // the start sees nothing: no bound (the caller has P14)
		const double h = est.h, theta = 4.0; // at this h the quotient is exactly 4
		const VecX   r = h * h * x.Kx + 2 * h * x.Dx - theta * x.x;
		est.residual  = std::sqrt(s.dot(r, r)) / theta;
		// at least one Rayleigh–Ritz step: a warm start sitting on a lesser mode has a small residual,
		// and only the step on span{x, r} lets the top mode's share in it (the noise) grow
		if (est.residual <= tolerance && est.iterations > 1) {
			est.converged = true;
			break;
		}
		if (est.iterations >= maxIterations) break;
		// LOBPCG: Rayleigh–Ritz on span{x, r, p}; the images of every vector are kept, so the subspace
		// can be re-weighted for a new h without new products
		w.x = r;
		s.apply(w.x, w.Dx, w.Kx);
		++est.iterations;
		detail::orthogonalise(s, w, x);
		if (!detail::normalise(s, w)) break;
		std::vector<const detail::Imaged*> basis { &x, &w };
		if (haveP) {
			detail::orthogonalise(s, p, x);
			detail::orthogonalise(s, p, w);
			if (detail::normalise(s, p)) basis.push_back(&p);
		}
		const int       m = static_cast<int>(basis.size());
		Eigen::MatrixXd G(m, m);
		for (int a = 0; a < m; ++a)
			for (int b = 0; b < m; ++b)
				G(a, b) = s.dot(basis[a]->x, h * h * basis[b]->Kx + 2 * h * basis[b]->Dx);
		Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (G + G.transpose()));
		const Eigen::VectorXd c = eig.eigenvectors().col(m - 1);
		detail::Imaged        next;
		next.x = c[0] * x.x, next.Dx = c[0] * x.Dx, next.Kx = c[0] * x.Kx;
		detail::Imaged dir; // the new search direction: the part of the step that is not x
		dir.x.setZero(n), dir.Dx.setZero(n), dir.Kx.setZero(n);
		for (int a = 1; a < m; ++a) {
			dir.x += c[a] * basis[a]->x, dir.Dx += c[a] * basis[a]->Dx, dir.Kx += c[a] * basis[a]->Kx;
		}
		next.x += dir.x, next.Dx += dir.Dx, next.Kx += dir.Kx;
		if (!detail::normalise(s, next)) break;
		p     = dir;
		haveP = true;
		x     = next;
	}
	est.hSafe = est.h / (1 + est.residual);
	mode      = x.x;
	return est;
}

// The top mode of h²K̃ + 2hD̃ at the h where its eigenvalue is 4 (P18).  `mode` is the previous
// mode (empty at first) and receives the new one.  Warm, the start is the previous mode with a tenth
// of `candidates` (degrees of freedom where the network changed, e.g. bodies with new bridges).  Cold,
// it is the largest diagonal entries.  Either way, since a diagonal entry is a Rayleigh quotient, one
// above the eigenvalue found shows that the iteration settled on a lesser mode: it is started again there.
template <class Space>
StabilityEstimate stabilityLimit(const Space& s, VecX& mode, double tolerance, int maxIterations, const std::vector<std::size_t>& candidates = {})
{
	const std::size_t n = s.size();
	if (s.sum(static_cast<double>(s.op.pairs.size())) == 0 || s.sum(static_cast<double>(n)) == 0) return StabilityEstimate();
	// (every reduction is reached by every process: the short-circuits depend on reduced values only)
	const bool sized    = mode.size() == static_cast<long>(n);
	const VecX previous = sized ? mode : VecX(VecX::Zero(n));
	const bool warm     = s.sum(sized ? 0.0 : 1.0) == 0 && s.dot(previous, previous) > 0;
	VecX diagD, diagK;
	s.diagonal(diagD, diagK);
	// where the entries are compared first
	const double      hDiag = networkLimit(s.max(diagD.size() ? diagD.maxCoeff() : 0.0), s.max(diagK.size() ? diagK.maxCoeff() : 0.0));
	const auto        start = warm ? candidates : detail::largestEntries(s, diagD, diagK, hDiag, 8);
	StabilityEstimate est   = lobpcg(s, detail::startVector(s, mode, warm, start), tolerance, maxIterations, mode);
	// warm or cold, a diagonal entry above the eigenvalue found shows a stiffer mode elsewhere
	for (int restart = 0; restart < 3 && std::isfinite(est.h) && est.iterations < maxIterations; ++restart) {
		const std::vector<std::size_t> top   = detail::largestEntries(s, diagD, diagK, est.h, 1);
		const double                   above = top.empty() ? 0.0 : est.h * est.h * diagK[top[0]] + 2 * est.h * diagD[top[0]];
		if (s.max(above) <= 4 * (1 + tolerance)) break;
		const int spent = est.iterations;
		est             = lobpcg(s, detail::startVector(s, mode, true, top), tolerance, maxIterations - spent, mode);
		est.iterations += spent;
	}
	// and a pair whose own limit lies below the one found: started again from its relative motion
	VecX witness;
	if (std::isfinite(est.h) && est.iterations < maxIterations && detail::stiffestPair(s, witness) < est.h * (1 - tolerance)) {
		const int spent = est.iterations;
		est             = lobpcg(s, witness / std::sqrt(s.dot(witness, witness)), tolerance, maxIterations - spent, mode);
		est.iterations += spent;
	}
	return est;
}

// The same on a whole (not split) network.
inline StabilityEstimate stabilityLimit(const NetworkOperator& op, VecX& mode, double tolerance, int maxIterations,
                                        const std::vector<std::size_t>& candidates = {})
{
	return stabilityLimit(LocalNetwork { op }, mode, tolerance, maxIterations, candidates);
}

} // namespace viscbridge

