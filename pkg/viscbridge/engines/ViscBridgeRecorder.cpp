#include "viscbridge/engines/ViscBridgeRecorder.hpp"
#include "viscbridge/scene/RunEnd.hpp"
#include <core/Omega.hpp>

namespace yade {

bool ViscBridgeRecorder::isActivated()
{
	const bool due = PyRunner::isActivated(); // asked every step: it keeps the period's counters
	return due || isLastStepOfRun(*scene) || !Omega::instance().isRunning();
}

} // namespace yade
