// SchemeChooser: the engine that chooses the scheme of the viscous forces per phase of a run
// (physics.md A5), asked by everything that needs the scheme in use.  An interface in this layer, so
// the law and the other engines read the choice without knowing the engine
// (engines/ViscBridgeTimeStepper implements it, with autoIntegration).  The law's own `integration`
// holds until the chooser has chosen; the chooser never writes the law.
#pragma once
#include "viscbridge/core/models/Registry.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"

namespace yade {

class SchemeChooser {
public:
	virtual ~SchemeChooser() = default;
	// Whether it chooses at all (it may switch to either scheme: the scene must allow both).
	virtual bool choosesIntegration() const = 0;
	// The scheme it has chosen (a viscbridge::Integration), or -1 before its first choice.
	virtual int chosenIntegration() const = 0;
};

// The scheme of the viscous forces in `scene` now: the chooser's, once it has chosen, else the
// law's `integration` (lawIntegration).  The one answer the law, the solver's checks, the guard and
// the stepper share.
inline viscbridge::Integration integrationInUse(const Scene* scene, int lawIntegration)
{
	const auto* chooser = ViscBridgeContext::findEngine<SchemeChooser>(scene);
	const int   chosen  = chooser && chooser->choosesIntegration() ? chooser->chosenIntegration() : -1;
	return static_cast<viscbridge::Integration>(chosen >= 0 ? chosen : lawIntegration);
}

} // namespace yade
