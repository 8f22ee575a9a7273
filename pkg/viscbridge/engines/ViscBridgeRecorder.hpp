// ViscBridgeRecorder: a PyRunner that also runs in the last step of every run, so that a recorder
// (viscbridge.vtk.bridge_recorder) writes the state a run ends in when the run does not end on one
// of its periods.  The last step is known within the step (scene/RunEnd.hpp): O.run(n) and
// O.stopAtTime say it in advance, and a loop asked to stop after the step in progress (O.pause()
// from an engine before this one, Ctrl-C through the InterruptWatcher if it comes before this
// engine's turn) or stepped by O.step() is not running.  A stop requested later in the step is left
// to Python (viscbridge.vtk.flush, at the signal or at exit).  Cost per step: two comparisons and an
// atomic read, on top of the period's own test.
#pragma once
#include <pkg/common/PyRunner.hpp>

namespace yade {

class ViscBridgeRecorder : public PyRunner {
public:
	bool isActivated() override;
	// clang-format off
	YADE_CLASS_BASE_DOC(ViscBridgeRecorder, PyRunner,
		"A :yref:`PyRunner` that runs its command every period (iterPeriod, virtPeriod, realPeriod, as PyRunner) "
		"and also in the last step of every run: the step that reaches :yref:`O.stopAtIter<Omega.stopAtIter>` "
		"(``O.run(n)``) or :yref:`O.stopAtTime<Omega.stopAtTime>`, the step in which the run was paused "
		"(``O.pause()`` from an engine before it, Ctrl-C or SIGTERM caught by the plugin) and a step of ``O.step()``. "
		"A recorder placed after the NewtonIntegrator thus records the state every run ends in, once. "
		"Made by :yref:`viscbridge.vtk.bridge_recorder()`.");
	// clang-format on
};
REGISTER_SERIALIZABLE(ViscBridgeRecorder);

} // namespace yade
