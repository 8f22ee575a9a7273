// ViscBridgeGuard: checks the scene before the first step and stops a run before a blow-up spreads.
#pragma once
#include "ViscBridgeTimeStepper.hpp"
#include <core/GlobalEngine.hpp>

namespace yade {

class ViscBridgeGuard : public GlobalEngine {
	std::vector<Vector3r> startPos;   // per body id, where the energy reference was taken
	std::vector<Vector3r> lastPos;    // per body id, at the previous call (kinematic bodies' work)
	std::vector<Body::id_t> kinematic; // bodies that do not move under forces (walls, fixed ones)
	Real                  startEnergy = 0, boundaryWork = 0; // kinetic + elastic at the reference
	long                  referenceIter = -1;
	int                   boundaryWorkIx = -1;
	bool                  referencePending = true; // taken one step after a change, once contacts exist
	long                  checkedSignature = -1;
	NetworkTimeStepBound  bound;
	void                  validateScene();
	void                  takeReference();
	Real                  storedElasticEnergy() const;
	std::string           diagnose(Body::id_t worst, const std::string& what);
	int                   lastValidPeriod = 10;
	Real                  lastValidMargin = 1.05, lastValidFloor = 0;

public:
	// Raises `message` at the start of the next step (adds a guard to O.engines if there is none):
	// for errors found inside InteractionLoop's parallel loop, where nothing can be thrown.
	static void raiseAtNextStep(Scene* scene, const std::string& message);
	void        action() override;
	void        postLoad(ViscBridgeGuard&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(ViscBridgeGuard, GlobalEngine,
		"Put first in O.engines (before :yref:`ForceResetter`; :yref:`viscbridge.engines()` does). "
		"Before the first step, and whenever bodies or engines change, it checks what would otherwise "
		"crash or silently misbehave inside the interaction loop: every body has a :yref:`FrictMat`; "
		":yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous` and :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys` "
		"come together; 'implicit' integration has :yref:`ViscBridgeImplicitSolver` and an undamped "
		":yref:`NewtonIntegrator`; O.dt > 0. Problems raise an exception naming the parameter, its value "
		"and what is allowed.\n\n"
		"Every iterPeriod steps it stops the run (raising an exception, so ``O.run(n, True)`` reports it) "
		"on a NaN or inf position or velocity, or when the kinetic plus elastic energy exceeds what the "
		"scene had at the reference (one step after the start or after bodies or engines changed) plus "
		"what was put in since: the work of gravity (from the positions) and of moving walls and other "
		"kinematic bodies (accumulated every step; with O.trackEnergy also added to O.energy as "
		"``boundaryWork``, so that ``O.energy.total()`` closes with moving walls). Physics cannot exceed "
		"that bound; an explicit scheme above its stable step does. The message names the body, its most "
		"demanding interaction with its coefficients, the time-step criterion that was violated, and the "
		"Δt that would have been safe (:yref:`ViscBridgeTimeStepper` at its default safety).",
		((int,iterPeriod,10,Attr::triggerPostLoad,"Steps between the NaN and energy checks, >= 1 (walls' work is accumulated every step)."))
		((Real,energyMargin,1.05,Attr::triggerPostLoad,"Factor on the energy put in that the kinetic energy may reach, >= 1."))
		((Real,energyFloor,0,Attr::triggerPostLoad,"Kinetic energy always accepted [J], >= 0 (for scenes with nothing put in)."))
		((long,checks,0,Attr::readonly,"Number of energy checks done."))
		((Real,energyIn,0,Attr::readonly,"Energy put in since the reference, at the last check [J]."))
		((Real,kineticEnergy,0,Attr::readonly,"Kinetic energy at the last check [J]."))
		((string,lastError,"",Attr::readonly,"The message of the last stop."))
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeGuard);

} // namespace yade
