// What a ViscBridge scene must satisfy before its first step, checked by ViscBridgeGuard and
// ViscBridgeTimeStepper (whichever runs first) so that bad input is an exception naming the
// parameter, not a crash, a NaN or an exit() inside YADE's interaction loop.
#pragma once
#include <core/Scene.hpp>

namespace yade {

class Law2_ScGeom_ViscBridgePhys_HertzViscous;
class Ip2_FrictMat_FrictMat_ViscBridgePhys;

// The ViscBridge functors of the scene's InteractionLoop (nullptr where absent).
struct ViscBridgeFunctors {
	const Law2_ScGeom_ViscBridgePhys_HertzViscous* law = nullptr;
	const Ip2_FrictMat_FrictMat_ViscBridgePhys*    ip2 = nullptr;
	bool                                           hasLoop = false;
};
ViscBridgeFunctors findViscBridgeFunctors(const Scene* scene);

// Changes whenever bodies, materials, engines, the functors of an InteractionLoop or their models
// and scheme change (not when a body is moved): the validation below is redone then.
size_t sceneSignature(const Scene* scene);

// Throws std::invalid_argument (a Python ValueError) naming the offending parameter or body.
//   - engines: Law2_ScGeom_ViscBridgePhys_HertzViscous and Ip2_FrictMat_FrictMat_ViscBridgePhys
//     come together; 'implicit' (or a scheme chooser) has ViscBridgeImplicitSolver between InteractionLoop and
//     NewtonIntegrator, an undamped integrator and a dissipative tangential model;
//   - bodies: spheres have a finite radius > 0, dynamic bodies a finite mass > 0, and every body
//     the law can meet (sphere, wall, facet, box) a FrictMat;
//   - with checkDt, O.dt > 0.
void validateScene(const Scene* scene, bool checkDt);

// Whether the scene integrates its viscous forces implicitly now (yade/SchemeChooser.hpp: the law's
// scheme, or the time stepper's choice; ViscBridgeTimeStepper drops the viscous bound then).
bool viscousIntegrationIsImplicit(const Scene* scene);
// Whether it does, or may switch to it (autoIntegration): the engines must then allow it.
bool viscousIntegrationMayBeImplicit(const Scene* scene);

} // namespace yade
