// ViscBridgeImplicitSolver: backward Euler for the viscous bridge forces over the whole contact
// network (physics.md §4, P15), between InteractionLoop and NewtonIntegrator.
#pragma once
#include <array>
#include <limits>
#include <core/Body.hpp>
#include <core/GlobalEngine.hpp>
#include "viscbridge/core/linalg/ImplicitViscousSystem.hpp"
#include "viscbridge/core/linalg/LaggedPreconditioner.hpp"
#include "viscbridge/core/models/EnergyKeys.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include "viscbridge/yade/ContactForce.hpp"
#include "viscbridge/yade/StepErrorSource.hpp"
#include <lib/base/openmp-accu.hpp>

namespace yade {

class NewtonIntegrator;
class ViscBridgePhys;
class ViscBridgeImplicitWarmStart;
namespace distributed {
	struct Ownership;
}

class ViscBridgeImplicitSolver : public GlobalEngine, public StepErrorSource {
	// the warm start (per body id: the last solve's viscous forces), attached to the scene
	shared_ptr<ViscBridgeImplicitWarmStart> last;
	// The lagged factorisation and what it was computed for (bodies, bridges, free components).
	shared_ptr<viscbridge::LaggedPreconditioner> factorisation;
	std::vector<long>                      factorisedPattern, factorisedOrder; // sorted (the set), and as gathered (the order, to skip the sort when unchanged)
	long                                   factorisedIter = -1;
	int                                    lastIterationsSeen = 0;
	int                                    freshIterations    = 0; // of the first solve after the last refresh
	long                                   cycleSolves = 0, cycleIterations = 0; // since the last refresh
	size_t                                 validatedSignature = 0; // sceneSignature() of the last validated scene
	AttributeRollback<Real, int, int, std::string, Real> rollback;
	auto checked() { return std::tie(tolerance, maxIterations, refreshIterations, preconditioner, factorMemoryLimit); }
	std::array<int, viscbridge::energyKeyCount> energyIndex; // O.energy slots of the keys it books
	void bookKey(viscbridge::EnergyKey key, Real value);

	// The steps of action(), in order.
	struct Gathered; // the bridges the law described this step and the bodies they touch
	const NewtonIntegrator&       checkScene();
	void                          bookPendingWork();
	Gathered                      gather(const NewtonIntegrator& newton);
	void                          describedBridges(Gathered& g) const;
	viscbridge::SystemBody        systemBody(const Body& b, const distributed::Ownership& own, const NewtonIntegrator& newton) const;
	static Matrix3r               rotationalInertia(const Body& b, const NewtonIntegrator& newton);
	Body::id_t                    moving(Body::id_t id) const;
	Vector3r                      armInClump(Body::id_t id) const;
	std::vector<int>              touched; // workspace of gather(): per body id, its index in the system (−1: none)
	// workspace of describedBridges(): the bridges described this step, by their bodies' ids (OrderedWetContacts)
	mutable OrderedContacts       described;
	Eigen::VectorXd               warmStartGuess(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids) const;
	const viscbridge::Preconditioner* refreshPreconditioner(const viscbridge::ImplicitViscousSystem& sys, const std::vector<long>& pattern);
	std::string                       automaticKind(const viscbridge::ImplicitViscousSystem& sys) const;
	bool                              refreshLagged(const viscbridge::ImplicitViscousSystem& sys, bool samePattern);
	size_t                            chosenUnknowns = 0, chosenBridges = 0; // of the system for which 'auto' last chose the multigrid
	void solve(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, Eigen::VectorXd& x, const viscbridge::Preconditioner* pre);
	void applyForces(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
	                 const std::vector<viscbridge::BridgeResistance>& R);
	void bookEnergy(const viscbridge::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x, const std::vector<viscbridge::BridgeResistance>& R);
	// [accuracy] the error of this step, filtered by its system (physics.md A1a): for the time
	// stepper (StepErrorSource), Σ m|δv|² at step stepErrorIter and the bodies it covers
	long                  stepErrorIter = -1;
	Real                  stepErrorSq = 0, stepCarriedSq = 0;
	std::vector<char>     stepErrorCovered;
	std::vector<Vector3r> previousChange; // per body id: (v_{n+1/2} − v_{n−1/2})/Δt of the last solve (NaN: not solved)
	std::vector<Vector3r> stepChange;     // workspace: the same for this solve
	std::vector<char>     previousJumped, stepJumped; // per body id: that change was a jump of the model (A1)
	std::vector<Vector3r> historyWork;                // workspace: the history's errors of this step, per body id (A1e)
	long                  previousChangeIter = -1;
	long                  noCoefficientChangeAt = -1; // the step after a save (A1c)
	void estimateStepError(const viscbridge::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
	                       const std::vector<viscbridge::BridgeResistance>& R, const viscbridge::Preconditioner* pre);
	bool carriedErrorsOf(const viscbridge::ImplicitViscousSystem& sys, const Gathered& g, const Eigen::VectorXd& x,
	                     const std::vector<viscbridge::BridgeResistance>& R, Eigen::VectorXd& carried, Eigen::VectorXd& fresh); // false: nothing carried
	bool stepErrorOf(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
	                 Eigen::VectorXd& u); // false: not estimated (under MPI)
	void jumpStepError(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, const Eigen::VectorXd& x,
	                   const std::vector<char>& uncompared, Eigen::VectorXd& u) const;
	std::vector<char> jumpedBodies(const viscbridge::ImplicitViscousSystem& sys, const std::vector<Body::id_t>& ids, bool valid) const;
	bool offsetsOf(const std::vector<Body::id_t>& ids, size_t size, Eigen::VectorXd& o);
	bool historyOf(const std::vector<Body::id_t>& ids, size_t size, Eigen::VectorXd& h);
	void storeHistory(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed, const Eigen::VectorXd& once);
	static void filteredApart(const viscbridge::ImplicitViscousSystem& sys, const Eigen::MatrixXd& in, Eigen::MatrixXd& out, long carriedFrom,
	                          const viscbridge::Preconditioner* pre);
	void storeCarried(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed);
	// A1d: the filters every errorFilterInterval steps, and the share of the step's error the last one kept
	long lastFilterIter  = -1;
	Real filteredShare   = std::numeric_limits<Real>::quiet_NaN(); // Σ m|F²u|² / Σ m|Fu|²
	Real freshPersisting = std::numeric_limits<Real>::quiet_NaN(); // A1c: stepCarriedSq / Σ m|fresh|² at the last full filter
	Real lastEstimatedDt = 0;
	bool filterIsDue(bool stepErrorNow, bool freshNow);
	static void storeRelaxed(const std::vector<Body::id_t>& ids, const Eigen::VectorXd& relaxed, std::vector<Vector3r>& perBody);

public:
	long                     stepErrorStep() const override { return stepErrorIter; }
	Real                     stepErrorSquared() const override { return stepErrorSq; }
	Real                     stepCarriedSquared() const override { return stepCarriedSq; }
	const std::vector<char>& stepErrorCovers() const override { return stepErrorCovered; }
	void action() override;
	void postLoad(ViscBridgeImplicitSolver&);
	// Saving refreshes the factorisation at the next step, as loading must (the factor is not saved):
	// a run continued after O.save and one resumed from the file then solve the same systems.
	// The last step's blocks, velocity changes and error are not saved either: in the continued run,
	// as in the resumed one, the step after saving carries no change of coefficients (A1c), compares
	// no velocity change (A1a) and the stepper counts the step before it with its raw error (A1).
	void preSave(ViscBridgeImplicitSolver&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(ViscBridgeImplicitSolver, GlobalEngine,
		"Solves $(M+\\Delta t D)\\,v_{n+1/2} = M v_{n-1/2} + \\Delta t F_{other}$ for the translational "
		"and rotational velocities of every body that has a liquid bridge (P15), where $D$ collects "
		"the damping of every active bridge and every selected viscous effect (normal and tangential "
		"models, walls and fixed or blocked degrees of freedom as boundary conditions) and "
		"$F_{other}$ is every other force of the step (contacts, gravity, other laws). It then adds the "
		"viscous forces and torques $M(v_{n+1/2}-v_{n-1/2})/\\Delta t - F_{other}$, so that "
		":yref:`NewtonIntegrator` lands exactly on the implicit velocities. Backward Euler is "
		"unconditionally stable for the viscous part: the time step is left to the contact stiffness "
		"(:yref:`ViscBridgeTimeStepper` drops its viscous bound). First order in $\\Delta t$.\n\n"
		"A clump is one body of the system: its six velocities are the unknowns, its members' bridges act "
		"on it at the members' centres, and its inertia is the tensor :yref:`NewtonIntegrator` rotates it "
		"with (the principal moments turned to the global frame), so non-spherical granules built with "
		"``O.bodies.appendClumped`` keep the implicit scheme's stability.\n\n"
		"Needs :yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous.integration` = 'implicit' (the law then "
		"describes its bridges' damping instead of applying the forces), a dissipative tangential "
		"model ('none', 'slip' or 'goldman'; 'washino' is not dissipative and is refused), and "
		":yref:`NewtonIntegrator.damping` = 0. Place it after the time stepper and before "
		":yref:`NewtonIntegrator` (:yref:`viscbridge.engines(integration='implicit')` does).\n\n"
		"The linear system is solved matrix-free by preconditioned conjugate gradients to the relative "
		"residual `tolerance`, warm-started from the last step's viscous forces; the matrix products run "
		"in parallel with OpenMP. The default preconditioner ('auto') is a Cholesky factorisation of the "
		"system assembled in 6×6 blocks (one block row per body), by SuiteSparse's CHOLMOD (supernodal on the BLAS where the factor is dense, simplicial where it is sparse), "
		"that is kept while the bridges stay the same and "
		"refreshed when that pays: when the last solve's iterations reach the average cost per step since "
		"the last refresh, the refresh's own cost (refreshCost, in iterations) included — the renewal "
		"rule that minimises the average — or when they exceed refreshIterations (bridges below $S_{min}$ have "
		"constant coefficients, so it stays nearly exact; it ages as the bridges' normals turn); 'multigrid' "
		"uses an aggregation multigrid whose coarse unknowns are the rigid motions of clusters of bodies (P15b) instead: its memory "
		"grows linearly with the bodies and it is kept while bridges form and rupture, but it needs tens of iterations per step "
		"(docs/performance.md §3 says where each is faster; 'auto' takes it only where the factor would not fit in factorMemoryLimit); 'jacobi' uses 6×6 blocks per body (no factorisation, but hundreds of "
		"iterations when Δt·C/m is large). If CG does not converge within maxIterations, the "
		"assembled system is factorised and solved directly instead, with a warning and `fallbacks` "
		"counting it; if that fails too, the run stops with an error.\n\n"
		"Counters: iterations, totalIterations, products, solves, factorisations (refreshes), fallbacks, "
		"factorBlocks, factorBytes, refreshCost, preconditionerInUse; and the wall time of each step of the engine (gather, refresh, solve with its "
		"products and preconditioner, apply, book energy, the time stepper's error estimate) in timeGather … timeEstimate.\n\n"
		"Under yade.mpy (docs/cluster.md) it solves one system over all ranks: each rank holds its own bodies' rows, the "
		"velocities of the neighbours' bodies its bridges touch are exchanged at every CG iteration, and the residual is "
		"global (same tolerance as serially; preconditioner: each rank's own block, no direct fallback).",
		((Real,tolerance,1e-6,Attr::triggerPostLoad,"Relative residual ‖r‖/‖b‖ at which CG stops, in (0, 1). The default adds an error far below the scheme's own (bench/accuracy_cost.py, docs/performance.md §1); 1e-9 costs about two more iterations per step."))
		((int,maxIterations,500,Attr::triggerPostLoad,"CG iterations before the direct fallback, >= 1."))
		((bool,warmStart,true,,"Start CG from the velocities the last step's viscous forces would give (else from the current velocities)."))
		((string,preconditioner,"auto",Attr::triggerPostLoad,"'auto' (the default: 'cholesky' unless its factor would take more than factorMemoryLimit, then 'multigrid'; the factor is the faster of the two at every size measured, docs/performance.md §3), 'cholesky' (lagged sparse factorisation in 6×6 blocks: a few iterations per step, but its fill, memory and sweeps grow faster than the bodies), 'multigrid' (lagged aggregation multigrid whose coarse unknowns are the rigid motions of clusters of bodies, P15b: memory and cost per iteration grow linearly with the bodies, at about 100 iterations per solve on stiff networks) or 'jacobi' (6×6 blocks per body). preconditionerInUse says which ran."))
		((Real,factorMemoryLimit,0,Attr::triggerPostLoad|Attr::noSave,"With preconditioner='auto': the largest Cholesky factor it accepts [bytes], >= 0; 0 (the default): half the memory available (Linux's MemAvailable) when the factor is analysed, since the solver's peak memory was 1.5× its factor's at 10⁵ bodies (docs/performance.md §3). It depends on the machine, so it is not saved with the scene: a loaded scene has the default again."))
		((string,preconditionerInUse,"",Attr::readonly|Attr::noSave,"The preconditioner of the last solve: 'cholesky', 'multigrid' or 'jacobi' (also when a factorisation failed and block Jacobi took over); with 'auto', the one it chose."))
		((Real,factorBytes,0,Attr::readonly|Attr::noSave,"Memory of the last Cholesky factor analysed [bytes] (CHOLMOD's L: its numbers and row indices), which 'auto' compares with factorMemoryLimit."))
		((string,factorKind,"",Attr::readonly|Attr::noSave,"With 'cholesky': the kind of the last factorisation, 'supernodal' (dense BLAS kernels on groups of columns: large or densely bridged beds) or 'simplicial' (column by column: small, sparse ones, where it is faster); CHOLMOD chooses from the factor's flops per entry (docs/performance.md §4). Empty otherwise."))
		((int,levels,0,Attr::readonly|Attr::noSave,"Levels of the last multigrid built, the coarsest (factorised) included; 1 for the Cholesky factor."))
		((int,refreshIterations,12,Attr::triggerPostLoad,"With 'cholesky' or 'multigrid': recompute the preconditioner at the latest when the last solve took more CG iterations than this (with 'multigrid': more than this beyond the first solve after the last refresh), >= 1 (earlier when the renewal rule says a refresh pays; it ages as the bridges' normals turn: docs/performance.md §4)."))
		((long,factorisations,0,Attr::readonly,"Refreshes of the lagged preconditioner (Cholesky factorisations or multigrid builds)."))
		((int,iterations,0,Attr::readonly,"CG iterations of the last solve."))
		((Real,residual,0,Attr::readonly,"Relative residual of the last solve."))
		((long,totalIterations,0,Attr::readonly,"CG iterations of all solves (totalIterations/solves: iterations per step)."))
		((long,products,0,Attr::readonly|Attr::noSave,"Matrix-free products $(M+\\Delta t D)x$ of all solves (one per iteration, one per solve for the start)."))
		((long,solves,0,Attr::readonly,"Number of solves (steps with at least one bridge)."))
		((long,estimateFilters,0,Attr::readonly|Attr::noSave,"Solves in which the time stepper's error estimate was filtered in full (physics.md A1d: every :yref:`ViscBridgeTimeStepper.errorFilterInterval` steps, every step while its accuracy sets dt)."))
		((long,fallbacks,0,Attr::readonly,"Solves that needed the direct (sparse Cholesky) fallback."))
		((int,unknowns,0,Attr::readonly,"Free velocity components in the last solve."))
		((int,bridges,0,Attr::readonly,"Bridges in the last solve."))
		((long,factorBlocks,0,Attr::readonly|Attr::noSave,"6×6 blocks the last lagged preconditioner keeps besides its diagonal (the factor's fill included; for the multigrid, every level's couplings and transfers and the coarsest factor)."))
		((Real,refreshCost,0,Attr::readonly|Attr::noSave,"Estimated cost of one refresh (assembly and factorisation) in CG iterations, from the factor's structure; weighs the renewal rule."))
		((Real,timeGather,0,Attr::readonly|Attr::noSave,"Wall time of the step 'gather': collecting bodies and bridges, building the system and the start vector, all solves [s]."))
		((Real,timeFactorise,0,Attr::readonly|Attr::noSave,"Wall time of the step 'refresh': assembling and factorising the preconditioner [s]."))
		((Real,timeSolve,0,Attr::readonly|Attr::noSave,"Wall time of the step 'solve': conjugate gradients (and fallbacks), of which timeProducts and timePreconditioner [s]."))
		((Real,timeProducts,0,Attr::readonly|Attr::noSave,"Wall time of the matrix-free products inside 'solve' [s]."))
		((Real,timePreconditioner,0,Attr::readonly|Attr::noSave,"Wall time of the preconditioner applications inside 'solve' [s]."))
		((Real,timeApply,0,Attr::readonly|Attr::noSave,"Wall time of the step 'apply': the forces and torques that land Newton on the solution [s]."))
		((Real,timeEnergy,0,Attr::readonly|Attr::noSave,"Wall time of the step 'book energy': each bridge's reported forces and the viscous work [s]."))
		((Real,timeEstimate,0,Attr::readonly|Attr::noSave,"Wall time of the step 'estimate': the filtered step error and the relaxed offsets the time stepper's error estimate takes from this step (physics.md A1a, A1b; only with a ViscBridgeTimeStepper) [s]."))
		// Work of the last solve's forces, booked at the next step, when NewtonIntegrator reports the
		// kinetic energy of the velocities they produced (the same alignment as the explicit law).
		// Saved with the scene, so that a run continued after O.save/O.load books the same energy.
		((Real,pendingNormal,0,Attr::hidden,"Normal viscous work of the last solve, not yet booked."))
		((Real,pendingTangential,0,Attr::hidden,"Tangential viscous work of the last solve, not yet booked."))
		((Real,pendingRotational,0,Attr::hidden,"Rotational viscous work of the last solve, not yet booked."))
		((bool,pendingWork,false,Attr::hidden,"Whether pending* hold work not yet booked."))
		((bool,pendingTangentialKeys,false,Attr::hidden,"Whether the tangential and rotational keys are booked."))
		,
		/* ctor */ rollback.keep(checked()); energyIndex.fill(-1);
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeImplicitSolver);

} // namespace yade
