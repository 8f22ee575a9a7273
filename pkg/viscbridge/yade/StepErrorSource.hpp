// StepErrorSource: what the time stepper asks of the implicit solver for its error estimate — the
// velocity error of the last solved step over the bodies the solver holds, filtered by the step's
// system (physics.md A1a).  An interface in this layer, so the stepper reads it without knowing the
// engine (engines/ViscBridgeImplicitSolver implements it).
#pragma once
#include <lib/base/Math.hpp>
#include <vector>

namespace yade {

class StepErrorSource {
public:
	virtual ~StepErrorSource() = default;
	// The step the estimate is of (−1: none), Σ m|δv|² over the bodies it covers [kg·m²/s²], and
	// per body id whether it covers it.
	virtual long                     stepErrorStep() const   = 0;
	virtual Real                     stepErrorSquared() const = 0;
	// Σ m|δv|² of the step's own share of the carried error (A1c), which the controller measures and
	// the run's error counts through the carried position error instead
	virtual Real                     stepCarriedSquared() const = 0;
	virtual const std::vector<char>& stepErrorCovers() const  = 0;
};

} // namespace yade
