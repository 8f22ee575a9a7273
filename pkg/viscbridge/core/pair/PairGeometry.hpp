// Reduced radius and mass, gap clamping and bridge rupture distance (physics.md §1, P6, P11).
#pragma once
#include <cmath>

namespace viscbridge {

// r̄ = r_i r_j/(r_i + r_j) (§1).  A side that is not a sphere (wall, facet, box) is passed as
// radius 0 and the pair is a sphere against a plane: r̄ = r_sphere.  YADE's geometry functors
// report an artificial radius for such sides; it must never reach this function.
inline double reducedRadius(double r1, double r2)
{
	if (r1 <= 0) return r2;
	if (r2 <= 0) return r1;
	return r1 * r2 / (r1 + r2);
}

// m* = m_i m_j/(m_i + m_j) (§1); a body that does not move under forces (a wall or a fixed
// particle) has infinite effective mass and m* is the other body's mass.
inline double reducedMass(double m1, bool dynamic1, double m2, bool dynamic2)
{
	if (!dynamic1) return m2;
	if (!dynamic2) return m1;
	return m1 * m2 / (m1 + m2);
}

// P6: the viscous coefficients are evaluated at max(S, S_min), also in overlap (S < 0), so the
// force is finite and continuous through contact.
inline double clampedGap(double S, double sMin) { return S > sMin ? S : sMin; }

// P11 (Lian et al. 1993): rupture distance of a bridge of volume V with contact angle θ.
inline double ruptureDistance(double volume, double contactAngle) { return (1.0 + 0.5 * contactAngle) * std::cbrt(volume); }

} // namespace viscbridge
