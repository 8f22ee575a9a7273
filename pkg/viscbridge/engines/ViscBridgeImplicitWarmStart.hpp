// The implicit solver's warm start, attached to the scene (yade/SceneAttachment.hpp) so that a run
// resumed from a saved scene starts CG where the continued run does, while scenes saved before it
// existed keep loading.
#pragma once
#include <lib/serialization/Serializable.hpp>

namespace yade {

class ViscBridgeImplicitWarmStart : public Serializable {
public:
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(ViscBridgeImplicitWarmStart, Serializable,
		"The warm start of :yref:`ViscBridgeImplicitSolver`: the viscous forces and torques of its last solve, "
		"per body id, from which the next solve's conjugate gradients start. Kept in "
		":yref:`O.miscParams<Omega.miscParams>` (created by the solver) and saved with the scene.",
		((vector<Vector3r>,force,,Attr::readonly,"Per body id: the viscous force of the last solve [N]."))
		((vector<Vector3r>,torque,,Attr::readonly,"Per body id: the viscous torque of the last solve [N·m]."))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(ViscBridgeImplicitWarmStart);

} // namespace yade
