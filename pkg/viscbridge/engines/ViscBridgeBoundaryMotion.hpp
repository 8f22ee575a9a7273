// ViscBridgeBoundaryMotion: under yade.mpy, moves the master's boundaries (walls, facets driven by a
// kinematic engine or with a velocity set) on every worker, as NewtonIntegrator moves them on the
// master.  YADE's NewtonIntegrator moves only the bodies of its own subdomain, and mpy sends the
// master's states to the workers only with mpy.MASTER_UPDATE_STATES (its comment: "else they will be
// fixed or moved by the workers (e.g. MotionEngines)"; the engines set the velocities, nothing moves
// the bodies): without this, a worker's particles meet a drum's facets where they were at the start.
// docs/cluster.md, "Moving walls and the drum".
#pragma once
#include <core/GlobalEngine.hpp>

namespace yade {

class ViscBridgeBoundaryMotion : public GlobalEngine {
public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC(ViscBridgeBoundaryMotion, GlobalEngine,
		"Under yade.mpy, moves the master's bodies that are not dynamic and have a velocity (walls and facets a "
		":yref:`RotationEngine`, :yref:`TranslationEngine` or other kinematic engine drives, or whose velocity is set) on "
		"every worker, with the same arithmetic as :yref:`NewtonIntegrator` on the master, so that every rank has them "
		"at the same place at every step: YADE's NewtonIntegrator moves only the bodies of its own subdomain. It must "
		"come after NewtonIntegrator; viscbridge.mpi.decompose() puts it there. Does nothing in a serial run and on the "
		"master. Without it, ViscBridge refuses a scene with moving boundaries under yade.mpy at its first step."
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeBoundaryMotion);

} // namespace yade
