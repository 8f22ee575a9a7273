// Registers every ViscBridge class with YADE (one list for the whole plugin).
#include "HeaderProbe.hpp"
#include "Ig2_Wall_Facet_Sphere_BridgeRange.hpp"
#include "Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "ViscBridgePhys.hpp"
#include "ViscBridgeTimeStepper.hpp"
#include "ViscBridgeGuard.hpp"
#include "ViscBridgeImplicitSolver.hpp"

namespace yade {
YADE_PLUGIN((ViscBridgeHeaderProbe)(ViscBridgePhys)(Ip2_FrictMat_FrictMat_ViscBridgePhys)(Law2_ScGeom_ViscBridgePhys_HertzViscous)
            (Ig2_Wall_Sphere_ViscBridgeScGeom)(Ig2_Facet_Sphere_ViscBridgeScGeom)
            (ViscBridgeTimeStepper)(ViscBridgeImplicitSolver)(ViscBridgeGuard));
} // namespace yade
