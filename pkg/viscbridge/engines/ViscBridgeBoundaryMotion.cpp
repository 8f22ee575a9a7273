#include "viscbridge/engines/ViscBridgeBoundaryMotion.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include <core/Scene.hpp>

namespace yade {

CREATE_LOGGER(ViscBridgeBoundaryMotion);

void ViscBridgeBoundaryMotion::action()
{
	if (!distributed::active(scene) || distributed::rank(scene) == 0) return;
	const Real dt = scene->dt;
	for (const auto& b : *scene->bodies)
		if (b && distributed::isMasterBoundary(*b)) {
			// NewtonIntegrator's leapfrogTranslate and leapfrogSphericalRotate for a body whose every
			// degree of freedom is blocked (no acceleration), term for term: the same bits as on the master
			State& s = *b->state;
			s.pos += s.vel * dt;
			const Real angle2 = s.angVel.squaredNorm();
			if (angle2 != 0) {
				const Real  angle = sqrt(angle2);
				Quaternionr q(AngleAxisr(angle * dt, s.angVel / angle));
				s.ori = q * s.ori;
			}
			s.ori.normalize();
		}
}

} // namespace yade
