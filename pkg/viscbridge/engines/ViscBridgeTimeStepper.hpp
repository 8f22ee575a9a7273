// ViscBridgeTimeStepper: sets O.dt at a fraction of the stability limit of the live contact network
// (physics.md §7, P16–P18), bracketed by the rigorous bound P14 (§3).
#pragma once
#include "viscbridge/scene/NetworkOfScene.hpp"
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include "viscbridge/yade/ContactForce.hpp"
#include "viscbridge/scene/NetworkTimeStepBound.hpp"
#include "viscbridge/core/timestep/AccuracyControl.hpp"
#include "viscbridge/yade/SchemeChooser.hpp"
#include <core/TimeStepper.hpp>

namespace yade {

class ViscBridgeTimeStepper : public TimeStepper, public SchemeChooser {
	NetworkTimeStepBound          bound;   // P14 and the Rayleigh bound
	NetworkOfScene                network; // the operator of P16–P18
	std::vector<viscbridge::Vec6> modeById; // the last dominant mode, per body id (the warm start)
	size_t                        validatedSignature = 0; // sceneSignature() of the last validated scene
	// what the last full update found, and what bridges formed since have added (Weyl: the top
	// eigenvalue grows at most by the new pairs' largest row sum, as P14 counts it)
	Real                          modeD = 0, modeK = 0, hP14 = 0, hAtUpdate = 0, addedD = 0, addedK = 0;
	std::vector<Real>             addedDamping, addedStiffness; // per body id, since the last full update
	std::vector<Body::id_t>       changedBodies;                // bodies of the bridges formed since
	long                          lastUpdateIter = -1;
	// [saved scenes] ViscBridgeTimeStepperState.cpp: the state unpacked from savedState when loading,
	// used at the first step if the scene is still the one saved (its signature; 0: none)
	size_t                        resumedSignature = 0;
	bool                          resumedCountsInteractions = false; // a state of layout 3 (its signature counted the interactions)
	std::vector<size_t>           savedBridges; // bridgeKeys() of the saved scene, sorted: the bridges the state knows
	void                          restoreSavedState();
	bool                          resumesSavedState(Scene*);
	AttributeRollback<Real, Real, Real, Real, Real, int, int, Real, Real, int> rollback;
	auto checked() { return std::tie(safety, maxGrowth, rayleighFraction, maxDt, tolerance, maxIterations, maxInterval, accuracy, implicitCost, errorFilterInterval); }
	// [accuracy] ViscBridgeTimeStepperAccuracy.cpp (physics.md §7a): each body's force a step ago,
	// the run's error sums, and the limit of the scheme not running (P14) for the choice between them
	std::vector<Vector3r>         previousForce;
	long                          forceIter = -1, lastSwitchIter = -1;
	viscbridge::AccuracyEstimate  accuracyEstimate;
	NetworkTimeStepBound          otherBound;
	viscbridge::StepMotion        lastStepMotion(Scene*);
	void                          advanceOffsets(Scene*, Real dtBefore); // A1b, once the step's dt is set
	static Vector3r               acceleration(const State&, const Vector3r& force, const Vector3r& gravity);
	Real                          explicitDamping(size_t id) const;
	// A1c under the explicit scheme: the bodies whose errors this step carries (with |δv|), staged in
	// lastStepMotion's loop and relaxed through the network after it
	struct ExplicitCarry {
		size_t id;
		Real   dvNorm;
	};
	std::vector<ExplicitCarry>    explicitCarried;
	std::vector<char>             carryStaged;   // per body id: in explicitCarried (workspace)
	std::vector<Vector3r>         carryChange;   // per body id: −Δt⁻¹ m × the network's relaxation of its error (workspace)
	std::vector<Real>             liveDamping;   // per body id: its bridges' Σ C^n(S)/m* at their gaps now (workspace)
	OrderedContacts               carryContacts; // its bridges, by their bodies' ids (OrderedWetContacts)
	void                          stageExplicitCarry(size_t id, const Vector3r& dv, Vector3r& carried, Vector3r& shifted);
	void                          carryExplicit(Scene*, Real& carriedSq, Real& shiftedSq, Real& freshSq);
	void                          resumeOffsets(Scene*);
	static void                   resumePairs(std::vector<Real>& saved, size_t bodies, std::vector<Vector3r>& a, std::vector<Vector3r>& b);
	void packPairs(std::vector<Real>& out, const std::vector<Vector3r>* a, const std::vector<Vector3r>* b, size_t counted) const;
	void                          resumeForces();
	bool                          restartOffsets = false; // resetErrorEstimate(): the offsets start afresh too
	std::vector<Real>             resumedMotion; // [saved scenes] (id, F, o) per body: forces restored at loading, offsets set in the scene at its first step
	static constexpr size_t       savedMotionStride = 7;
	std::vector<Real>             resumedErrors; // [saved scenes] (id, ε, ξ) per body: the carried velocity and position errors (A1c), set with the offsets
	std::vector<Real>             resumedHistory; // [saved scenes] (id, ε_h, Fu) per body: the history's error (A1e), set with the offsets (stride savedErrorStride)
	static constexpr size_t       savedErrorStride = 7;
	static Vector3r               resumedVector(const std::vector<Real>& saved, size_t at) { return Vector3r(saved[at], saved[at + 1], saved[at + 2]); }
	Real                          accuracyStep(Scene*); // records the last step; the step the tolerance allows (inf: none)
	Real                          otherSchemeLimit(Scene*, bool runningImplicit);
	void                          requireSchemeEngines(Scene*) const; // what autoIntegration needs, or an exception naming it
	void                          refuseAccuracyOverRanks(Scene*) const; // [MPI] accuracy > 0 under yade.mpy: an exception naming what to do
	void                          chooseScheme(Scene*, Real accuracyStepNow);
	int                           chosenScheme = -1; // autoIntegration's choice (a viscbridge::Integration; -1: none yet), saved
	static constexpr long         minSchemeSteps = 50;
	bool                          decided        = false; // whether autoIntegration has chosen since this object was made or loaded

	bool viscousImplicit() const;
	void fullUpdate(Scene*);
	int  fullUpdateCap() const; // the most steps between full updates: maxInterval, or timeStepUpdateInterval if > 1
	// A bridge formed since the last full update: its bodies and the P14 rates it adds, C/m* and k/m*.
	struct FormedBridge {
		Body::id_t id1, id2;
		Real       damping, stiffness;
	};
	static FormedBridge formedRecord(Body::id_t id1, Body::id_t id2, const ViscBridgePhys& ph);
	bool                listening = false; // the bridge events of a step are taken from the step after the stepper's first (not saved)
	void                addFormedBridges(Scene*); // the corrections between full updates, from the law's bridge events
	void                correctForFormed(Scene*, const std::vector<FormedBridge>&);
	Real limitNow() const;         // the bracketed limit with the corrections [s]
	void describeMode();
	Real criticalShare = 0; // the largest share of a body in the mode
	// [MPI] under yade.mpy (ViscBridgeTimeStepperDistributed.cpp; no-ops serially): the bounds of the
	// last evaluation, whether anything changed and the corrections since the last update, and the
	// described mode, all over the ranks, so that they take the same decisions and set the same dt
	void agreeOnBounds(Scene*);
	void agreeOnChanges(Scene*, bool& changed);
	void agreeWithOtherRanks(Scene*);

public:
	void computeTimeStep(Scene*) override;
	bool isActivated() override;
	bool choosesIntegration() const override { return autoIntegration; }
	int  chosenIntegration() const override { return chosenScheme; }
	Real exactLimit();
	void reset();
	void resetErrorEstimate() { accuracyEstimate.reset(); errorEstimate = stepError = 0; errorTightening = 1; restartOffsets = true; }
	void postLoad(ViscBridgeTimeStepper&);
	void preSave(ViscBridgeTimeStepper&);
	void postSave(ViscBridgeTimeStepper&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(ViscBridgeTimeStepper, TimeStepper,
		"Sets :yref:`O.dt<Omega.dt>` = safety × the stability limit of the explicit scheme on the live "
		"contact network (physics.md §7): the smallest $h$ with $\\lambda_{max}(h^2\\tilde K + 2h\\tilde D) = 4$ "
		"(P18), $\\tilde D$, $\\tilde K$ the mass-scaled damping and stiffness of every bridge and contact — "
		"the bridges' viscous coefficients at $S_{min}$, where they are largest, the contact dashpots and "
		"the Hertz–Mindlin tangent stiffness now, the capillary force's largest $|dF/dS|$. The top mode "
		"is found matrix-free (one pass over the interactions per product) by LOBPCG, warm-started from "
		"the previous mode, and started again where a diagonal entry or a pair's own limit shows a stiffer "
		"mode (physics.md §7); the estimate is corrected upwards by its residual and bracketed from below by "
		"the rigorous bound P14 ($\\Delta t \\le \\min_i 4/(d_i+\\sqrt{d_i^2+4\\kappa_i})$), which is "
		"1.5–4× lower on packings. Spheres also obey rayleighFraction × their Rayleigh time.\n\n"
		"The full computation runs every updateInterval steps, an interval that doubles while the limit "
		"stays within 1 % and halves when it moves by more than 5 % (1 … maxInterval). In between, every "
		"step takes the bridges that formed (the law reports them) into account with a rigorous "
		"correction (Weyl's inequality with their P14 rates), and a full update follows as soon as they "
		"lower the limit by 10 %. The stepper therefore runs every step; the inherited "
		":yref:`timeStepUpdateInterval<TimeStepper.timeStepUpdateInterval>`, when set above YADE's default 1 (as "
		"GlobalStiffnessTimeStepper scripts do), is the most steps between full updates (it caps maxInterval); "
		"formations are still corrected every step. With :yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous.integration` = "
		"'implicit' the bridges' viscous damping leaves the operator (P15).\n\n"
		"The default safety 0.5 puts a dashpot-dominated mode at $1/\\lambda_{max}$ of its damping, the "
		"limit below which a viscous mode decays without reversing (no spurious rebound; for an equal "
		"pair $t_v$, P12).\n\n"
		"Under yade.mpy (docs/cluster.md) the limit is the minimum over the ranks (each sees its own bodies' "
		"interactions), so that every rank sets the same dt; a dt that differs between ranks stops every rank.",
		((Real,safety,0.5,Attr::triggerPostLoad,"Fraction of the stability limit used as time step, in (0, 1]."))
		((Real,maxGrowth,1.1,Attr::triggerPostLoad,"Largest factor by which dt may grow in one step, >= 1 (decreases apply at once)."))
		((Real,rayleighFraction,0.4,Attr::triggerPostLoad,"Collision bound of a sphere: rayleighFraction × its Rayleigh time T_R, in (0, 1] (0.4 × safety 0.5 = the customary 0.2 T_R)."))
		((Real,maxDt,0,Attr::triggerPostLoad,"Upper limit of dt [s], >= 0; 0: none."))
		((Real,tolerance,1e-3,Attr::triggerPostLoad,"Relative residual $\\|r\\|/\\theta$ at which the mode iteration stops, in (0, 0.1]; it is also the width of the error bracket's upper side."))
		((int,maxIterations,30,Attr::triggerPostLoad,"Operator products a full update may spend, >= 1 (a warm start needs one or two)."))
		((int,maxInterval,50,Attr::triggerPostLoad,"Most steps between two full updates, >= 1."))
		((Real,dtCollision,0,Attr::readonly,"safety × the collision bound: springs and contact damping (P14 without the bridges) and the Rayleigh bound [s]."))
		((Real,dtViscous,0,Attr::readonly,"safety × the limit the top mode's damping alone would allow, $2/d$ with $d=y^T\\tilde Dy$ (inf without bridges or with implicit integration) [s]."))
		((Real,dtNetwork,0,Attr::readonly,"safety × the network limit the time step uses: the spectral estimate corrected by its residual, at least P14 [s]."))
		((Real,dtP14,0,Attr::readonly,"safety × the rigorous bound P14 [s]."))
		((Real,dtRitz,0,Attr::readonly,"safety × the limit of the mode's Rayleigh quotients: an upper bound of the true limit (the true one lies between dtNetwork and dtRitz) [s]."))
		((Real,dtBound,0,Attr::readonly,"safety × the combined bound, before the growth limit and maxDt [s]."))
		((Real,errorBound,0,Attr::readonly,"Relative width of the bracket of the true limit: (dtRitz − dtNetwork)/dtRitz."))
		((string,governing,"collision",Attr::readonly,"What sets dt: 'viscous-network' (a mode of the network dominated by the bridges' damping), 'collision' (one dominated by contact stiffness), 'rayleigh' (the spheres' Rayleigh bound), or 'accuracy' (the step the tolerance `accuracy` allows is below the stability limit)."))
		((Real,accuracy,0,Attr::triggerPostLoad|Attr::noSave,"Tolerance on the run's relative error, in (0, 1); 0: none (dt from stability alone). With a tolerance, dt is also at most the step at which the last step's error estimate (stepError) would meet it (physics.md A4: first order, with a margin 0.9, shrinking at most 5× per step, growing at most maxGrowth×), so the run's error — positions against their distance travelled, as bench/accuracy_cost.py measures it — stays near the tolerance (docs/timestep.md says where this holds). governing says 'accuracy' when it sets dt. Refused under yade.mpy (its estimate is not carried across the ranks)."))
		((bool,autoIntegration,false,Attr::noSave,"Choose the scheme per phase of the run (physics.md A5): switch the scheme of the viscous forces between 'explicit' and 'implicit' at full updates (the scene's scheme, read by :yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous.integrationInUse`; the law's own integration is the scheme the run starts with), whichever is cheaper for the step that stability and `accuracy` allow, an implicit step costing implicitCost explicit ones (needs :yref:`ViscBridgeImplicitSolver` in O.engines: viscbridge.engines(integration='auto') sets all up). The limit of the scheme not running is its rigorous bound P14, so a switch errs on the side of staying. scheme and schemeSwitches say which ran."))
		((int,errorFilterInterval,8,Attr::triggerPostLoad|Attr::noSave,"Steps between two full filters of the error estimate by :yref:`ViscBridgeImplicitSolver` while `accuracy` does not set dt (no tolerance, or its step at least 4× the one taken), >= 1 (physics.md A1d). In between (and except at a change of dt by more than 1 %), the leapfrog's offsets and the carried errors are relaxed by the solver's factor (the carried errors checked by CG where it lags), and a step's error is filtered once, its second filter taken at the share the last full one kept. 1: every step, as always while `accuracy` sets dt."))
		((Real,implicitCost,3,Attr::triggerPostLoad|Attr::noSave,"With autoIntegration: the cost of an implicit step in explicit steps, >= 1 (2–4 measured on beds of 300 spheres, 4–14 on 10³–10⁴: docs/performance.md §3)."))
		((string,scheme,"",Attr::readonly|Attr::noSave,"The scheme of the viscous forces at the last step: 'explicit' or 'implicit'."))
		((long,schemeSwitches,0,Attr::readonly|Attr::noSave,"Switches of the scheme made by autoIntegration."))
		((Real,errorEstimate,0,Attr::readonly|Attr::noSave,"Estimated relative error of the run so far (physics.md A2), the larger of two measures (mass-weighted RMS over the dynamic bodies): the positions, Σ Δt|(δv, o)| plus the position error of the carried errors (A1c) against the distance travelled Σ Δt|v̄| (δv the steps' velocity errors against their second-order companions, A1; o the leapfrog's offset, A1b), and the kinetic-energy history, Σ Δt·2|v̄||δv_K| against Σ Δt|v̄|² (δv_K the velocity error the steps accumulated: A1c, A1e). Computed with or without `accuracy`; resetErrorEstimate() starts it afresh."))
		((Real,stepError,0,Attr::readonly|Attr::noSave,"Estimated relative error of the last step (physics.md A3): its velocity error δv and the leapfrog's offset o (A1b), relative to the larger of the run's mean speed and the current one."))
		((Real,errorTightening,1,Attr::readonly|Attr::noSave,"The share of `accuracy` each step's own error is held to (physics.md A4c): 1, or down to 0.01 while the error the steps accumulated (A1c, A1e) exceeds half the tolerance and grows — the error of a run whose steps' errors persist adds up beyond any one step's."))
		((Real,dtAccuracy,0,Attr::readonly|Attr::noSave,"The step the tolerance `accuracy` allows now (A4) [s]; inf without a tolerance or while nothing changes."))
		((int,criticalBody,-1,Attr::readonly,"Id of the body with the largest share of the top mode (or of the smallest P14 or Rayleigh bound when that governs), -1 if none."))
		((vector<int>,criticalBodies,,Attr::readonly,"Ids of the bodies carrying 90 % of the top mode, largest share first (at most 10; under yade.mpy, of this rank's part of the network)."))
		((int,iterations,0,Attr::readonly,"Operator products of the last full update."))
		((Real,residual,0,Attr::readonly,"Relative residual of the mode at the last full update."))
		((long,updates,0,Attr::readonly,"Full updates so far."))
		((int,updateInterval,1,Attr::readonly,"Steps between full updates now."))
		((Real,modeDamping,0,Attr::readonly,"The top mode's damping quotient $y^T\\tilde Dy$ [1/s]."))
		((Real,modeStiffness,0,Attr::readonly,"The top mode's stiffness quotient $y^T\\tilde Ky$ [1/s²]."))
		((vector<Real>,savedState,,Attr::hidden,"The state between full updates a saved scene resumes from (written on saving, read on loading; internal)."))
		,
		/* ctor */ timeStepUpdateInterval = 1; rollback.keep(checked());
		,
		/* py */
.def("reset", &ViscBridgeTimeStepper::reset,
		     "Forget the mode and the corrections since the last full update: the next step starts the mode iteration afresh (viscbridge.mpi.to_serial() calls it: a merged scene holds one rank's part of them).")
				.def("resetErrorEstimate", &ViscBridgeTimeStepper::resetErrorEstimate,
		     "Start the error estimate afresh (errorEstimate, stepError): e.g. after preparing a scene, to report the accuracy of the run that follows.")
				.def("exactLimit", &ViscBridgeTimeStepper::exactLimit,
		     "The network limit of the current scene by a dense eigen-solution (O(n³) in the number of bodies: for small scenes and checks), without safety [s].")
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeTimeStepper);

} // namespace yade
