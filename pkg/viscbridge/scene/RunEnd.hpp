// The last step of a run, known before the step ends: YADE's loop stops after the step that brings
// O.iter to O.stopAtIter (set by O.run(n)) or O.time to O.stopAtTime (set by Drum.run, Settling.run
// or the user; core/SimulationFlow.cpp).  YADE has no end-of-run hook, so the engines that must see
// a run's end (the recorders, the guard) ask this within the step.  Exact once the step's dt is
// set (after the time stepper): the loop's own test is the same sum, time + dt.
#pragma once
#include <core/Scene.hpp>

namespace yade {

inline bool isLastStepOfRun(const Scene& scene)
{
	return (scene.stopAtIter > 0 && scene.iter + 1 == scene.stopAtIter) || (scene.stopAtTime > 0 && scene.time + scene.dt >= scene.stopAtTime);
}

} // namespace yade
