// ViscBridgeForceSum: adds the forces of the step's wet contacts to their bodies in an order fixed by
// the bodies' ids, so that a run gives the same bits on any number of threads (docs/architecture.md, "Bit-identical on any number of threads").
// YADE's InteractionLoop hands interactions to threads on demand (guided schedule) and each thread
// adds into its own force slot; the slots' sum then depends on which thread took which contact, and a
// rounding difference of one step grows, in a bed with dry contacts, into a different trajectory.
#pragma once
#include <core/GlobalEngine.hpp>
#include <vector>

namespace yade {

class ViscBridgeForceSum : public GlobalEngine {
	// workspace, kept between steps (no allocation once grown)
	std::vector<Vector3r> force, torque;
	std::vector<char>     touched;

public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC(ViscBridgeForceSum, GlobalEngine,
		"Adds the forces and torques :yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous` computed in this step to the "
		"bodies, each body's in the order of the ids of its partners, so that a run is bit-identical on any number of "
		"OpenMP threads (``yade -j``) and run after run (docs/architecture.md). With this engine between InteractionLoop and "
		"NewtonIntegrator the law keeps each contact's forces until it runs; without it the law adds them itself, as "
		"YADE's laws do, and a run on several threads may differ from the serial one in its last bits and, where dry "
		"contacts amplify them, in its trajectory. :yref:`viscbridge.engines()` puts it right after the InteractionLoop. "
		"Forces of other laws are not touched (they are added as they are computed)."
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeForceSum);

} // namespace yade
