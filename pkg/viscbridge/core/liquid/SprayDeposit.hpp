// Where sprayed binder lands (physics.md §11, L6, L7): droplets travel in straight lines along the
// nozzle direction and wet the first particle they meet, so a particle receives in proportion to
// the area it shows the nozzle that no other particle hides (L6) — as a fine mist shared over every
// reached particle, or as whole droplets each landing on one (L6b); no film grows beyond a cap, the
// excess goes to the other exposed particles and, when they are all full, waits (L7).  YADE-free:
// the spray engine (engines/ViscBridgeSpray) applies these rules to the spheres in its zone.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace viscbridge {

// L6: the area of each sphere that a parallel spray along `direction` (unit) reaches, by a depth
// buffer over the plane normal to it: pixels of side h = (smallest radius)/pixelsPerRadius (coarser
// when the buffer would exceed maxPixels), each given to the sphere whose surface it meets first.
// A sphere far smaller than a pixel may be missed; the areas sum to the spray's shadow.  The
// buffers are the caller's, reused between calls (no allocation once they are large enough).
class SprayShadow {
	std::vector<double> depth;
	std::vector<int>    owner;

public:
	static constexpr double pixelsPerRadius = 5.0; // a disc of ~80 pixels: its area to ~2 %
	static constexpr double maxPixels       = 4e6;

	void exposedAreas(const std::vector<Vec3>& centres, const std::vector<double>& radii, const Vec3& direction, std::vector<double>& area)
	{
		const std::size_t n = centres.size();
		area.assign(n, 0.0);
		if (n == 0) return;
		// a basis of the plane the spray crosses
		const Vec3 e1 = direction.unitOrthogonal(), e2 = direction.cross(e1);
		double uMin = std::numeric_limits<double>::infinity(), vMin = uMin, uMax = -uMin, vMax = -uMin, rMin = uMin;
		for (std::size_t i = 0; i < n; ++i) {
			const double u = centres[i].dot(e1), v = centres[i].dot(e2), r = radii[i];
			uMin = std::min(uMin, u - r), uMax = std::max(uMax, u + r), vMin = std::min(vMin, v - r), vMax = std::max(vMax, v + r);
			rMin = std::min(rMin, r);
		}
		double h = rMin / pixelsPerRadius;
		if ((uMax - uMin) * (vMax - vMin) / (h * h) > maxPixels) h = std::sqrt((uMax - uMin) * (vMax - vMin) / maxPixels);
		// the grid shifted by an irrational fraction of a pixel: spheres on a lattice of the pixel's
		// own pitch would otherwise all meet the grid the same way and share one bias
		uMin -= 0.381966 * h, vMin -= 0.236068 * h;
		const long nu = static_cast<long>(std::ceil((uMax - uMin) / h)) + 1, nv = static_cast<long>(std::ceil((vMax - vMin) / h)) + 1;
		depth.assign(static_cast<std::size_t>(nu * nv), std::numeric_limits<double>::infinity());
		owner.assign(static_cast<std::size_t>(nu * nv), -1);
		for (std::size_t i = 0; i < n; ++i) rasterise(i, centres[i].dot(e1) - uMin, centres[i].dot(e2) - vMin, centres[i].dot(direction), radii[i], h, nu, nv);
		for (const int o : owner)
			if (o >= 0) area[static_cast<std::size_t>(o)] += h * h;
	}

private:
	// the pixels (centres) inside sphere i's disc, where its surface is nearer the nozzle than what they hold
	void rasterise(std::size_t i, double u, double v, double d, double r, double h, long nu, long nv)
	{
		const long i0 = std::max(0L, static_cast<long>(std::floor((u - r) / h))), i1 = std::min(nu - 1, static_cast<long>(std::ceil((u + r) / h)));
		const long j0 = std::max(0L, static_cast<long>(std::floor((v - r) / h))), j1 = std::min(nv - 1, static_cast<long>(std::ceil((v + r) / h)));
		for (long a = i0; a <= i1; ++a)
			for (long b = j0; b <= j1; ++b) {
				const double du = (a + 0.5) * h - u, dv = (b + 0.5) * h - v, rho2 = du * du + dv * dv;
				if (rho2 > r * r) continue;
				const double     front = d - std::sqrt(r * r - rho2);
				const std::size_t k    = static_cast<std::size_t>(a * nv + b);
				if (front < depth[k]) depth[k] = front, owner[k] = static_cast<int>(i);
			}
	}
};

// L7: share `amount` over the receivers in proportion to `weight`, none beyond its `room` (what its
// cap still allows); what a full receiver cannot take goes to the others in the same proportion.
// Writes each receiver's share into `given` and returns what none could take.  At most one round
// per receiver that fills up.
inline double shareWithinRoom(const std::vector<double>& weight, const std::vector<double>& room, double amount, std::vector<double>& given)
{
	const std::size_t n = weight.size();
	given.assign(n, 0.0);
	std::vector<bool> full(n, false);
	for (std::size_t i = 0; i < n; ++i) full[i] = !(weight[i] > 0) || !(room[i] > 0);
	while (amount > 0) {
		double open = 0;
		for (std::size_t i = 0; i < n; ++i)
			if (!full[i]) open += weight[i];
		if (!(open > 0)) break;
		const double perWeight = amount / open;
		bool         filled    = false;
		for (std::size_t i = 0; i < n; ++i) // a receiver the round would overfill takes its room and leaves the round
			if (!full[i] && given[i] + perWeight * weight[i] >= room[i]) amount -= room[i] - given[i], given[i] = room[i], full[i] = filled = true;
		if (filled) continue;
		for (std::size_t i = 0; i < n; ++i)
			if (!full[i]) given[i] += perWeight * weight[i];
		amount = 0;
	}
	return std::max(0.0, amount);
}

// A number in [0, 1) from (seed, counter) alone (splitmix64): droplet k of a spray lands where it
// would in any run that reaches it — after a save and load, on any number of threads.
inline double counterUniform(std::uint64_t seed, std::uint64_t counter)
{
	std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + counter + 0x632BE59BD9B4E019ULL;
	z               = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
	z               = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
	z ^= z >> 31;
	return static_cast<double>(z >> 11) * 0x1.0p-53;
}

// L6b: `amount` as whole droplets of `droplet` volume, each landing on one receiver drawn with
// probability proportional to `weight` among those with room for it (L7); droplet k of the spray's
// life is drawn from counterUniform(seed, k), `counter` counts them.  Writes each receiver's share
// into `given`; returns what stays (less than a droplet, or droplets no receiver has room for).
inline double shareAsDroplets(const std::vector<double>& weight, std::vector<double> room, double amount, double droplet, std::uint64_t seed,
                              std::uint64_t& counter, std::vector<double>& given)
{
	const std::size_t n = weight.size();
	given.assign(n, 0.0);
	std::vector<double> cumulative(n);
	auto                open = [&] { // the cumulative weight of the receivers a droplet still fits on
		double sum = 0;
		for (std::size_t i = 0; i < n; ++i) cumulative[i] = sum += (weight[i] > 0 && room[i] >= droplet) ? weight[i] : 0.0;
		return sum;
	};
	double total = open();
	while (amount >= droplet && total > 0) {
		const double      u = counterUniform(seed, counter++) * total;
		const std::size_t i = std::min<std::size_t>(n - 1, std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
		given[i] += droplet, room[i] -= droplet, amount -= droplet;
		if (room[i] < droplet) total = open(); // full for the next droplet
	}
	return amount;
}

} // namespace viscbridge
