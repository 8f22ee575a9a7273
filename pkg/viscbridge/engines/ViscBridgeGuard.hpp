// ViscBridgeGuard: checks the scene before the first step and stops a run before a blow-up spreads.
#pragma once
#include "viscbridge/scene/NetworkTimeStepBound.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include <core/GlobalEngine.hpp>
#include <chrono>

namespace yade {

class ViscBridgeGuard : public GlobalEngine {
	// the energy reference (E5 of physics.md): kinetic + elastic energy and positions at referenceIter
	std::vector<Vector3r>   startPos;
	std::vector<Vector3r>   lastPos;   // per body id, at the previous call (kinematic bodies' work)
	std::vector<Body::id_t> kinematic; // bodies with degrees of freedom that do not move under forces (walls, fixed or partly blocked ones)
	Real                    startEnergy = 0, boundaryWork = 0, lastSlack = 0, capillaryAtReference = 0;
	Real                    peakEnergyIn = 0; // the most energy the scene has held since the reference (E5: the margin's scale)
	long                    referenceIter = -1;
	int                     boundaryWorkIx = -1;
	bool                    referencePending = true; // taken one step after a change, once contacts exist
	bool                    rebaselineRequested = false;
	size_t                  checkedSignature = 0;
	// what tells a new O.run() from the next step of the same run
	long                                  lastCallIter = -1, lastStopAtIter = -1;
	Real                                  lastStopAtTime = -1, stepSeconds = 0;
	bool                                  lastStepOfRun = false;
	std::chrono::steady_clock::time_point lastCallEnd;
	NetworkTimeStepBound                  bound;
	// The bridges ruptured since the last check that passed (a blow-up tears the culprit's bridge
	// apart before it is diagnosed): their rates in P14, per body, so that the advised dt still
	// counts them (never unsafe).
	struct Ruptured {
		Body::id_t id;
		Real       damping, stiffness;
	};
	std::vector<Ruptured> ruptured;
	void                  collectRuptures();
	void                  boundWithRuptured(bool implicit);
	AttributeRollback<int, Real, Real>    rollback;
	auto                                  checked() { return std::tie(iterPeriod, energyMargin, energyFloor); }

	bool        startsNewRun();
	void        takeReference(Real slack);
	void        accumulateBoundaryWork(bool newRun);
	void        checkEnergy();
	// over the interactions: the stored elastic energy, and −(work of the capillary forces) so far,
	// the last step's included
	struct InteractionEnergy {
		Real elastic, capillary;
	};
	InteractionEnergy interactionEnergy() const;
	Real        mechanicalEnergyNow(bool upper) const; // upper: the larger half-step kinetic energy (E5)
	Vector3r    gravity() const; // NewtonIntegrator's
	std::string diagnose(Body::id_t worst, const std::string& what);
	std::string safeStepAdvice(bool implicit, bool washino);
	// [MPI] under yade.mpy, the same decisions on every rank (ViscBridgeGuardDistributed.cpp; no-ops serially)
	void agreeWithOtherRanks(bool& changed, bool& newRun);
	void sumOverRanks(Real& kinetic, Real& gravityWork, Real& work, Real& elastic, bool& finite) const;
	int  distributedCulprit(Body::id_t culprit, Real kinetic) const;

public:
	void        action() override;
	void        postLoad(ViscBridgeGuard&);
	void        requestRebaseline() { rebaselineRequested = true; }
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(ViscBridgeGuard, GlobalEngine,
		"Put first in O.engines (before :yref:`ForceResetter`; :yref:`viscbridge.engines()` does). "
		"Before the first step, and whenever bodies, materials or engines change, it checks what would "
		"otherwise crash or silently misbehave inside the interaction loop: spheres have a radius > 0, "
		"dynamic bodies a mass > 0, every sphere, wall, facet and box a :yref:`FrictMat` (clumps and "
		"other shapes are left alone); :yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous` and "
		":yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys` come together; 'implicit' integration has "
		":yref:`ViscBridgeImplicitSolver`, an undamped :yref:`NewtonIntegrator`, a dissipative "
		"tangential model; O.dt > 0. Problems raise an exception naming the parameter, "
		"its value and what is allowed.\n\n"
		"Every iterPeriod steps it stops the run (raising an exception, so ``O.run(n, True)`` reports it) "
		"on a NaN or inf position or velocity (of a particle, or of a wall, facet or other body whose motion is "
		"prescribed: the collider would drop its contacts and the spheres pass through it), or when the kinetic plus elastic energy exceeds what the "
		"scene had at the reference plus what was put in since (the work of gravity, from the positions, "
		"and of moving walls and other kinematic bodies (accumulated every step; with O.trackEnergy also "
		"added to O.energy as ``boundaryWork``, so that ``O.energy.total()`` closes with moving walls)), "
		"by more than (energyMargin − 1) × the most energy it has held since the reference (physics.md E5: the integrator's own "
		"energy error scales with the energy in motion, not with what is left when a bouncing body climbs back). "
		"Physics cannot exceed that bound; an explicit scheme above its stable step does. The message "
		"names the body, its most demanding interaction with its coefficients, the time-step criterion "
		"that was violated, and a Δt that would be safe (half the rigorous bound P14 of the current contacts "
		"and of the bridges that ruptured since the last check that passed: a blow-up often tears the "
		"culprit's bridge apart before it is diagnosed, and the advice must still count it) — only when "
		"that is smaller than the current one; with tangentialModel='washino', "
		"which is not dissipative, it says that the gain may be the model's.\n\n"
		"The reference is taken one step after the start and after bodies or engines change. At the "
		"start of every new ``O.run()`` it is taken again from the current state, keeping the energy "
		"margin the scene had at the last check: velocities or positions changed by hand between two "
		"runs (an impact 'kick') are then the new starting point, not a blow-up, while a slowly "
		"growing instability still runs out of margin. After changing the state by hand between "
		"single ``O.step()`` calls, call :yref:`rebaseline()<ViscBridgeGuard.rebaseline>`.\n\n"
		"Under yade.mpy (docs/cluster.md) the check is global: energies and work are summed over the ranks, every rank "
		"takes the same decision at the same step, a stop carries the rank that owns the body, and a dt that differs "
		"between ranks stops every rank.",
		((int,iterPeriod,10,Attr::triggerPostLoad,"Steps between the NaN and energy checks, >= 1 (walls' work is accumulated every step)."))
		((Real,energyMargin,1.05,Attr::triggerPostLoad,"Tolerance of the energy check, >= 1: the kinetic + elastic energy may exceed the energy put in by (energyMargin − 1) × the most energy the scene has held since the reference."))
		((Real,energyFloor,0,Attr::triggerPostLoad,"Kinetic energy always accepted [J], >= 0 (for scenes with nothing put in)."))
		((long,checks,0,Attr::readonly,"Number of energy checks done."))
		((long,rebaselines,0,Attr::readonly,"Energy references taken again at the start of a new run or by rebaseline()."))
		((Real,energyIn,0,Attr::readonly,"Energy put in since the reference, at the last check [J]."))
		((Real,kineticEnergy,0,Attr::readonly,"Kinetic energy at the last check [J]."))
		((string,lastError,"",Attr::readonly,"The message of the last stop."))
		,
		/* ctor */ rollback.keep(checked());,
		/* py */
		.def("rebaseline", &ViscBridgeGuard::requestRebaseline,
		     "Take the energy reference again from the state at the next step, with no margin carried over: call it after changing "
		     "velocities or positions by hand between O.step() calls (a new O.run() does this by itself).")
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeGuard);

} // namespace yade
