// Small helpers shared by the kernel tests: fixed-seed random vectors and a relative comparison.
#pragma once
#include "viscbridge/core/linalg/Types.hpp"
#include <cmath>
#include <random>

namespace vbtest {

using viscbridge::Vec3;

// π written out here, so that expected values do not reuse the header's constant.
inline constexpr double kPi = 3.141592653589793;

inline double uniform(std::mt19937& g, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(g); }

// Log-uniform in [lo, hi]: gaps span several decades and every decade should be sampled.
inline double logUniform(std::mt19937& g, double lo, double hi) { return std::exp(uniform(g, std::log(lo), std::log(hi))); }

inline Vec3 randomVec(std::mt19937& g, double scale) { return scale * Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)); }

inline Vec3 randomUnit(std::mt19937& g)
{
	Vec3 v;
	do v = randomVec(g, 1.0);
	while (v.norm() < 0.1 || v.norm() > 1.0); // rejection: isotropic directions
	return v.normalized();
}

// A random unit vector perpendicular to the unit vector n.
inline Vec3 randomPerpendicularUnit(std::mt19937& g, const Vec3& n)
{
	Vec3 t;
	do {
		const Vec3 v = randomUnit(g);
		t            = v - v.dot(n) * n;
	} while (t.norm() < 0.1);
	return t.normalized();
}

// Two unit vectors completing n to a right-handed orthonormal basis (t1, t2, n).
inline void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2)
{
	const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
	t1           = (a - a.dot(n) * n).normalized();
	t2           = n.cross(t1);
}

} // namespace vbtest
