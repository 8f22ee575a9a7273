// Registers every ViscBridge class with YADE (one list for the whole plugin).
#include "viscbridge/plugin/HeaderProbe.hpp"
#include "viscbridge/yade/Ig2_Facet_Sphere_ViscBridgeScGeom.hpp"
#include "viscbridge/yade/Ig2_Wall_Sphere_ViscBridgeScGeom.hpp"
#include "viscbridge/yade/Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "viscbridge/yade/Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/engines/ViscBridgeTimeStepper.hpp"
#include "viscbridge/engines/ViscBridgeGuard.hpp"
#include "viscbridge/engines/ViscBridgeImplicitSolver.hpp"
#include "viscbridge/engines/ViscBridgeImplicitWarmStart.hpp"
#include "viscbridge/engines/ViscBridgeBoundaryMotion.hpp"
#include "viscbridge/engines/ViscBridgeForceSum.hpp"
#include "viscbridge/engines/ViscBridgeLiquid.hpp"
#include "viscbridge/engines/ViscBridgeRecorder.hpp"
#include "viscbridge/engines/ViscBridgeSpray.hpp"

namespace yade {
YADE_PLUGIN((ViscBridgeHeaderProbe)(ViscBridgePhys)(Ip2_FrictMat_FrictMat_ViscBridgePhys)(Law2_ScGeom_ViscBridgePhys_HertzViscous)
            (Ig2_Wall_Sphere_ViscBridgeScGeom)(Ig2_Facet_Sphere_ViscBridgeScGeom)
            (ViscBridgeTimeStepper)(ViscBridgeImplicitSolver)(ViscBridgeImplicitWarmStart)(ViscBridgeGuard)(ViscBridgeForceSum)(ViscBridgeBoundaryMotion)(ViscBridgeLiquid)(ViscBridgeRecorder)(ViscBridgeSpray)(ViscBridgeState)(ViscBridgeContext));
} // namespace yade
